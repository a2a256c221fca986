// One attempt at a step of a given size h, by any of the five methods:
//
// NMDP (ne-pgm, ne-zopgm, pbd-pgm, pbd-zopgm), Algorithm 1 of the paper as fixed by DESIGN.md 3:
//   θ ← q_n, w ← w_start;  θ ← Proj(θ, w)
//   repeat:  D = (∂G/∂θ)⁻¹ B  (B = −∂G/∂w),  g = Dᵀ∇K,  Q = Dᵀ ∇²K D
//            Δw = argmin gᵀΔw + ½ Δwᵀ(Q + β diag Q)Δw  over the capped simplices (CappedSimplexQp;
//            the paper and DESIGN.md write βI: β is made relative to each weight's own curvature)
//            ‖B Δw‖∞ < tol_w·m‖g‖ (the step as a generalized force), or a predicted decrease of K
//            below what K resolves or (unless the contact term is dropped) below ε·½m(‖g‖h)² → done
//            θ' = Proj(θ, w + Δw) from θ + DΔw;  fails or K(θ') ≥ K(θ) → β ← η_reject·β (fail past
//            β_max), same D;  else accept, β ← max(β/η, β_min); done if K(θ) − K(θ') < ε·½m(‖g‖h)²
//            or (unless the contact term is dropped) ‖θ' − θ‖∞ < ε
// The zeroth-order variants never ask the model for dV/dξ: D and Newton use central differences of V
// (ZerothOrderJacobian::FiniteDifference) or the paper's ∂Ḡ/∂θ with that term dropped.
//
// Proj(θ, w) is solver/manifold_projection.hpp. A trial θ' of the PGM loop (solver/pgm.cpp) is
// projected only until its residual r can no longer change the trust-region test: |λᵀr| ≤ 0.1 × the
// predicted decrease of K (λ the adjoint (∂G/∂θ)⁻ᵀ∇K); the final θ is projected to the full tolerance.
//
// ne-mdp (DESIGN.md 6, solver/ne_mdp.cpp): explicit PD and dynamics at (q_n, q̇_n), vertices at q_n,
// one QP for the weights that minimise the kinetic energy of the post-contact velocity, symplectic
// Euler update.
//
// All buffers are sized in the constructor; attempt() allocates nothing.
#pragma once
#include <Eigen/Cholesky>

#include "solver/capped_simplex_qp.hpp"
#include "solver/manifold_projection.hpp"
#include "solver/step_residual.hpp"

namespace nmdp {

// One attempt: its status and iteration counts (the sub-step fields of StepStats stay unset), and
// the first accepted move's actual decrease of K over the QP's predicted one (−1 if there was none)
// with the β it was accepted at.
struct StepAttempt : StepStats {
  double first_agreement = -1, first_beta = 0;
};

class StepSolver {
 public:
  explicit StepSolver(const System& system);

  // Tries one step of size h from `state` with the PD target at state.time + h; w_start is the
  // initial weight vector (feasible; zeros for a cold start). `beta` is read and updated.
  // On success theta(), velocity(), weights() and contactWrench(c) hold the solution. A raised
  // `cancel` (may be null) ends the outer iteration with StepStatus::Cancelled.
  StepAttempt attempt(const System& system, const IntegratorOptions& options, const SimulationState& state, double h,
                      const PdTarget& target, const Eigen::VectorXd& w_start, double& beta, CancelFlag cancel = nullptr);

  const Eigen::VectorXd& theta() const { return theta_; }
  const Eigen::VectorXd& velocity() const { return velocity_; }
  const Eigen::VectorXd& weights() const { return w_; }
  Vec6 contactWrench(int c) const;  // V_c(θ) w_c, [torque about the sphere centre; force], world
  StepResidual& residual() { return residual_; }

