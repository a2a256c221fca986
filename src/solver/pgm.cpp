// The NMDP outer loop (Algorithm 1 as fixed by DESIGN.md 3; the scheme is in solver/step_solver.hpp):
// a projected gradient method on the kinetic energy K over the contact weights w, with a
// trust-region penalty β and each trial θ projected onto G(·, w) = 0.
#include <algorithm>
#include <cmath>

#include "solver/step_solver.hpp"

namespace nmdp {

namespace {

ContactDerivative contactDerivativeOf(const IntegratorOptions& options) {
  return needsContactDerivative(options.method)                                    ? ContactDerivative::Model
         : options.zeroth_order_jacobian == ZerothOrderJacobian::FiniteDifference ? ContactDerivative::FiniteDifference
                                                                                   : ContactDerivative::Dropped;
}

}  // namespace

struct StepSolver::PgmLoop {
  ContactDerivative derivative = ContactDerivative::Model;
  double K = 0.0;                 // kinetic energy at the accepted iterate (θ, w)
  double energy_tolerance = 0.0;  // ε·½ m (‖g‖ h)²
  double least_decrease = 0.0;    // a predicted decrease below this is not worth a trial
  double eta = 0.0;               // β's relaxation after an accepted move (but for η_limited)
  bool theta_loose = false;       // θ is projected only as far as its trust-region test needed
  bool evaluated_here = true;     // the residual holds G and K at (θ, w)
  bool derivatives_here = false;  // ... and ∂G/∂θ, B, ∇K, ∇²K
  bool need_direction = true;
  double previous_prediction = 0.0;  // the QP's predicted decrease for the previous accepted move (0: none)
};

void StepSolver::preparePgm(const System& system, const IntegratorOptions& options, const SimulationState& state,
                            double h, const PdTarget& target, const Eigen::VectorXd& w_start) {
  const Form form = isPositionBased(options.method) ? Form::PositionBased : Form::NewtonEuler;
  if (options.order == 2)
    residual_.prepareSecondOrder(system, form, secondOrderStepCoefficients(state, h), state.q, state.qd, state.q_prev,
                                 state.qd_prev, target, state.base_chart, options.kinetic_energy);
  else
    residual_.prepare(system, form, h, state.q, state.qd, state.q_prev, state.h_prev, target, state.base_chart,
                      options.kinetic_energy);
  theta_ = state.q;
  if (options.predict_first_iterate) theta_.noalias() += h * state.qd;
  w_ = w_start;
  projection_.forget();  // ∂G/∂θ of another step (another h, q_n, target)
}

StepAttempt StepSolver::pgm(const System& system, const IntegratorOptions& options, const SimulationState& state,
                            double h, const PdTarget& target, const Eigen::VectorXd& w_start, double& beta, CancelFlag cancel) {
  StepAttempt stats;
  PgmLoop loop;
  loop.derivative = contactDerivativeOf(options);
  preparePgm(system, options, state, h, target, w_start);
  if (!projection_.project(residual_, system, options, theta_, w_, loop.derivative, stats)) {
    stats.status = StepStatus::ProjectionFailed;
    return stats;
  }
  loop.K = residual_.K;
  // ε on K is relative to the energy gravity gives the robot in one step, ½ m (‖g‖ h)², so that it
  // means the same for a quadruped and a 1 kg box.
  const double gravity_h = std::max(system.model->gravity.norm(), 1.0) * h;
  loop.energy_tolerance = options.epsilon * 0.5 * mass_scale_ * gravity_h * gravity_h;
  // A step predicted to lower K by less than ε would end the iteration once taken, so it is not
  // taken: its projection is most of an iteration's cost. The QP's model is K's to second order
  // near the solution, so this stops where the ε rule would. Not with the dropped term, whose model
  // misses the contact stiffness.
  loop.least_decrease = loop.derivative == ContactDerivative::Dropped ? 0.0 : loop.energy_tolerance;
  // The dropped term's model overstates how far θ follows w, so its penalty relaxes at DESIGN.md's
  // η = 1.5 (η_limited still applies after a penalty-limited move, whose model agreed); a larger η
  // lets a held block creep.
  loop.eta = loop.derivative == ContactDerivative::Dropped ? std::min(options.eta, kDesignRelaxation) : options.eta;
  for (;;) {
    if (stats.outer_iterations == options.max_outer_iterations) {
      stats.status = StepStatus::MaxIterations;
      return stats;
    }
    if (cancel && *cancel) {
      stats.status = StepStatus::Cancelled;
      return stats;
    }
    ++stats.outer_iterations;
    if (loop.need_direction && !computeDirection(system, loop, stats)) {
      stats.status = StepStatus::ProjectionFailed;
      return stats;
    }
    if (!solveQp(beta)) {
      stats.status = StepStatus::QpFailed;
      return stats;
    }
    const PgmNext next = stepIsWorthTaking(options, loop.K, loop.least_decrease)
                             ? tryMove(system, options, loop, beta, stats)
                             : confirmConvergence(options, loop, beta, stats);
    if (next == PgmNext::Fail) return stats;
    if (next == PgmNext::Converged) break;
  }
  finishPgm(system, options, loop, stats);
  return stats;
}

// D = (∂G/∂θ)⁻¹ B, g = Dᵀ∇K, Q = Dᵀ∇²K D and the adjoint λ at the accepted iterate; false when
// ∂G/∂θ is rank-deficient.
bool StepSolver::computeDirection(const System& system, PgmLoop& loop, StepAttempt& stats) {
  if (!loop.derivatives_here) {
    if (loop.evaluated_here)  // by the projection that ended at θ
      residual_.addDerivatives(system, theta_, w_, loop.derivative);
    else
      residual_.evaluate(system, theta_, w_, loop.derivative);
    ++stats.g_evaluations;
    loop.derivatives_here = loop.evaluated_here = true;
  }
  if (!projection_.factor(residual_.dG_dtheta)) return false;
  CompletePivotingLu& lu = projection_.lu();
  adjoint_ = residual_.grad_K;
  lu.solveTransposeInPlace(adjoint_);
  adjoint_norm_ = adjoint_.lpNorm<1>();
  // A loosely projected θ's K, corrected to where Newton would end: θ* = θ − (∂G/∂θ)⁻¹G moves K by
  // −λᵀG to second order, so the next trials are judged against K(θ*), not against θ's own
  // projection error.
  if (loop.theta_loose) loop.K -= adjoint_.dot(residual_.G);
  B_theta_ = residual_.B;
  D_ = residual_.B;
  lu.solveInPlace(D_);
  g_.noalias() = D_.transpose() * residual_.grad_K;
  HD_.noalias() = residual_.hess_K * D_;
  Q_.noalias() = D_.transpose() * HD_;
  scaleFromQ();
  loop.need_direction = false;
  return true;
}

// The QP's step is below tol_w, or its predicted decrease of K below ε (least_decrease) or below
// what K can resolve (θ is only known to the projection's tolerance, so the trust-region test would
// compare noise; at small h this, not ε, stops the iteration). A large penalty makes any step
// small, so convergence is confirmed without it (re-solved at β_min); if the penalty was hiding
// progress, it is lowered and the loop iterates again (no projection needed).
StepSolver::PgmNext StepSolver::confirmConvergence(const IntegratorOptions& options, const PgmLoop& loop, double& beta,
                                                   StepAttempt& stats) {
  if (beta <= options.beta_min) return PgmNext::Converged;
  if (!solveQp(options.beta_min)) {
    stats.status = StepStatus::QpFailed;
    return PgmNext::Fail;
  }
  if (!stepIsWorthTaking(options, loop.K, loop.least_decrease)) return PgmNext::Converged;
  beta = std::max(options.beta_min, beta / (options.eta * options.eta));
  return PgmNext::Iterate;
}

// Projects θ + DΔw onto G(·, w + Δw) = 0 and applies the trust-region test: a rejected move raises
// β (failing past β_max), an accepted one moves the iterate and relaxes β.
StepSolver::PgmNext StepSolver::tryMove(const System& system, const IntegratorOptions& options, PgmLoop& loop,
                                        double& beta, StepAttempt& stats) {
  w_trial_ = w_ + dw_;
  // Newton starts from the QP's own linear prediction of where the step goes, θ + D Δw.
  Eigen::VectorXd& candidate = theta_candidate_;
  candidate = theta_;
  candidate.noalias() += D_ * dw_;
  // The trial only has to be projected well enough to compare K: a residual r moves K by about λᵀr,
  // so ‖r‖∞ ≤ κ·(predicted decrease)/‖λ‖₁ decides the trust-region test as the full projection
  // would, to κ of the step's decrease. Not with the dropped term, whose Jacobian is not G's.
  const double loose = loop.derivative != ContactDerivative::Dropped && adjoint_norm_ > 0
                           ? kTrialLooseness * predicted_decrease_ / adjoint_norm_
                           : 0.0;
  const bool projected = projection_.project(residual_, system, options, candidate, w_trial_, loop.derivative, stats, loose);
  const bool trial_loose = loose > projection_.tolerance();
  loop.evaluated_here = loop.derivatives_here = false;
  if (!projected || !(residual_.K < loop.K)) {
    ++stats.rejected;
    beta *= options.eta_reject;
    if (beta > options.beta_max) {
      stats.status = StepStatus::TrustRegionFailed;
      return PgmNext::Fail;
    }
    return PgmNext::Iterate;
  }
  const double decrease = loop.K - residual_.K;
  const double agreement = decrease / predicted_decrease_;
  if (stats.first_agreement < 0) {
    stats.first_agreement = agreement;
    stats.first_beta = beta;
  }
  const bool penalty_limited = agreement > kModelAgreed && loop.previous_prediction > 0 &&
                               predicted_decrease_ > kSamePace * loop.previous_prediction;
  loop.previous_prediction = predicted_decrease_;
  const double moved = (candidate - theta_).lpNorm<Eigen::Infinity>();
  theta_.swap(candidate);
  w_.swap(w_trial_);
  loop.theta_loose = trial_loose;
  loop.K = residual_.K;
  loop.evaluated_here = true;
  loop.need_direction = true;
  beta = std::max(beta / (penalty_limited ? options.eta_limited : loop.eta), options.beta_min);
  // A small move ends the iteration (DESIGN.md 3), except with the dropped term: that model makes
  // small moves far from the solution (its D̄ overstates how θ follows w), so there only K decides;
  // with the move rule a pushed block slides where it should stick.
  if (decrease >= loop.energy_tolerance && (moved >= options.epsilon || loop.derivative == ContactDerivative::Dropped))
    return PgmNext::Iterate;
  return PgmNext::Converged;
}

// The solution θ projected to the full tolerance, the contact wrenches evaluated at it, and θ̇.
void StepSolver::finishPgm(const System& system, const IntegratorOptions& options, const PgmLoop& loop,
                           StepAttempt& stats) {
  bool evaluated_here = loop.evaluated_here;
  if (loop.theta_loose) {
    if (!projection_.project(residual_, system, options, theta_, w_, loop.derivative, stats)) {
      stats.status = StepStatus::ProjectionFailed;
      return;
    }
    evaluated_here = true;
  }
  if (!evaluated_here) {  // for the contact wrenches at θ
    residual_.evaluateValue(system, theta_, w_);
    ++stats.g_evaluations;
  }
  residual_.velocity(system, theta_, velocity_);
  if (!theta_.allFinite() || !velocity_.allFinite()) stats.status = StepStatus::NonFinite;
}

}  // namespace nmdp
