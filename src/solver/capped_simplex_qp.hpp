// The per-step QP of the projected gradient method (DESIGN.md 3, step 3.2):
//
//     minimize_Δw  gᵀΔw + ½ Δwᵀ (Q + βI) Δw
//     subject to   w + Δw ≥ 0,   1ᵀ(w_c + Δw_c) ≤ 1  for every contact c,
//
// solved exactly by a primal active-set method in z = w + Δw (H = Q + βI, c = g − H w):
//
//     minimize_z ½ zᵀ H z + cᵀ z   s.t.  z ≥ 0,  1ᵀ z_c ≤ 1.
//
// The working set is a set of variables fixed at their bound (z_i = 0) and a set of contacts whose
// cap is active (1ᵀ z_c = 1). Each iteration solves the equality-constrained QP of the working set
// by a Cholesky factorization of H restricted to the free variables plus a Schur complement over the
// active caps (at most one per contact), then either steps to the blocking constraint (added) or,
// at the minimizer of the working set, drops the constraint with the most negative multiplier.
// It terminates at a KKT point (multipliers ≥ −tol, relative to the scale of H and c) or reports
// MaxIterations. The working set is kept linearly independent by construction.
//
// Warm start: the previous active set is tried first (its equality-constrained minimizer, if
// feasible, is the starting point: one iteration when the active set did not change); otherwise the
// method starts from the (feasible) w with the part of the previous set that is active at w.
//
// Multipliers (Lagrangian ½zᵀHz + cᵀz − λᵀz + Σ_c ν_c(1ᵀz_c − 1)):
//     H z + c − λ + Σ_c ν_c 1_c = 0,   λ ≥ 0, ν ≥ 0,   λ_i z_i = 0,   ν_c (1 − 1ᵀz_c) = 0.
//
// The workspace is sized once (constructor or resize()); solve() allocates nothing afterwards.
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace nmdp {

// Which constraints are active: at_bound[i] ⇔ z_i = 0 is in the working set, cap[c] ⇔ 1ᵀz_c = 1.
struct QpActiveSet {
  std::vector<std::uint8_t> at_bound;  // size Σ K_c
  std::vector<std::uint8_t> cap;       // size C
};

enum class QpStatus {
  Converged,      // KKT point to the tolerance
  MaxIterations,  // iteration cap reached; Δw is feasible but not optimal
  NotConvex,      // Q + βI restricted to the free variables is not positive definite
  InvalidInput,   // sizes do not match the workspace, non-finite data, β ≤ 0 with singular Q ...
};

const char* toString(QpStatus status);

struct QpOptions {
  int max_iterations = 0;         // 0: 10·n + 50
  double dual_tolerance = 1e-13;  // multipliers ≥ −dual_tolerance·scale are accepted
  double feasibility_tolerance = 1e-13;  // for accepting a warm-start point (z ∈ [0, 1])
  bool refine = true;             // one step of iterative refinement on each equality-constrained solve
};

struct QpResult {
  QpStatus status = QpStatus::InvalidInput;
  int iterations = 0;          // equality-constrained solves
  int active_set_changes = 0;  // constraints added + dropped
  int factorizations = 0;      // Cholesky factorizations from scratch (the rest are O(k²) updates)
  bool warm_start_used = false;  // the warm active set's minimizer was feasible and used as start
};

class CappedSimplexQp {
 public:
  CappedSimplexQp() = default;
  explicit CappedSimplexQp(const std::vector<int>& contact_sizes) { resize(contact_sizes); }

  // Allocates the workspace for contacts of the given sizes (consecutive blocks of w).
  void resize(const std::vector<int>& contact_sizes);
  int size() const { return n_; }
  int contacts() const { return static_cast<int>(sizes_.size()); }

  QpOptions options;

  // Solves for Δw (resized to n if needed; pre-size it to avoid the allocation). w is the current
  // weight vector; it should be feasible — tiny violations are repaired (negatives clamped to 0, a cap
  // sum above 1 scaled down), which only changes the starting point, not the problem. `warm` is the
  // active set of a previous solve (same sizes) or nullptr.
  QpResult solve(const Eigen::MatrixXd& Q, double beta, const Eigen::VectorXd& g, const Eigen::VectorXd& w,
                 Eigen::VectorXd& dw, const QpActiveSet* warm = nullptr);

  // After solve(): the final working set and its multipliers (λ ≥ 0 on fixed variables, 0 elsewhere;
  // ν ≥ 0 on active caps, 0 elsewhere).
  const QpActiveSet& activeSet() const { return active_; }
  const Eigen::VectorXd& boundMultipliers() const { return lambda_; }
  const Eigen::VectorXd& capMultipliers() const { return nu_; }

 private:
  // Solves the equality-constrained QP of the working set; writes zs_ (all n, fixed = 0) and nu_.
  bool solveEqp();
  bool factorWorkingSet(int k, int m);  // L of H_SS (if not valid) and S's Cholesky factor; false if not PD
  void solveDisplacement(int k, int m);  // x0_ and nu_ for the factored working set
  // The start of solve(): w repaired into z_, the working set from `warm` (or the bounds and caps
  // active at z_); true when the warm set's minimizer is already feasible (then z_ is it).
  bool startAt(const Eigen::VectorXd& w, const QpActiveSet* warm, double feas_tol, QpResult& result);
  bool warmMinimizerFeasible(double feas_tol) const;
  // One primal step toward the working set's minimizer: to it (returns true), or to the first
  // blocking bound or cap, which joins the working set (returns false).
  bool stepTowardMinimizer(QpResult& result);
  // At the working set's minimizer: drops the most negative multiplier's constraint; false when
  // none is below −dual_tol (optimal).
  bool dropConstraint(double dual_tol, QpResult& result);
  void finishMultipliers(const QpResult& result);  // λ and ν (by contact) of the final working set
  void buildLists();  // free set and caps from the working set; invalidates the factor
  void buildCaps();
  void removeFree(int i);
  void appendFree(int i);
  void solveReduced();
  void computeGradient();  // grad_ = H d + g  (= H z + c)

  int n_ = 0;
  std::vector<int> sizes_, offsets_, contact_of_;
  QpActiveSet active_;
  // problem data for the current solve
  Eigen::MatrixXd H_;
  Eigen::VectorXd w_, g_;       // copies of the inputs
  Eigen::VectorXd d_, ds_;      // iterate and working-set minimizer as displacements from w (Δw)
  Eigen::VectorXd z_, zs_;      // the same as points (w + d; exactly 0 on fixed variables)
  Eigen::VectorXd p_, grad_, lambda_, nu_;
  // reduced system buffers
  std::vector<int> free_, capped_;  // free variable indices; contacts with an active cap
  std::vector<int> cap_index_;      // contact → position in capped_, or −1
  Eigen::MatrixXd L_;               // n×n: Cholesky factor of H_SS (top-left k×k)
  Eigen::MatrixXd U_;               // n×C: V = L⁻¹ E_Sᵀ
  Eigen::MatrixXd S_;               // C×C Schur complement E H_SS⁻¹ Eᵀ
  Eigen::VectorXd y_, r_, x0_, nuv_, rnu_, rc_;  // reduced vectors
  Eigen::VectorXd t_;               // scratch for factor updates
  Eigen::VectorXd xf_, hx_;         // n-vectors for products with H
  bool factor_valid_ = false;       // L_ holds the Cholesky factor of H over free_ (in free_'s order)
  int updates_since_factor_ = 0;
  int factorizations_ = 0;
  int refactor_period_ = 64;        // refactor from scratch after this many updates
  double scale_ = 1.0;
};

// Max violation of the KKT conditions of the QP at Δw with multipliers λ (size n) and ν (size C):
// stationarity ‖g + (Q+βI)Δw − λ + Σ ν_c 1_c‖∞ and complementarity |λ_i z_i|, |ν_c (1 − 1ᵀz_c)|
// (both divided by max(1, max|Q+βI|, max|g|)), primal feasibility max(−z_i, 1ᵀz_c − 1) and dual
// feasibility max(−λ_i, −ν_c) (the latter also divided by the scale). z = w + Δw.
double kktResidual(const Eigen::MatrixXd& Q, double beta, const Eigen::VectorXd& g, const Eigen::VectorXd& w,
                   const std::vector<int>& contact_sizes, const Eigen::VectorXd& dw, const Eigen::VectorXd& lambda,
                   const Eigen::VectorXd& nu);

}  // namespace nmdp
