// Algorithm 2, adaptive sub-stepping (DESIGN.md 4):
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
#include "config/integrator_options.hpp"
#include "control/pd_target_source.hpp"
#include "solver/simulation_state.hpp"
#include "solver/step_stats.hpp"
#include "solver/step_workspace.hpp"
#include "solver/system.hpp"

namespace nmdp {

// Takes [t, t + dt] from `state` as above, accumulating into `stats`; false on failure (stats.status
// says why, the state is at the last accepted sub-step).
bool stepAdaptively(const System& system, const IntegratorOptions& options, const PdTargetSource& targets,
                    SimulationState& state, double dt, StepWorkspace& workspace, StepStats& stats, CancelFlag cancel);

}  // namespace nmdp
