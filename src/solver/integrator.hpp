// One time step of any of the five methods: the base chart re-centred if needed, then adaptive
// sub-stepping (solver/adaptive_stepping.hpp) over the step solver (solver/step_solver.hpp), with
// the contact wrenches averaged over the step. On failure the state is left at the last accepted
// sub-step and the status says why. Nothing prints.
#pragma once
#include "config/integrator_options.hpp"
#include "control/pd_target_source.hpp"
#include "solver/simulation_state.hpp"
#include "solver/step_stats.hpp"
#include "solver/step_workspace.hpp"
#include "solver/system.hpp"

namespace nmdp {

// Advances `state` by dt (or as far as it got, on failure). Returns the status and statistics.
// `cancel` (may be null) is polled during the step. The step depends on `state` alone, not on what
// the workspace computed before: the weight QP's warm start travels in the state (taken by the
// solver here, handed back at the end) and the energy check's cached energy is recomputed, to the
// same bits, for a state it has not seen. So one workspace may step many states (a rollout).
StepStats advance(const System& system, const IntegratorOptions& options, const PdTargetSource& targets,
                  SimulationState& state, double dt, StepWorkspace& workspace, CancelFlag cancel = nullptr);

}  // namespace nmdp
