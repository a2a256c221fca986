#include <Eigen/Cholesky>

#include "multibody/crba.hpp"
#include "multibody/rnea.hpp"
#include "solver/step_solver.hpp"

namespace nmdp {

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
  rnea(model, data, state.q, state.qd, zero_acceleration_);
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
    scaleFromQ();
    if (!solveQp(1e-12)) {
      stats.status = StepStatus::QpFailed;
      return stats;
    }
    w_ += dw_;
    velocity_.noalias() += h * (D_ * w_);
  }
  theta_ = state.q + h * velocity_;
  if (!theta_.allFinite() || !velocity_.allFinite()) stats.status = StepStatus::NonFinite;
  return stats;
}

}  // namespace nmdp
