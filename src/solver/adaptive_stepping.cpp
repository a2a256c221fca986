#include "solver/adaptive_stepping.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "multibody/crba.hpp"
#include "solver/bdf2.hpp"

namespace nmdp {

namespace {

struct Recursion {
  const System& system;
  const IntegratorOptions& options;
  const PdTargetSource& targets;
  SimulationState& state;
  StepWorkspace& ws;
  StepStats& stats;
  CancelFlag cancel;
  bool halted = false;  // a failure that halving must not retry (Diverged, Cancelled)
  bool error_rejected = false;  // error control refused a converged sub-step; retry at suggested_h
  double suggested_h = 0.0;
  bool closest_recorded = false;  // stats.energy holds a sub-step's balance

  bool step(double h) {
    if (cancel && *cancel) return halt(StepStatus::Cancelled);
    targets.evaluate(state.time + h, ws.target);
    StepSolver& solver = ws.solver;
    const Eigen::VectorXd& w_start = options.warm_start_weights ? state.w : ws.zero_weights;
    // β carries over from accepted steps only: a failed attempt leaves it where it started.
    const double beta_start = options.adapt_start_penalty ? std::max(state.beta, state.beta_start) : state.beta;
    double beta = beta_start;
    StepAttempt a = solver.attempt(system, options, state, h, ws.target, w_start, beta, cancel);
    addIterationCounts(stats, a);
    if (a.status == StepStatus::Converged && options.order == 2 && state.second_order_history && touchesDown()) {
      // A BDF2 step across an impact carries the position's extrapolation q̂ past the contact that
      // stopped the velocity (the body sinks by c·h·v); retake it at first order (accept() keeps the
      // next two first order too), as a multistep method restarts at a discontinuity. A retry of
      // this sub-step after a failure or an error rejection is first order as well.
      state.second_order_history = false;
      ++stats.first_order_restarts;
      beta = beta_start;
      a = solver.attempt(system, options, state, h, ws.target, w_start, beta, cancel);
      addIterationCounts(stats, a);
    }
    if (a.status == StepStatus::Cancelled) return halt(StepStatus::Cancelled);
    if (a.status == StepStatus::Converged && !energyHolds(h)) return halt(StepStatus::Diverged);
    if (a.status == StepStatus::Converged && options.accuracy > 0 && !errorHolds(h)) return false;
    if (a.status == StepStatus::Converged) {
      state.beta = beta;
      if (options.adapt_start_penalty && a.first_agreement >= 0) {
        // A trust region's radius rule, applied to the next step's first move.
        constexpr double kOverreached = 0.5, kAgreed = 0.9, kFactor = 2.0;
        const double start = a.first_agreement < kOverreached ? kFactor * a.first_beta
                             : a.first_agreement > kAgreed    ? a.first_beta / kFactor
                                                              : a.first_beta;
        state.beta_start = std::clamp(start, options.beta_min, options.beta_max);
      }
      accept(h);
      return true;
    }
    if (!options.adaptive || 0.5 * h < options.min_substep) {
      stats.status = a.status;
      return false;
    }
    return step(0.5 * h) && !halted && step(0.5 * h);
  }

  // Whether a contact wrench carries load: a force above a tenth of the contact's even share of the
  // robot's weight (m·1 m/s² without gravity). Smooth contact models let a foot in the air push
  // with a small force (the Coulomb cone's kζ, 0.1 N by default); that is no impact.
  bool carriesLoad(const Vec6& f) const {
    constexpr double kShareOfEvenLoad = 0.1;
    const Model& model = *system.model;
    const double weight = model.total_mass * std::max(model.gravity.norm(), 1.0);
    return f.tail<3>().norm() > kShareOfEvenLoad * weight / static_cast<double>(system.contacts.size());
  }

  // Whether the solved sub-step puts load on a contact that carried none in the sub-step before.
  bool touchesDown() const {
    for (size_t c = 0; c < state.contact_active.size(); ++c)
      if (!state.contact_active[c] && carriesLoad(ws.solver.contactWrench(static_cast<int>(c)))) return true;
    return false;
  }

  bool energyCheckOn() const { return options.energy_tolerance < std::numeric_limits<double>::infinity(); }

  bool halt(StepStatus status) {
    stats.status = status;
    halted = true;
    return false;
  }

  // The energy balance of the converged attempt (solver/energy_balance.hpp); records the sub-step
  // closest to the limit in stats.energy.
  bool energyHolds(double h) {
    if (!energyCheckOn()) return true;
    const Model& model = *system.model;
    if (!(ws.state_energy_q == state.q && ws.state_energy_qd == state.qd && ws.state_energy_chart == state.base_chart)) {
      ws.energy_data.base_chart = state.base_chart;
      ws.state_energy = mechanicalEnergy(model, ws.energy_data, state.q, state.qd);
      ws.state_energy_q = state.q;
      ws.state_energy_qd = state.qd;
      ws.state_energy_chart = state.base_chart;
    }
    const StepSolver& solver = ws.solver;
    ws.energy_data.base_chart = state.base_chart;
    const MechanicalEnergy after = mechanicalEnergy(model, ws.energy_data, solver.theta(), solver.velocity());
    const EnergyBalance b = energyBalance(model, ws.state_energy, after, system.gains, ws.target, system.external_force,
                                          state.q, solver.theta(), h, options.energy_tolerance);
    if (!closest_recorded || b.excess() - b.tolerance > stats.energy.excess - stats.energy.tolerance ||
        b.diverged()) {
      stats.energy = {b.excess(), b.supplied, b.turnover, b.tolerance, b.free_fall};
      closest_recorded = true;
    }
    if (b.diverged()) return false;
    // After accept() the state is (θ, θ̇) in the same chart: its energy is `after`.
    ws.state_energy = after;
    ws.state_energy_q = solver.theta();
    ws.state_energy_qd = solver.velocity();
    return true;
  }

