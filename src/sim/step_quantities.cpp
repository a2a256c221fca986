#include "sim/step_quantities.hpp"

#include <Eigen/Geometry>
#include <limits>

#include "multibody/kinematics.hpp"
#include "solver/contact_kinematics.hpp"
#include "solver/energy_balance.hpp"

namespace nmdp {

namespace {
// x, y, z, w of a rotation, w ≥ 0 (q and −q are the same rotation).
Vec4 quaternionOf(const Mat3& R) {
  Eigen::Quaterniond quaternion(R);
  quaternion.normalize();
  Vec4 xyzw = quaternion.coeffs();
  if (xyzw[3] < 0) xyzw = -xyzw;
  return xyzw;
}

}  // namespace

StepQuantities::StepQuantities(const Simulation& sim)
    : data_(sim.model()),
      frames_(sim.system().contacts.size()),
      features_(static_cast<Eigen::Index>(sim.system().contacts.size()),
                static_cast<Eigen::Index>(sim.contactModel().featureInfo().size())) {
  target_.position.setZero(sim.model().nq);
  target_.velocity.setZero(sim.model().nq);
}

void StepQuantities::compute(const Simulation& sim, TrajectoryRow& row) {
  const Model& model = sim.model();
  const System& system = sim.system();
  const SimulationState& state = sim.state();
  row.time = state.time;
  row.q = state.q;
  row.qdot = state.qd;

  // Kinematics and energies: crba runs the forward kinematics the poses below read.
  data_.base_chart = state.base_chart;
  const MechanicalEnergy energy = mechanicalEnergy(model, data_, state.q, state.qd);
  row.kinetic_energy = energy.kinetic;
  row.potential_energy = energy.gravity;
  basePose(model, data_, row.base_position, row.base_rpy);
  Mat3 R;
  Vec3 p;
  linkPose(model, data_, model.root_link, R, p);
  row.base_quaternion = quaternionOf(R);
  row.base_chart = quaternionOf(state.base_chart);
  for (int l = 0; l < static_cast<int>(model.links.size()); ++l) {
    linkPose(model, data_, l, R, p);
    row.link_position.row(l) = p.transpose();
    row.link_quaternion.row(l) = quaternionOf(R).transpose();
  }

  // Contacts: the sphere centres, their distances, the model's features and the step's wrenches.
  const std::vector<Vec6>& wrenches = sim.contactWrenches();
  TerrainQuery query;
  for (size_t c = 0; c < frames_.size(); ++c) {
    const Eigen::Index i = static_cast<Eigen::Index>(c);
    contactFrame(model, data_, system.contacts[c], frames_[c]);
    row.foot_point.row(i) = frames_[c].position.transpose();
    sim.terrain().query(frames_[c].position, query, false);
    row.signed_distance[i] = query.distance - frames_[c].radius;
    row.wrench.row(i) = wrenches[c].transpose();
  }
  if (!frames_.empty()) {
    sim.contactModel().features(frames_, sim.terrain(), features_);
    row.features = features_;
  }

  // The PD law at the end state (see the header).
  sim.targets().evaluate(state.time, target_);
  const PdGains& gains = system.gains;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (Eigen::Index j = 0; j < model.nq; ++j) {
    if (model.bodies[static_cast<size_t>(j)].is_base) {
      row.q_target[j] = row.qdot_target[j] = nan;
      row.torque_pd[j] = row.torque_feedforward[j] = row.torque[j] = 0.0;
      continue;
    }
    row.q_target[j] = target_.position[j];
    row.qdot_target[j] = target_.velocity[j];
    const bool passive = gains.kp[j] == 0.0 && gains.kd[j] == 0.0;  // stable_pd skips it: exactly 0
    row.torque_pd[j] =
        passive ? 0.0 : -gains.kp[j] * (state.q[j] - target_.position[j]) - gains.kd[j] * (state.qd[j] - target_.velocity[j]);
    row.torque_feedforward[j] = gains.tau_ff[j];
    row.torque[j] = row.torque_pd[j] + row.torque_feedforward[j];
  }
}

}  // namespace nmdp
