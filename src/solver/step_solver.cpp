#include "solver/step_solver.hpp"

#include <cmath>
#include <limits>

#include "multibody/crba.hpp"
#include "multibody/rnea.hpp"

namespace nmdp {

namespace {
bool allFinite(const Eigen::VectorXd& v) { return v.allFinite(); }
bool isSmall(const Eigen::VectorXd& dw, double tol) { return dw.size() == 0 || dw.lpNorm<Eigen::Infinity>() < tol; }
}  // namespace

bool StepSolver::solveQp(double beta) {
  const QpResult qp = qp_.solve(Q_, beta * q_scale_, g_, w_, dw_, warm_valid_ ? &warm_ : nullptr);
  if (qp.status != QpStatus::Converged) return false;
  warm_ = qp_.activeSet();
  warm_valid_ = true;
  return true;
}

StepSolver::StepSolver(const System& system, const IntegratorOptions& options)
    : residual_(system), lu_(system.model->nq, system.model->nq), llt_(system.model->nq) {
  (void)options;
  const Model& model = *system.model;
  const int n = model.nq;
  const int C = static_cast<int>(system.contacts.size());
  const int m = residual_.weightCount();
  K_vertices_ = C > 0 ? m / C : 0;
  qp_.resize(std::vector<int>(C, K_vertices_));
  warm_.at_bound.assign(m, 0);
  warm_.cap.assign(C, 0);
  theta_.setZero(n);
  theta_trial_.setZero(n);
  theta_candidate_.setZero(n);
  G_previous_.setZero(n);
  secant_residual_.setZero(n);
  jacobian_.setZero(n, n);
  secant_correction_.setZero(n, n);
  velocity_.setZero(n);
  step_.setZero(n);
  tau_.setZero(n);
  w_.setZero(m);
  w_trial_.setZero(m);
  dw_.setZero(m);
  g_.setZero(m);
  D_.setZero(n, m);
  Q_.setZero(m, m);
  HD_.setZero(n, m);
  mass_scale_ = model.total_mass > 0 ? model.total_mass : 1.0;
  weight_scale_ = mass_scale_ * std::max(model.gravity.norm(), 1.0);
}

Vec6 StepSolver::contactWrench(int c) const {
  const ContactWrenches& cw = residual_.wrenches[c];
  return cw.V * w_.segment(c * K_vertices_, K_vertices_);
}

template <typename Derived>
void StepSolver::solveInPlace(Eigen::MatrixBase<Derived>& x) {
  // x ← Q U⁻¹ L⁻¹ P x, written out so that no temporary is allocated (FullPivLU::solve allocates).
  x = lu_.permutationP() * x;
  lu_.matrixLU().template triangularView<Eigen::UnitLower>().solveInPlace(x);
  lu_.matrixLU().template triangularView<Eigen::Upper>().solveInPlace(x);
  x = lu_.permutationQ() * x;
}

StepAttempt StepSolver::attempt(const System& system, const IntegratorOptions& options, const SimulationState& state,
                                double h, const PdTarget& target, const Eigen::VectorXd& w_start, double& beta) {
  if (options.method == Method::NeMdp) return neMdp(system, state, h, target, w_start);
  return pgm(system, options, state, h, target, w_start, beta);
}

bool StepSolver::project(const System& system, const IntegratorOptions& options, Eigen::VectorXd& theta,
                         const Eigen::VectorXd& w, bool first_order, StepAttempt& stats) {
  ++stats.projections;
  const int n = static_cast<int>(theta.size());
  // Round-off in G: the inertial term divides θ's round-off by h².
  const double h = residual_.h();
  const double lever = 1.0 + theta.lpNorm<Eigen::Infinity>();
  const double tolerance = options.projection_tolerance * weight_scale_ +
                           1e3 * std::numeric_limits<double>::epsilon() * mass_scale_ * lever * lever / (h * h);
  const bool secant = !first_order && options.zeroth_order_secant;
  residual_.evaluate(system, theta, w, first_order);
  ++stats.g_evaluations;
  if (!allFinite(residual_.G)) return false;
  double norm = residual_.G.lpNorm<Eigen::Infinity>();
  for (int it = 0;; ++it) {
    if (norm <= tolerance) return true;
    if (it == options.projection_max_iterations) return false;
    if (secant) {
      jacobian_ = residual_.dG_dtheta + secant_correction_;
      lu_.compute(jacobian_);
    } else {
      lu_.compute(residual_.dG_dtheta);
    }
    if (lu_.rank() < n) return false;
    step_ = -residual_.G;
    solveInPlace(step_);
    ++stats.newton_iterations;
    if (secant) G_previous_ = residual_.G;
    double trial_norm = 0.0;
    for (int k = 0;; ++k) {
      theta_trial_ = theta + step_;
      residual_.evaluate(system, theta_trial_, w, first_order);
      ++stats.g_evaluations;
      trial_norm = residual_.G.lpNorm<Eigen::Infinity>();
      if (trial_norm < norm) break;
      if (k == options.projection_backtracking) return false;  // divergence (also catches NaN)
      step_ *= 0.5;
    }
    if (secant) updateSecant();
    theta.swap(theta_trial_);
    norm = trial_norm;
  }
}

void StepSolver::updateSecant() {
  // Structured Broyden: S, the stiffness ∂Ḡ/∂θ lacks, is updated so that
  // (∂Ḡ/∂θ(θ_new) + S) Δθ = ΔG along the Newton step just taken (w fixed; values of G only).
  const double ss = step_.squaredNorm();
  if (!(ss > 0)) return;
  secant_residual_ = residual_.G - G_previous_;
  secant_residual_.noalias() -= residual_.dG_dtheta * step_;
  secant_residual_.noalias() -= secant_correction_ * step_;
  secant_correction_.noalias() += (secant_residual_ / ss) * step_.transpose();
}

StepAttempt StepSolver::pgm(const System& system, const IntegratorOptions& options, const SimulationState& state,
                            double h, const PdTarget& target, const Eigen::VectorXd& w_start, double& beta) {
  StepAttempt stats;
  const bool first_order = needsContactDerivative(options.method);
  const Form form = isPositionBased(options.method) ? Form::PositionBased : Form::NewtonEuler;
  residual_.prepare(system, form, h, state.q, state.qd, state.q_prev, state.h_prev, target, state.base_chart);
  theta_ = state.q;
  w_ = w_start;
  if (!project(system, options, theta_, w_, first_order, stats)) {
    stats.status = StepStatus::ProjectionFailed;
    return stats;
  }
  double K = residual_.K;
  bool evaluated_here = true;  // the residual holds the evaluation at (θ, w)
  bool need_direction = true;
  for (;;) {
    if (stats.outer_iterations == options.max_outer_iterations) {
      stats.status = StepStatus::MaxIterations;
      return stats;
    }
    ++stats.outer_iterations;
    if (need_direction) {
      if (!first_order && options.zeroth_order_secant) {
        jacobian_ = residual_.dG_dtheta + secant_correction_;
        lu_.compute(jacobian_);
      } else {
        lu_.compute(residual_.dG_dtheta);
      }
      if (lu_.rank() < theta_.size()) {
        stats.status = StepStatus::ProjectionFailed;
        return stats;
      }
      D_ = residual_.B;
      solveInPlace(D_);
      g_.noalias() = D_.transpose() * residual_.grad_K;
      HD_.noalias() = residual_.hess_K * D_;
      Q_.noalias() = D_.transpose() * HD_;
      // β is relative to the scale of Q, which follows V² and 1/h² over many orders of magnitude
      // (a foot in the air carries k ζ = 0.1 N, a landing one thousands): an absolute β carried
      // from step to step would be meaningless.
      const double mean_diagonal = Q_.size() ? Q_.diagonal().mean() : 0.0;
      q_scale_ = mean_diagonal > 0 ? mean_diagonal : 1.0;
      need_direction = false;
    }
    if (!solveQp(beta)) {
      stats.status = StepStatus::QpFailed;
      return stats;
    }
    if (!isSmall(dw_, options.tol_w)) {
      w_trial_ = w_ + dw_;
      Eigen::VectorXd& candidate = theta_candidate_;
      candidate = theta_;
      const bool projected = project(system, options, candidate, w_trial_, first_order, stats);
      evaluated_here = false;
      if (!projected || !(residual_.K < K)) {
        ++stats.rejected;
        beta *= options.eta;
        if (beta > options.beta_max) {
          stats.status = StepStatus::TrustRegionFailed;
          return stats;
        }
        continue;
      }
      const double decrease = K - residual_.K;
      const double moved = (candidate - theta_).lpNorm<Eigen::Infinity>();
      theta_.swap(candidate);
      w_.swap(w_trial_);
      K = residual_.K;
      evaluated_here = true;
      need_direction = true;
      beta = std::max(beta / options.eta, options.beta_min);
      if (decrease >= options.epsilon && moved >= options.epsilon) continue;
    }
    break;
  }
  if (!evaluated_here) {
    residual_.evaluate(system, theta_, w_, first_order);
    ++stats.g_evaluations;
  }
  velocity_ = (theta_ - state.q) / h;
  if (!allFinite(theta_)) stats.status = StepStatus::NonFinite;
  return stats;
}

StepAttempt StepSolver::neMdp(const System& system, const SimulationState& state, double h, const PdTarget& target,
                              const Eigen::VectorXd& w_start) {
  StepAttempt stats;
  stats.outer_iterations = 1;
  stats.g_evaluations = 1;
  const Model& model = *system.model;
  Data& data = residual_.data;
  data.base_chart = state.base_chart;
  const int n = model.nq;
  // Explicit PD at (q_n, q̇_n).
  const PdGains& gains = system.gains;
  for (int j = 0; j < n; ++j) {
    const double kp = gains.kp[j], kd = gains.kd[j], ff = gains.tau_ff[j];
    tau_[j] = (kp == 0.0 && kd == 0.0 && ff == 0.0)
                  ? 0.0
                  : -kp * (state.q[j] - target.position[j]) - kd * (state.qd[j] - target.velocity[j]) + ff;
  }
  if (system.external_force.size() != 0) tau_ += system.external_force;
  // q̇* = q̇_n + h H⁻¹ (τ − C q̇ − g) at q_n.
  step_.setZero();
  rnea(model, data, state.q, state.qd, step_);
  tau_ -= data.tau;
  crbaFromKinematics(model, data);
  llt_.compute(data.H);
  if (llt_.info() != Eigen::Success) {
    stats.status = StepStatus::NonFinite;
    return stats;
  }
  llt_.solveInPlace(tau_);
  velocity_ = state.qd + h * tau_;
  w_ = w_start;
  if (residual_.weightCount() > 0) {
    residual_.evaluateContacts(system, state.q);
    // Post-contact velocity v = q̇* + h H⁻¹ B w; its kinetic energy is
    // ½ q̇*ᵀHq̇* + h (Bᵀq̇*)ᵀ w + ½ h² wᵀ (Bᵀ H⁻¹ B) w.
    D_ = residual_.B;
    llt_.solveInPlace(D_);
    Q_.noalias() = (h * h) * residual_.B.transpose() * D_;
    // The QP model is taken around the warm start w (gradient g₀ + Q w).
    g_.noalias() = h * residual_.B.transpose() * velocity_;
    g_.noalias() += Q_ * w_;
    // Bᵀ H⁻¹ B is singular when there are more vertices than degrees of freedom: a penalty far below
    // the scale of Q makes the optimum unique without changing the velocity noticeably.
    const double mean_diagonal = Q_.diagonal().mean();
    q_scale_ = mean_diagonal > 0 ? mean_diagonal : 1.0;
    if (!solveQp(1e-12)) {
      stats.status = StepStatus::QpFailed;
      return stats;
    }
    w_ += dw_;
    velocity_.noalias() += h * (D_ * w_);
  }
  theta_ = state.q + h * velocity_;
  if (!allFinite(theta_) || !allFinite(velocity_)) stats.status = StepStatus::NonFinite;
  return stats;
}

}  // namespace nmdp
