#include "sim/trajectory_recorder.hpp"

#include "multibody/kinematics.hpp"

namespace nmdp {

TrajectoryLayout trajectoryLayout(const Simulation& sim) {
  TrajectoryLayout layout;
  layout.joint_names = sim.model().dof_names;
  for (const ContactPoint& c : sim.system().contacts) layout.contact_names.push_back(c.name);
  layout.config_json = sim.resolvedScene().dump(2);
  layout.string_attributes = {{"robot", sim.model().robot_name},
                              {"method", methodName(sim.options().method)},
                              {"contact_model", sim.contactModel().describe()},
                              {"terrain", sim.terrain().describe()}};
  layout.number_attributes = {{"dt", sim.dt()}, {"duration", sim.scene().duration}};
  return layout;
}

TrajectoryRecorder::TrajectoryRecorder(TrajectoryWriter& writer, const Simulation& sim)
    : writer_(writer),
      model_(sim.model()),
      pose_data_(sim.model()),
      every_(sim.scene().output_every),
      scheduled_(sim.scheduledSteps()) {
  StepStats initial;
  initial.converged = true;
  keep(sim, initial);
}

void TrajectoryRecorder::keep(const Simulation& sim, const StepStats& stats) {
  const SimulationState& state = sim.state();
  last_.time = state.time;
  last_.q = state.q;
  last_.qd = state.qd;
  last_.base_chart = state.base_chart;
  last_.wrench = sim.contactWrenches();
  last_.stats = stats;
  recorded_ = false;
}

void TrajectoryRecorder::record() {
  Vec3 base_position, base_rpy;
  pose_data_.base_chart = last_.base_chart;
  forwardKinematics(model_, pose_data_, last_.q);
  basePose(model_, pose_data_, base_position, base_rpy);
  writer_.append(last_.time, last_.q, last_.qd, base_position, base_rpy, last_.wrench, last_.stats);
  recorded_ = true;
}

void TrajectoryRecorder::start() { record(); }

void TrajectoryRecorder::observe(const Simulation& sim, const StepStats& stats) {
  ++completed_;
  keep(sim, stats);
  if (completed_ % every_ == 0 || completed_ == scheduled_) record();
}

void TrajectoryRecorder::finish() {
  if (!recorded_) record();
}

}  // namespace nmdp
