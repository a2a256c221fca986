// One time step of any of the five methods, with Algorithm 2 adaptive sub-stepping (DESIGN.md 4):
//
//   Step(h):  if the method succeeds at h → advance the state
//             else if h/2 < min_substep → fail
//             else Step(h/2); Step(h/2)
//
// Every sub-step is a complete step of its own size h (θ̇ = (θ − q_n)/h, PBD α = h/h_prev, BDF2
// ω = h/h_prev, PD target at t + h), so a split trajectory is exactly the trajectory of the smaller steps. On failure the
// state is left at the last accepted sub-step and the status says why. Nothing prints.
//
// A sub-step that converges is accepted only if its energy balance holds (solver/energy_balance.hpp);
// one that fails it ends the step with StepStatus::Diverged, without halving: the check judges the
// result, not the solver's progress, and an explicit method past its stability limit (ne-mdp, whose
// blow-up the paper reports) must fail there rather than be rescued by smaller steps. A raised
// CancelFlag ends the step with StepStatus::Cancelled at the next sub-step or outer iteration.
//
// With error control (IntegratorOptions::accuracy > 0) a converged sub-step is also judged by its
// local error estimate (solver/local_error.hpp): above the tolerance it is rejected and retried at
// the size the controller gives; the step of dt is then a sequence of such sub-steps, each of them
// split as above if it fails, the last one landing on t + dt.
#pragma once
#include <cstdint>
#include <vector>

#include "control/pd_target_source.hpp"
#include "solver/energy_balance.hpp"
#include "config/integrator_options.hpp"
#include "solver/simulation_state.hpp"
#include "solver/step_stats.hpp"
#include "solver/system.hpp"
#include "solver/local_error.hpp"
#include "solver/step_solver.hpp"

namespace nmdp {

// Every buffer one step needs, sized once for a system and method.
struct StepWorkspace {
  StepWorkspace(const System& system, const IntegratorOptions& options);
  StepSolver solver;
  // Contact wrenches [torque about the sphere centre; force] (world) of the last step, averaged over
  // its sub-steps weighted by their duration (impulse / dt).
  std::vector<Vec6> contact_wrench;
  // Accepted sub-steps of the last step, in order (size() == stats.substeps).
  std::vector<double> substep_sizes;
  std::vector<std::uint8_t> substep_in_contact;  // any contact force nonzero in that sub-step
  PdTarget target;                 // scratch for the PD target
  std::vector<Vec6> impulse;       // scratch
  Eigen::VectorXd zero_weights;    // cold start
  // The energy check: its own kinematics workspace, and the mechanical energy of the state it was
  // last computed for (q, q̇, chart), reused while the state is the same.
  Data energy_data;
  MechanicalEnergy state_energy;
  Eigen::VectorXd state_energy_q, state_energy_qd;
  Mat3 state_energy_chart = Mat3::Zero();
  LocalError local_error;  // error control's estimator
};

// Advances `state` by dt (or as far as it got, on failure). Returns the status and statistics.
// `cancel` (may be null) is polled during the step.
StepStats advance(const System& system, const IntegratorOptions& options, const PdTargetSource& targets,
                  SimulationState& state, double dt, StepWorkspace& workspace, CancelFlag cancel = nullptr);

}  // namespace nmdp