  // The weight QP's warm start (its last active set), carried from step to step in the state
  // (SimulationState::qp_warm): taken at the start of a step, handed back at its end. A set whose
  // sizes do not match this system's is a cold start. Neither allocates once `set` is sized.
  void takeWarmStart(const QpActiveSet& set, bool valid);
  void returnWarmStart(QpActiveSet& set, bool& valid) const;

 private:
  // What the PGM loop does next: iterate again, stop converged, or stop failed (status set).
  enum class PgmNext { Iterate, Converged, Fail };
  struct PgmLoop;  // the outer loop's state (solver/pgm.cpp)

  StepAttempt pgm(const System& system, const IntegratorOptions& options, const SimulationState& state, double h,
                  const PdTarget& target, const Eigen::VectorXd& w_start, double& beta, CancelFlag cancel);
  void preparePgm(const System& system, const IntegratorOptions& options, const SimulationState& state, double h,
                  const PdTarget& target, const Eigen::VectorXd& w_start);
  bool computeDirection(const System& system, PgmLoop& loop, StepAttempt& stats);
  PgmNext confirmConvergence(const IntegratorOptions& options, const PgmLoop& loop, double& beta, StepAttempt& stats);
  PgmNext tryMove(const System& system, const IntegratorOptions& options, PgmLoop& loop, double& beta,
                  StepAttempt& stats);
  void finishPgm(const System& system, const IntegratorOptions& options, const PgmLoop& loop, StepAttempt& stats);
  StepAttempt neMdp(const System& system, const SimulationState& state, double h, const PdTarget& target,
                    const Eigen::VectorXd& w_start);
  void scaleFromQ();          // penalty_scale_ from the diagonal of Q_
  bool solveQp(double beta);  // Δw into dw_ with the penalty β·diag(penalty_scale_); false if the QP failed
  // Whether dw_ is a step to try: its contact force change above tol_w·m‖g‖, and predicted to lower
  // K by more than K can resolve and more than least_decrease.
  bool stepIsWorthTaking(const IntegratorOptions& options, double K, double least_decrease);

  StepResidual residual_;
  CappedSimplexQp qp_;
  QpActiveSet warm_;
  bool warm_valid_ = false;
  ManifoldProjection projection_;
  // A trial PGM step is projected until its residual moves K by at most this fraction of the decrease
  // the QP predicts (see pgm()); the accepted solution is then projected to the full tolerance.
  static constexpr double kTrialLooseness = 0.1;
  // An accepted move was limited by the penalty (IntegratorOptions::eta_limited) when K fell by more
  // than kModelAgreed of the QP's prediction and that prediction was at least kSamePace of the
  // previous move's.
  static constexpr double kModelAgreed = 0.75, kSamePace = 0.3;
  // DESIGN.md's reference η, the most β relaxes by with the dropped zeroth-order term (but for η_limited).
  static constexpr double kDesignRelaxation = 1.5;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd theta_, theta_candidate_, velocity_, w_, w_trial_, dw_, g_, tau_;
  Eigen::VectorXd zero_acceleration_;  // ne-mdp's RNEA argument: C q̇ + g without the inertial term
  Eigen::MatrixXd D_, Q_, HD_;
  Eigen::VectorXd Qdw_, generalized_force_change_;
  Eigen::VectorXd penalty_scale_;  // the unit of β per weight: max(Q_ii, 1e-12·max Q_ii)
  Eigen::MatrixXd Q_penalized_;
  Eigen::MatrixXd B_theta_;  // B at the current iterate (the residual may hold a rejected trial)
  Eigen::VectorXd adjoint_;  // λ = (∂G/∂θ)⁻ᵀ ∇K at the current iterate: K moves by λᵀr for a residual r
  double adjoint_norm_ = 0.0;  // ‖λ‖₁
  double predicted_decrease_ = 0.0;    // of K, by the QP model, for the last step
  double weight_scale_ = 1.0;  // m‖g‖, or m·1 m/s² without gravity
  double mass_scale_ = 1.0;
  int K_vertices_ = 0;
};

}  // namespace nmdp