  // The order the sub-step of size h from the current state is taken at (solver/bdf2.hpp).
  int orderOfStep(double h) const {
    return options.order == 2 && secondOrderStepCoefficients(state, h).extrapolation != 0.0 ? 2 : 1;
  }

  // Error control: the converged sub-step's local error (solver/local_error.hpp). Above the
  // tolerance the sub-step is refused (state untouched) unless it is already at min_substep.
  bool errorHolds(double h) {
    const StepSolver& solver = ws.solver;
    const int order = orderOfStep(h);
    LocalErrorStep s;
    s.order = order;
    s.h = h;
    s.h_prev = state.h_prev;
    s.q_before = &state.q;
    s.q_after = &solver.theta();
    s.v_before = &state.qd;
    s.v_after = &solver.velocity();
    s.v_prev = &state.qd_prev;
    // H(θ) in the state's chart: the energy check's mechanicalEnergy left it in energy_data.
    if (!energyCheckOn()) {
      ws.energy_data.base_chart = state.base_chart;
      crba(*system.model, ws.energy_data, solver.theta());
    }
    const double err = ws.local_error.normalized(s, ws.energy_data.H, options.accuracy);
    if (!(err <= 1.0) && 0.5 * h >= options.min_substep) {
      ++stats.error_rejections;
      error_rejected = true;
      suggested_h = std::max(LocalError::nextStep(h, std::isfinite(err) ? err : 1e6, order), options.min_substep);
      return false;
    }
    stats.error_estimate = std::max(stats.error_estimate, err);
    state.h_next = std::max(LocalError::nextStep(h, err, order), options.min_substep);
    return true;
  }

  void accept(double h) {
    const StepSolver& solver = ws.solver;
    // Copies, not swaps: each of the state's vectors keeps its buffer for the whole run (the Python
    // bindings' numpy arrays view state().q and state().qd).
    state.q_prev = state.q;
    state.q = solver.theta();
    state.qd_prev = state.qd;
    state.qd = solver.velocity();
    state.h_prev = h;
    state.time += h;
    state.w = solver.weights();
    bool in_contact = false, touchdown = false;
    for (size_t c = 0; c < ws.impulse.size(); ++c) {
      const Vec6 f = solver.contactWrench(static_cast<int>(c));
      ws.impulse[c] += h * f;
      in_contact = in_contact || !f.isZero(0.0);
      const bool active = carriesLoad(f);
      touchdown = touchdown || (active && !state.contact_active[c]);
      state.contact_active[c] = active ? 1 : 0;
    }
    // The impact of a compliant contact at a coarse step ends within the sub-step after the
    // touchdown: the two sub-steps after it are first order, so that BDF2 restarts from velocities
    // on the far side of the jump.
    state.substeps_since_touchdown =
        touchdown ? 0 : std::min(state.substeps_since_touchdown + 1, kTouchdownRestartSubsteps);
    state.second_order_history = state.substeps_since_touchdown >= kTouchdownRestartSubsteps;
    ws.substep_sizes.push_back(h);
    ws.substep_in_contact.push_back(in_contact ? 1 : 0);
    ++stats.substeps;
    stats.min_substep = stats.substeps == 1 ? h : std::min(stats.min_substep, h);
  }
};

// Error control's cover of [t, t + dt]: sub-steps of the controller's size, never above dt, the
// last one shortened (or the last two evened out) to land on t + dt.
bool controlledSteps(Recursion& recursion, SimulationState& state, double dt, const IntegratorOptions& options) {
  const double t_end = state.time + dt;
  // A remainder below this share of dt is round-off of the sub-steps' sum, not time left.
  constexpr double kLanded = 1e-9;
  // Stretch a sub-step by up to this factor rather than leave a sliver for the next.
  constexpr double kStretch = 1.2;
  bool retry = false;  // the last sub-step was rejected: its successor may not be stretched back
  while (t_end - state.time > kLanded * dt) {
    const double remaining = t_end - state.time;
    double h = state.h_next > 0 ? std::min(state.h_next, dt) : dt;
    if (h * (retry ? 1.0 : kStretch) >= remaining)
      h = remaining;
    else if (2 * h > remaining)
      h = 0.5 * remaining;
    recursion.error_rejected = false;
    retry = false;
    if (recursion.step(h)) continue;
    if (!recursion.error_rejected || recursion.halted) return false;
    state.h_next = recursion.suggested_h;
    retry = true;
  }
  state.time = t_end;
  return true;
}

}  // namespace

bool stepAdaptively(const System& system, const IntegratorOptions& options, const PdTargetSource& targets,
                    SimulationState& state, double dt, StepWorkspace& workspace, StepStats& stats, CancelFlag cancel) {
  Recursion recursion{system, options, targets, state, workspace, stats, cancel};
  return options.accuracy > 0 ? controlledSteps(recursion, state, dt, options) : recursion.step(dt);
}

}  // namespace nmdp
