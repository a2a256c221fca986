// The project's quadruped standing on flat ground under stable PD, with every method.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_models/coulomb_model.hpp"
#include "multibody/kinematics.hpp"
#include "solver/integrator.hpp"
#include "terrain/plane.hpp"
#include "integrator_fixtures.hpp"
#include "test_support.hpp"

namespace nmdp {
namespace {

TEST(IntegratorQuadruped, StandsWithEveryMethod) {
  for (const char* name : {"ne-pgm", "ne-zopgm", "pbd-pgm", "pbd-zopgm", "ne-mdp"}) {
    SCOPED_TRACE(name);
    test::QuadrupedOnPlane robot;
    IntegratorOptions options;
    options.kinetic_energy = KineticEnergyMeasure::FullBody;  // the paper's K
    options.method = *parseMethod(name);
    const double dt = options.method == Method::NeMdp ? 0.001 : 0.05;
    const Eigen::VectorXd q0 = robot.standing();
    ConstantPdTarget target(q0);
    StepWorkspace ws(robot.system, options);
    SimulationState state = initialState(robot.system, options, q0, Eigen::VectorXd::Zero(q0.size()), dt);
    const int steps = static_cast<int>(std::lround(2.0 / dt));
    int outer = 0, substeps = 0;
    double wall = 0;
    for (int i = 0; i < steps; ++i) {
      const StepStats s = advance(robot.system, options, target, state, dt, ws);
      ASSERT_TRUE(s.converged) << "step " << i << ": " << toString(s.status);
      outer += s.outer_iterations;
      substeps += s.substeps;
      wall += s.wall_time;
    }
    double fz = 0;
    for (const Vec6& f : ws.contact_wrench) fz += f[5];
    std::printf("%s: z %.5f (start %.5f) x %.2e fz %.4f mg %.4f outer/step %.2f substeps/step %.2f wall/step %.1f us\n",
                name, state.q[2], q0[2], state.q[0], fz, robot.model.total_mass * 9.81, double(outer) / steps,
                double(substeps) / steps, 1e6 * wall / steps);
    // Standing still after 2 s: the feet carry the weight and the trunk is at rest. The feet are at
    // least as deep as four full cones need to carry the weight (3.5 mm with the default Coulomb
    // stiffness); any deeper rest is also a maximal-dissipation state, and the settling ends within
    // 1 cm with every method (measured: 2.7 mm first order, 4.2 mm zeroth order).
    const double weight = robot.model.total_mass * robot.model.gravity.norm();
    EXPECT_NEAR(fz, weight, 1e-4 * weight);
    Data data(robot.model);
    data.base_chart = state.base_chart;
    forwardKinematics(robot.model, data, state.q);
    const double full_cone_depth = std::cbrt(weight / 4 / robot.contact_model.parameters().k);
    for (const ContactPoint& c : robot.system.contacts)
      EXPECT_LT(linkPoint(robot.model, data, c.link, c.offset).z() - c.radius, -0.99 * full_cone_depth) << c.name;
    const double sink = q0[2] - state.q[2];
    EXPECT_GT(sink, 0.0);
    EXPECT_LT(sink, 0.01);
    EXPECT_LT(state.qd.lpNorm<Eigen::Infinity>(), 1e-3);
  }
}

}  // namespace
}  // namespace nmdp
