// Proj(θ, w): Newton on G(·, w) = 0 with a complete-pivoting LU (rank-revealing, as FullPivLU), kept
// across iterations while they contract (chord steps, Anderson-accelerated). A Newton step is
// accepted only if ‖G‖₂ decreases; a step that still does not after projection_backtracking
// halvings, a rank-deficient Jacobian, or the iteration cap is divergence (the paper notes the
// projection can diverge without a line search; the stiff contact makes the full step overshoot on
// landing, and the paper's zeroth-order ∂Ḡ/∂θ lacks that stiffness). Converged when ‖G‖∞ ≤
// projection_tolerance · m‖g‖ plus a round-off allowance that grows as 1/h² (the inertial term is
// (θ − q_n)/h² and θ carries round-off).
//
// The factorization is shared with the PGM outer loop (solver/step_solver.hpp), which factors ∂G/∂θ
// at its iterate for D and the adjoint; the projection's chord steps start from it.
// Buffers are sized by resize(); project() allocates nothing.
#pragma once
#include <Eigen/Core>

#include "solver/anderson_acceleration.hpp"
#include "solver/complete_pivoting_lu.hpp"
#include "solver/step_residual.hpp"
#include "solver/step_stats.hpp"

namespace nmdp {

class ManifoldProjection {
 public:
  // n coordinates; G is measured in units of weight_scale (m‖g‖) and θ's round-off in mass_scale (m).
  void resize(int n, double weight_scale, double mass_scale);

  // Newton on G(·, w) = 0 from θ (in place), to the projection tolerance or to `loose` if that is
  // larger. On success the residual holds the evaluation at θ. Counts go to `counts`.
  bool project(StepResidual& residual, const System& system, const IntegratorOptions& options, Eigen::VectorXd& theta,
               const Eigen::VectorXd& w, ContactDerivative derivative, StepStats& counts, double loose = 0.0);

  // Factors ∂G/∂θ (the PGM iterate's); false (and nothing kept) when it is rank-deficient.
  bool factor(const Eigen::MatrixXd& dG_dtheta);
  void forget() { factorization_valid_ = false; }  // ∂G/∂θ of another step (another h, q_n, target)
  CompletePivotingLu& lu() { return lu_; }
  double tolerance() const { return tolerance_; }  // ‖G‖∞ tolerance of the last projection

 private:
  // Newton keeps an old factorization while each (accelerated) step shrinks ‖G‖₂ at least by this
  // factor; Anderson acceleration of those chord steps remembers this many of them.
  static constexpr double kRefreshContraction = 0.5;
  static constexpr int kAndersonMemory = 3;

  CompletePivotingLu lu_;
  bool factorization_valid_ = false;  // lu_ factors a full-rank ∂G/∂θ of this step at some iterate
  AndersonAcceleration anderson_;
  Eigen::VectorXd step_, theta_trial_;
  double tolerance_ = 0.0;
  double weight_scale_ = 1.0;
  double mass_scale_ = 1.0;
};

}  // namespace nmdp
