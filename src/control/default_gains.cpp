#include "control/default_gains.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "multibody/crba.hpp"
#include "multibody/data.hpp"
#include "multibody/feet.hpp"
#include "multibody/kinematics.hpp"

namespace nmdp {

GainInertia gainInertia(const Model& model, const Eigen::VectorXd& q) {
  if (q.size() != model.nq)
    throw std::invalid_argument("default gains: the pose has " + std::to_string(q.size()) + " entries, the robot has " +
                                std::to_string(model.nq) + " coordinates");
  if (!q.allFinite()) throw std::invalid_argument("default gains: the pose is not finite");
  GainInertia out;
  out.subtree = Eigen::VectorXd::Zero(model.nq);
  out.load = Eigen::VectorXd::Zero(model.nq);
  Data data(model);
  crba(model, data, q);  // also leaves the kinematics at q
  for (int j = 0; j < model.nq; ++j)
    if (!model.bodies[j].is_base) out.subtree[j] = data.H(j, j);

  // The load term: only where the legs carry the robot (not on a fixed base).
  if (model.base != BaseType::Fixed) {
    struct Foot {
      int body;
      Vec3 point;
    };
    std::vector<Foot> feet;
    for (const FootContact& f : detectFeet(model)) {
      const int link = model.linkIndex(f.point.name);
      if (link < 0 || model.links[link].body < 0) continue;
      feet.push_back({model.links[link].body, linkPoint(model, data, link, f.point.offset)});
    }
    out.feet = static_cast<int>(feet.size());
    if (!feet.empty() && model.total_mass > 0.0) {
      const double share = model.total_mass / static_cast<double>(feet.size());
      Mat3X J(3, model.nq);
      for (const Foot& f : feet) {
        pointJacobian(model, data, f.body, f.point, J);
        for (int j = 0; j < model.nq; ++j)
          if (!model.bodies[j].is_base && model.isAncestor(j, f.body)) out.load[j] += share * J.col(j).squaredNorm();
      }
    }
  }

  out.total = out.subtree + out.load;
  return out;
}

PdGains gainsForInertia(const Model& model, const Eigen::VectorXd& inertia, double frequency_hz, double damping_ratio) {
  const double omega = 2.0 * M_PI * frequency_hz;
  return actuatedPdGains(model, [&](int j) {
    return std::pair(inertia[j] * omega * omega, 2.0 * damping_ratio * omega * inertia[j]);
  });
}

PdGains defaultPdGains(const Model& model, const Eigen::VectorXd& q) {
  return gainsForInertia(model, gainInertia(model, q).total);
}

}  // namespace nmdp
