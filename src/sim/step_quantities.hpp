// What the output file stores per row beyond the state (sim/trajectory_writer.hpp's TrajectoryRow):
// poses (trunk, chart, links, foot spheres), the contacts' distances and the contact model's
// features, the PD torques and targets, and the energies, computed from a Simulation after a step.
//
// The torques are the stable PD law of control/stable_pd.hpp at the state the step ended in:
//   torque_pd = −K_p (q − θ̄(t)) − K_d (q̇ − θ̄̇(t)),  torque = torque_pd + τ_ff,
// θ̄, θ̄̇ the targets at the row's time t (what the integrator asked for at the end of the step's last
// sub-step). The solver evaluates the law at the end of every sub-step with q̇ = (q − q_start)/h, the
// velocity it stores, so this is the torque of the step's last sub-step, and the step's whole torque
// when it took one sub-step. (Second-order PBD, integrator.order 2 with a position-based method,
// stores a BDF2 velocity instead: there the stored torque differs from the applied one by K_d times
// the difference of the two velocities.) The first row's torque is the law at the initial state, which no
// step applied yet.
//
// Allocates only in the constructor.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "multibody/data.hpp"
#include "sim/simulation.hpp"
#include "sim/trajectory_layout.hpp"
#include "sim/trajectory_writer.hpp"

namespace nmdp {

class StepQuantities {
 public:
  explicit StepQuantities(const Simulation& sim);
  // Every field of `row` (sized by TrajectoryRow::resize(trajectoryLayout(sim))) but step and stats,
  // from the simulation's current state and last step.
  void compute(const Simulation& sim, TrajectoryRow& row);

 private:
  Data data_;
  PdTarget target_;
  std::vector<ContactFrame> frames_;
  Eigen::MatrixXd features_;  // C × F
};

}  // namespace nmdp
