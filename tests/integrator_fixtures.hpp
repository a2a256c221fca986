// Systems the integrator tests share: the 1 kg box on a plane and the project's quadruped on a
// plane, both with the Coulomb cone.
#pragma once
#include <cmath>
#include <string>

#include "contact_models/coulomb_model.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/integrator.hpp"
#include "terrain/plane.hpp"
#include "test_support.hpp"

namespace nmdp::test {

// Options of `method` at `order` with error control off: tests of the discretization at the step
// they give it (error control has its own, test_error_control.cpp).
inline IntegratorOptions fixedStepOptions(const char* method, int order = 1) {
  IntegratorOptions o;
  o.method = *parseMethod(method);
  o.order = order;
  o.accuracy = 0;
  return o;
}

// The box on a floating base with its four bottom corners (radius 0) as contacts, or no contacts.
struct BoxOnPlane {
  static constexpr double kHalfHeight = 0.05;
  Model model = loadUrdf(sourcePath("tests/data/box.urdf"), {});
  CoulombModel contact_model;
  PlaneTerrain terrain;
  System system;
  explicit BoxOnPlane(bool with_contacts, const CoulombParameters& params = {}) : contact_model(params) {
    system.model = &model;
    system.gains = massScaledPdGains(model);  // all zero: every coordinate is a base coordinate
    if (with_contacts) {
      for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0}) {
          ContactPoint c;
          c.name = std::string("corner") + (sx > 0 ? "+" : "-") + (sy > 0 ? "+" : "-");
          c.link = model.linkIndex("box");
          c.offset = Vec3(0.1 * sx, 0.1 * sy, -kHalfHeight);
          c.radius = 0.0;
          system.contacts.push_back(c);
        }
      system.contact_model = &contact_model;
      system.terrain = &terrain;
    }
  }
  double mass() const { return model.total_mass; }
  // Base height at which each corner carries a quarter of the weight with its whole cone (1ᵀw = 1).
  double restingHeight() const {
    const CoulombParameters& p = contact_model.parameters();
    const double depth = std::pow(mass() * -model.gravity.z() / 4 / p.k - p.zeta, 1.0 / p.p);
    return kHalfHeight - depth;
  }
};

// The project's quadruped with one contact sphere per foot.
struct QuadrupedOnPlane {
  Model model;
  CoulombModel contact_model;
  PlaneTerrain terrain;
  System system;
  explicit QuadrupedOnPlane(BaseType base = BaseType::Floating, const ContactModel* model_override = nullptr)
      : model(loadUrdf(quadrupedUrdf(), [&] {
          UrdfOptions o;
          o.base = base;
          return o;
        }())) {
    system.model = &model;
    system.contacts = footContactPoints(model);
    system.contact_model = model_override ? model_override : &contact_model;
    system.terrain = &terrain;
    system.gains = massScaledPdGains(model);
  }
  // Foot clearances φ(c) − r at q (negative: penetration).
  Eigen::VectorXd clearances(const Eigen::VectorXd& q) const {
    Data data(model);
    forwardKinematics(model, data, q);
    Eigen::VectorXd out(system.contacts.size());
    for (size_t c = 0; c < system.contacts.size(); ++c) {
      const ContactPoint& cp = system.contacts[c];
      out[c] = linkPoint(model, data, cp.link, cp.offset).z() - cp.radius;
    }
    return out;
  }
  // Legs straight, the feet `depth` below the ground (depth < 0: above it).
  Eigen::VectorXd standing(double depth = 0.0) const {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq);
    q[model.dofIndex("base_z")] -= clearances(q).minCoeff() + depth;
    return q;
  }
};

}  // namespace nmdp::test
