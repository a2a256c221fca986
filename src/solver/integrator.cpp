#include "solver/integrator.hpp"

#include <chrono>
#include <cmath>

#include "multibody/base_chart.hpp"
#include "multibody/kinematics.hpp"
#include "solver/adaptive_stepping.hpp"

namespace nmdp {

namespace {

// The middle base angle approaches gimbal lock at ±π/2; re-centre the chart well before.
constexpr double kRebaseAngle = 0.75;

void rebaseIfNeeded(const Model& model, Data& data, SimulationState& state) {
  if (model.base != BaseType::Floating) return;
  if (std::abs(state.q[4]) < kRebaseAngle) return;
  const Mat3 old_chart = state.base_chart;
  const Mat3 R_prev = old_chart * baseAnglesRotation(state.q_prev.segment<3>(3));
  data.base_chart = old_chart;
  rebaseFloatingChart(model, data, state.q, state.qd);
  state.base_chart = data.base_chart;
  state.q_prev.segment<3>(3) = baseAnglesOf(state.base_chart.transpose() * R_prev);
  state.second_order_history = false;  // q̇_prev's base angle rates belong to the old chart
}

}  // namespace

StepStats advance(const System& system, const IntegratorOptions& options, const PdTargetSource& targets,
                  SimulationState& state, double dt, StepWorkspace& workspace, CancelFlag cancel) {
  const auto start = std::chrono::steady_clock::now();
  StepStats stats;
  workspace.substep_sizes.clear();
  workspace.substep_in_contact.clear();
  for (Vec6& i : workspace.impulse) i.setZero();
  rebaseIfNeeded(*system.model, workspace.solver.residual().data, state);
  if (state.contact_active.size() != system.contacts.size()) state.contact_active.assign(system.contacts.size(), 0);
  const double t0 = state.time;
  workspace.solver.takeWarmStart(state.qp_warm, state.qp_warm_valid);
  const bool ok = stepAdaptively(system, options, targets, state, dt, workspace, stats, cancel);
  workspace.solver.returnWarmStart(state.qp_warm, state.qp_warm_valid);
  stats.converged = ok;
  if (ok) stats.status = StepStatus::Converged;
  const double elapsed = state.time - t0;
  for (size_t c = 0; c < workspace.impulse.size(); ++c)
    workspace.contact_wrench[c] = elapsed > 0 ? Vec6(workspace.impulse[c] / elapsed) : Vec6::Zero();
  stats.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace nmdp
