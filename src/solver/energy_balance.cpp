#include "solver/energy_balance.hpp"

#include <cmath>

#include "multibody/crba.hpp"
#include "multibody/pbd_terms.hpp"

namespace nmdp {

namespace {
bool hasGains(const PdGains& gains, Eigen::Index j) {
  return gains.kp[j] != 0.0 || gains.kd[j] != 0.0 || gains.tau_ff[j] != 0.0;
}
}  // namespace

MechanicalEnergy mechanicalEnergy(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  crba(model, data, q);  // forward kinematics, then H
  MechanicalEnergy e;
  e.kinetic = 0.5 * qd.dot(data.H.lazyProduct(qd));  // lazy: no temporary vector inside a step
  e.gravity = gravityPotential(model, data, nullptr, nullptr);
  return e;
}

double springEnergy(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& q) {
  double P = 0.0;
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    if (!hasGains(gains, j) || gains.kp[j] == 0.0) continue;
    const double d = q[j] - target.position[j];
    P += 0.5 * gains.kp[j] * d * d;
  }
  return P;
}

EnergyBalance energyBalance(const Model& model, const MechanicalEnergy& before, const MechanicalEnergy& after,
                            const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& external_force,
                            const Eigen::VectorXd& q_before, const Eigen::VectorXd& q_after, double h,
                            double relative_tolerance) {
  const double P0 = springEnergy(gains, target, q_before), P1 = springEnergy(gains, target, q_after);
  double supplied = 0.0;
  for (Eigen::Index j = 0; j < q_before.size(); ++j) {
    if (!hasGains(gains, j)) continue;
    const double target_rate = target.velocity[j];
    supplied += 0.25 * h * gains.kd[j] * target_rate * target_rate + gains.tau_ff[j] * (q_after[j] - q_before[j]);
  }
  if (external_force.size() == q_before.size()) supplied += external_force.dot(q_after - q_before);
  EnergyBalance b;
  b.gain = (after.total() + P1) - (before.total() + P0);
  b.supplied = supplied;
  b.turnover = before.kinetic + after.kinetic + std::abs(after.gravity - before.gravity) + P0 + P1 + std::abs(supplied);
  const double gravity_step = model.gravity.norm() * h;
  b.free_fall = 0.5 * model.total_mass * gravity_step * gravity_step;
  b.tolerance = relative_tolerance * b.turnover + b.free_fall;
  return b;
}

}  // namespace nmdp
