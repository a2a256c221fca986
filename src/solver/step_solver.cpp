#include "solver/step_solver.hpp"

#include <cmath>
#include <limits>

#include "multibody/crba.hpp"
#include "multibody/rnea.hpp"

namespace nmdp {

namespace {
bool allFinite(const Eigen::VectorXd& v) { return v.allFinite(); }
}  // namespace

bool StepSolver::stepIsWorthTaking(const IntegratorOptions& options, double K, double least_decrease) {
  if (dw_.size() == 0) return false;
  // Δw has no scale of its own (a deep foot's vertices carry 1e9 N, and a weight of 1e-8 on them
  // matters), so tol_w bounds the change of the generalized contact force relative to the weight.
  generalized_force_change_.noalias() = B_theta_ * dw_;
  if (generalized_force_change_.lpNorm<Eigen::Infinity>() < options.tol_w * weight_scale_) return false;
  Qdw_.noalias() = Q_ * dw_;
  const double predicted = -(g_.dot(dw_) + 0.5 * dw_.dot(Qdw_));
  predicted_decrease_ = predicted;
  const double theta_accuracy = projection_tolerance_ * residual_.h() * residual_.h() / mass_scale_;
  const double resolvable =
      64 * std::numeric_limits<double>::epsilon() * std::abs(K) + residual_.grad_K.lpNorm<1>() * theta_accuracy;
  return predicted > std::max(resolvable, least_decrease);
}

void StepSolver::scaleFromQ() {
  // β is relative to each weight's own curvature Q_ii (Marquardt's scaling): a foot in the air has
  // vertices of 0.1 N and a loaded foot of hundreds of N, so their Q_ii differ by 1e6, and one
  // scalar penalty either freezes the light ones or does not restrain the heavy ones.
  const double largest = Q_.size() ? Q_.diagonal().maxCoeff() : 0.0;
  const double floor = largest > 0 ? 1e-12 * largest : 1.0;
  penalty_scale_ = Q_.diagonal().cwiseMax(floor);
}

bool StepSolver::solveQp(double beta) {
  Q_penalized_ = Q_;
  Q_penalized_.diagonal() += beta * penalty_scale_;
  const QpResult qp = qp_.solve(Q_penalized_, 0.0, g_, w_, dw_, warm_valid_ ? &warm_ : nullptr);
  if (qp.status != QpStatus::Converged) return false;
  warm_ = qp_.activeSet();
  warm_valid_ = true;
  return true;
}

StepSolver::StepSolver(const System& system)
    : residual_(system), llt_(system.model->nq) {
  const Model& model = *system.model;
  const int n = model.nq;
  const int C = static_cast<int>(system.contacts.size());
  const int m = residual_.weightCount();
  K_vertices_ = C > 0 ? m / C : 0;
  lu_.resize(n);
  anderson_.resize(n, kAndersonMemory);
  qp_.resize(std::vector<int>(C, K_vertices_));
  warm_.at_bound.assign(m, 0);
  warm_.cap.assign(C, 0);
  theta_.setZero(n);
  theta_trial_.setZero(n);
  theta_candidate_.setZero(n);
  adjoint_.setZero(n);
  velocity_.setZero(n);
  step_.setZero(n);
  tau_.setZero(n);
  w_.setZero(m);
  w_trial_.setZero(m);
  dw_.setZero(m);
  g_.setZero(m);
  D_.setZero(n, m);
  Qdw_.setZero(m);
  penalty_scale_.setZero(m);
  Q_penalized_.setZero(m, m);
  B_theta_.setZero(n, m);
  generalized_force_change_.setZero(n);
  Q_.setZero(m, m);
  HD_.setZero(n, m);
  mass_scale_ = model.total_mass > 0 ? model.total_mass : 1.0;
  weight_scale_ = mass_scale_ * std::max(model.gravity.norm(), 1.0);
}

Vec6 StepSolver::contactWrench(int c) const {
  const ContactWrenches& cw = residual_.wrenches[c];
  return cw.V * w_.segment(c * K_vertices_, K_vertices_);
}

StepAttempt StepSolver::attempt(const System& system, const IntegratorOptions& options, const SimulationState& state,
                                double h, const PdTarget& target, const Eigen::VectorXd& w_start, double& beta,
                                CancelFlag cancel) {
  if (options.method == Method::NeMdp) return neMdp(system, state, h, target, w_start);
  return pgm(system, options, state, h, target, w_start, beta, cancel);
}

bool StepSolver::project(const System& system, const IntegratorOptions& options, Eigen::VectorXd& theta,
                         const Eigen::VectorXd& w, ContactDerivative derivative, StepAttempt& stats, double loose) {
  ++stats.projections;
  const int n = static_cast<int>(theta.size());
  // Round-off in G: the inertial term divides θ's round-off by h².
  const double h = residual_.h();
  const double lever = 1.0 + theta.lpNorm<Eigen::Infinity>();
  const double tolerance = options.projection_tolerance * weight_scale_ +
                           1e3 * std::numeric_limits<double>::epsilon() * mass_scale_ * lever * lever / (h * h);
  projection_tolerance_ = tolerance;
  const double stop = std::max(tolerance, loose);
  bool fresh = false, refresh = !factorization_valid_;
  if (refresh)
    residual_.evaluate(system, theta, w, derivative);
  else
    residual_.evaluateValue(system, theta, w);
  ++stats.g_evaluations;
  if (!allFinite(residual_.G)) return false;
  // Converged on ‖G‖∞; a step must decrease ‖G‖₂, the merit function Newton's direction descends.
  double norm = residual_.G.lpNorm<Eigen::Infinity>(), merit = residual_.G.norm();
  // The factorization of ∂G/∂θ at a nearby iterate (at first the current PGM iterate's, which D
  // used) is kept while its steps contract ‖G‖₂ by kRefreshContraction (chord steps: values of G
  // only, a fifth of the cost); it is refreshed at the current θ when they do not or fail, and only
  // a fresh factorization whose step fails is divergence. Anderson acceleration combines the steps
  // taken with one factorization, which undoes most of its staleness (the chord steps alone
  // contract ‖G‖ at a steady 0.07–0.3 per step on the trot).
  bool evaluated_with_derivatives = refresh;
  bool values_at_theta = true;  // the residual's last evaluation is at θ (to be completed, not redone)
  anderson_.reset();
  for (int it = 0;; ++it) {
    if (norm <= stop) return true;
    if (it == options.projection_max_iterations) return false;
    if (refresh) {
      if (!evaluated_with_derivatives) {
        if (values_at_theta)
          residual_.addDerivatives(system, theta, w, derivative);
        else
          residual_.evaluate(system, theta, w, derivative);
        ++stats.g_evaluations;
      }
      factorization_valid_ = lu_.compute(residual_.dG_dtheta) == n;
      if (!factorization_valid_) return false;
      fresh = true;
      refresh = evaluated_with_derivatives = false;
      anderson_.reset();
    }
    step_ = -residual_.G;
    lu_.solveInPlace(step_);
    anderson_.accelerate(theta, step_);
    ++stats.newton_iterations;
    double trial_merit = 0.0;
    bool decreased = false;
    for (int k = 0;; ++k) {
      theta_trial_ = theta + step_;
      residual_.evaluateValue(system, theta_trial_, w);
      ++stats.g_evaluations;
      trial_merit = residual_.G.norm();
      if (trial_merit < merit) {  // false for NaN
        decreased = true;
        break;
      }
      // An old factorization is refreshed rather than its step shortened.
      if (!fresh || k == options.projection_backtracking) break;
      step_ *= 0.5;
    }
    if (!decreased) {
      if (fresh) return false;  // divergence (also catches NaN)
      refresh = true;  // at θ (the residual holds the trial's values until then)
      values_at_theta = false;
      continue;
    }
    theta.swap(theta_trial_);
    values_at_theta = true;
    refresh = trial_merit > kRefreshContraction * merit;
    fresh = false;
    merit = trial_merit;
    norm = residual_.G.lpNorm<Eigen::Infinity>();
  }
}

StepAttempt StepSolver::pgm(const System& system, const IntegratorOptions& options, const SimulationState& state,
                            double h, const PdTarget& target, const Eigen::VectorXd& w_start, double& beta, CancelFlag cancel) {
  StepAttempt stats;
  const ContactDerivative derivative =
      needsContactDerivative(options.method)                                    ? ContactDerivative::Model
      : options.zeroth_order_jacobian == ZerothOrderJacobian::FiniteDifference ? ContactDerivative::FiniteDifference
                                                                                : ContactDerivative::Dropped;
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
  factorization_valid_ = false;  // ∂G/∂θ of another step (another h, q_n, target)
  if (!project(system, options, theta_, w_, derivative, stats)) {
    stats.status = StepStatus::ProjectionFailed;
    return stats;
  }
  double K = residual_.K;
  // ε on K is relative to the energy gravity gives the robot in one step, ½ m (‖g‖ h)²: 2 J for the
  // 17 kg quadruped at 50 ms (so ε·2 J ≈ the paper's absolute 1e-6 J for its 100 kg robot), but
  // 5e-3 J for a 1 kg box at 10 ms, whose sticking would otherwise pass for converged while it creeps.
  const double gravity_h = std::max(system.model->gravity.norm(), 1.0) * h;
  const double energy_tolerance = options.epsilon * 0.5 * mass_scale_ * gravity_h * gravity_h;
  // A step predicted to lower K by less than ε would end the iteration once taken (below), so it
  // is not taken: its projection is most of an iteration's cost. The QP's model is K's to second
  // order near the solution (predicted and actual decreases agree to a few per cent on the trot),
  // so this stops where the rule below would, one step short of a step smaller than ε. Not with
  // the dropped term, whose model misses the contact stiffness.
  const double least_decrease = derivative == ContactDerivative::Dropped ? 0.0 : energy_tolerance;
  // The dropped term's model overstates how far θ follows w, so its penalty relaxes at DESIGN.md's
  // η (η_limited still applies after a penalty-limited move, whose model agreed): at η = 5 a block
  // held at 0.9 μmg crept 2.6e-4 m in 1 s (4.8e-5 m at 1.5).
  const double eta = derivative == ContactDerivative::Dropped ? std::min(options.eta, kDesignRelaxation) : options.eta;
  bool theta_loose = false;     // θ is projected only as far as its trust-region test needed
  bool evaluated_here = true;  // the residual holds G and K at (θ, w)
  bool derivatives_here = false;  // ... and ∂G/∂θ, B, ∇K, ∇²K
  bool need_direction = true;
  double previous_prediction = 0.0;  // the QP's predicted decrease for the previous accepted move (0: none)
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
    if (need_direction) {
      if (!derivatives_here) {
        if (evaluated_here)  // by the projection that ended at θ
          residual_.addDerivatives(system, theta_, w_, derivative);
        else
          residual_.evaluate(system, theta_, w_, derivative);
        ++stats.g_evaluations;
        derivatives_here = evaluated_here = true;
      }
      factorization_valid_ = lu_.compute(residual_.dG_dtheta) == theta_.size();
      if (!factorization_valid_) {
        stats.status = StepStatus::ProjectionFailed;
        return stats;
      }
      adjoint_ = residual_.grad_K;
      lu_.solveTransposeInPlace(adjoint_);
      adjoint_norm_ = adjoint_.lpNorm<1>();
      // A loosely projected θ's K, corrected to where Newton would end: θ* = θ − (∂G/∂θ)⁻¹G moves K
      // by −λᵀG to second order (75–30 000× closer to the fully projected K on sampled trot
      // steps), so the next trials are judged against K(θ*), not against θ's own projection error.
      if (theta_loose) K -= adjoint_.dot(residual_.G);
      B_theta_ = residual_.B;
      D_ = residual_.B;
      lu_.solveInPlace(D_);
      g_.noalias() = D_.transpose() * residual_.grad_K;
      HD_.noalias() = residual_.hess_K * D_;
      Q_.noalias() = D_.transpose() * HD_;
      scaleFromQ();
      need_direction = false;
    }
    if (!solveQp(beta)) {
      stats.status = StepStatus::QpFailed;
      return stats;
    }
    // Converged when the step is below tol_w, or when the decrease of K the QP predicts is below ε
    // (least_decrease) or below what K can resolve: θ is only known to the projection's tolerance,
    // so the trust-region test would compare noise (at small h this, not ε, is what stops the
    // iteration). A large penalty makes any step small, so convergence is confirmed without it
    // (re-solved at β_min); if the penalty was hiding progress, it is lowered and the QP solved
    // again (no projection needed).
    if (!stepIsWorthTaking(options, K, least_decrease)) {
      if (beta <= options.beta_min) break;
      if (!solveQp(options.beta_min)) {
        stats.status = StepStatus::QpFailed;
        return stats;
      }
      if (!stepIsWorthTaking(options, K, least_decrease)) break;
      beta = std::max(options.beta_min, beta / (options.eta * options.eta));
      continue;
    }
    {
      w_trial_ = w_ + dw_;
      // Newton starts from the QP's own linear prediction of where the step goes, θ + D Δw.
      Eigen::VectorXd& candidate = theta_candidate_;
      candidate = theta_;
      candidate.noalias() += D_ * dw_;
      // The trial only has to be projected well enough to compare K: a residual r moves K by
      // about λᵀr (λ = (∂G/∂θ)⁻ᵀ∇K at the iterate), so ‖r‖∞ ≤ κ·(predicted decrease)/‖λ‖₁ decides
      // the trust-region test as the full projection would, to κ of the step's decrease. Early
      // steps, which lower K by much, stop Newton long before the tolerance; near the solution the
      // bound falls below it. Not with the dropped term, whose Jacobian is not G's.
      const double loose = derivative != ContactDerivative::Dropped && adjoint_norm_ > 0
                               ? kTrialLooseness * predicted_decrease_ / adjoint_norm_
                               : 0.0;
      const bool projected = project(system, options, candidate, w_trial_, derivative, stats, loose);
      const bool trial_loose = loose > projection_tolerance_;
      evaluated_here = derivatives_here = false;
      if (!projected || !(residual_.K < K)) {
        ++stats.rejected;
        beta *= options.eta_reject;
        if (beta > options.beta_max) {
          stats.status = StepStatus::TrustRegionFailed;
          return stats;
        }
        continue;
      }
      const double decrease = K - residual_.K;
      const double agreement = decrease / predicted_decrease_;
      if (stats.first_agreement < 0) {
        stats.first_agreement = agreement;
        stats.first_beta = beta;
      }
      const bool penalty_limited = agreement > kModelAgreed && previous_prediction > 0 &&
                                   predicted_decrease_ > kSamePace * previous_prediction;
      previous_prediction = predicted_decrease_;
      const double moved = (candidate - theta_).lpNorm<Eigen::Infinity>();
      theta_.swap(candidate);
      w_.swap(w_trial_);
      theta_loose = trial_loose;
      K = residual_.K;
      evaluated_here = true;
      need_direction = true;
      beta = std::max(beta / (penalty_limited ? options.eta_limited : eta), options.beta_min);
      // A small move ends the iteration (DESIGN.md 3), except with the dropped term: that model makes
      // small moves far from the solution (its D̄ overstates how θ follows w), so there only K
      // decides; with the move rule, a block pushed at 0.9 μmg slid 1 m in 1 s instead of sticking.
      if (decrease >= energy_tolerance && (moved >= options.epsilon || derivative == ContactDerivative::Dropped))
        continue;
    }
    break;
  }
  if (theta_loose) {  // the solution is projected to the full tolerance
    if (!project(system, options, theta_, w_, derivative, stats)) {
      stats.status = StepStatus::ProjectionFailed;
      return stats;
    }
    evaluated_here = true;
  }
  if (!evaluated_here) {  // for the contact wrenches at θ
    residual_.evaluateValue(system, theta_, w_);
    ++stats.g_evaluations;
  }
  residual_.velocity(system, theta_, velocity_);
  if (!allFinite(theta_) || !allFinite(velocity_)) stats.status = StepStatus::NonFinite;
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
    scaleFromQ();
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
