// Systems the integrator tests share: the pendulum, the 1 kg box on a plane and the project's
// quadruped on a plane (both with the Coulomb cone), and the references they are checked against.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

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

// A 1 kg bob on a 1 m rod (tests/data/pendulum.urdf, bob inertia 1e-6), fixed base, no gains.
struct FixedPendulum {
  Model model = loadUrdf(sourcePath("tests/data/pendulum.urdf"), [] {
    UrdfOptions o;
    o.base = BaseType::Fixed;
    return o;
  }());
  System system;
  FixedPendulum() {
    system.model = &model;
    system.gains.kp.setZero(1);
    system.gains.kd.setZero(1);
    system.gains.tau_ff.setZero(1);
  }
};

// (θ, θ̇) after T of θ̈ = −ω² sin θ from (θ0, v0), by RK4 with `n` steps: the exact solution for the
// tests' purposes.
inline std::pair<double, double> pendulumReference(double w2, double theta0, double v0, double T, int n = 200000) {
  const double h = T / n;
  double th = theta0, v = v0;
  auto acc = [&](double x) { return -w2 * std::sin(x); };
  for (int i = 0; i < n; ++i) {
    const double k1x = v, k1v = acc(th);
    const double k2x = v + 0.5 * h * k1v, k2v = acc(th + 0.5 * h * k1x);
    const double k3x = v + 0.5 * h * k2v, k3v = acc(th + 0.5 * h * k2x);
    const double k4x = v + h * k3v, k4v = acc(th + h * k3x);
    th += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  return {th, v};
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
    system = systemOnFeet(model, model_override ? *model_override : contact_model, terrain, massScaledPdGains(model));
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

// The largest ‖q_ne − q_pbd‖∞ over `duration` of ne-pgm and pbd-pgm runs at dt with `options`
// (their method replaced) from (q0, q̇0): how far the two forms' trajectories are apart. NaN if a
// step fails. Assumes no floating-base re-charting (checked).
inline double neToPbdDistance(const QuadrupedOnPlane& robot, IntegratorOptions options, const Eigen::VectorXd& q0,
                              const Eigen::VectorXd& qd0, const PdTargetSource& target, double dt, double duration) {
  std::vector<Eigen::VectorXd> traj[2];
  const Method methods[2] = {Method::NePgm, Method::PbdPgm};
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k < 2; ++k) {
    options.method = methods[k];
    StepWorkspace ws(robot.system, options);
    SimulationState state = initialState(robot.system, options, q0, qd0, dt);
    for (int i = 0; i < steps; ++i) {
      const StepStats st = advance(robot.system, options, target, state, dt, ws);
      EXPECT_TRUE(st.converged) << methodName(methods[k]) << " dt " << dt << " step " << i << ": " << toString(st.status);
      if (!st.converged) return NAN;
      EXPECT_EQ(state.base_chart, Mat3::Identity()) << "the comparison assumes no re-charting";
      traj[k].push_back(state.q);
    }
  }
  double diff = 0;
  for (int i = 0; i < steps; ++i) diff = std::max(diff, (traj[0][i] - traj[1][i]).lpNorm<Eigen::Infinity>());
  return diff;
}

}  // namespace nmdp::test
