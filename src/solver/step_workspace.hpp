// Every buffer a time step needs, sized once for a system and method: the solver, the energy
// check's and error control's workspaces, and the per-step outputs. What one step hands to the next
// is in SimulationState, not here (solver/integrator.hpp).
#pragma once
#include <cstdint>
#include <vector>

#include "control/pd_target_source.hpp"
#include "solver/energy_balance.hpp"
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

}  // namespace nmdp
