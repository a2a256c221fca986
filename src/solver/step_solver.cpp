#include "solver/step_solver.hpp"

#include <cmath>
#include <limits>

#include "multibody/crba.hpp"
#include "multibody/rnea.hpp"

namespace nmdp {

namespace {
bool allFinite(const Eigen::VectorXd& v) { return v.allFinite(); }
}  // namespace

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
  residual_.evaluate(system, theta, w, first_order);
  ++stats.g_evaluations;
  if (!allFinite(residual_.G)) return false;
  double norm = residual_.G.lpNorm<Eigen::Infinity>();
  for (int it = 0;; ++it) {
    if (norm <= tolerance) return true;
    if (it == options.projection_max_iterations) return false;
    lu_.compute(residual_.dG_dtheta);
    if (lu_.rank() < n) return false;
    step_ = -residual_.G;
    solveInPlace(step_);
    ++stats.newton_iterations;
    theta_trial_ = theta + step_;
    residual_.evaluate(system, theta_trial_, w, first_order);
    ++stats.g_evaluations;
    const double trial_norm = residual_.G.lpNorm<Eigen::Infinity>();
    if (!(trial_norm < norm)) return false;  // divergence (also catches NaN)
    theta.swap(theta_trial_);
    norm = trial_norm;
  }
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
      lu_.compute(residual_.dG_dtheta);
      if (lu_.rank() < theta_.size()) {
        stats.status = StepStatus::ProjectionFailed;
        return stats;
      }
      D_ = residual_.B;
      solveInPlace(D_);
      g_.noalias() = D_.transpose() * residual_.grad_K;
      HD_.noalias() = residual_.hess_K * D_;
      Q_.noalias() = D_.transpose() * HD_;
      need_direction = false;
    }
    const QpResult qp = qp_.solve(Q_, beta, g_, w_, dw_, warm_valid_ ? &warm_ : nullptr);
    if (qp.status != QpStatus::Converged) {
      stats.status = StepStatus::QpFailed;
      return stats;
    }
    warm_ = qp_.activeSet();
    warm_valid_ = true;
    if (!(dw_.size() == 0 || dw_.lpNorm<Eigen::Infinity>() < options.tol_w)) {
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
    g_.noalias() = h * residual_.B.transpose() * velocity_;
    // Bᵀ H⁻¹ B is singular when there are more vertices than degrees of freedom: a regularization far
    // below the scale of Q picks the minimum-norm-like optimum without changing the velocity.
    const double beta = 1e-12 * std::max(1.0, Q_.diagonal().maxCoeff());
    const QpResult qp = qp_.solve(Q_, beta, g_, w_, dw_, warm_valid_ ? &warm_ : nullptr);
    if (qp.status != QpStatus::Converged) {
      stats.status = StepStatus::QpFailed;
      return stats;
    }
    warm_ = qp_.activeSet();
    warm_valid_ = true;
    w_ += dw_;
    velocity_.noalias() += h * (D_ * w_);
  }
  theta_ = state.q + h * velocity_;
  if (!allFinite(theta_) || !allFinite(velocity_)) stats.status = StepStatus::NonFinite;
  return stats;
}

}  // namespace nmdp
