// Simulation::setFeedforward (sim/simulation.hpp): the PD law's τ_ff from the next step on. Known
// answers on the quadruped with its base welded and no contacts, K_p = K_d = 0: the gravity
// torque g(q₀) holds it still, g(q₀) + δτ starts it with the acceleration H⁻¹δτ; the scene's own
// controller.tau_ff is what setFeedforward replaces; bad vectors are refused by name.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <limits>

#include "multibody/crba.hpp"
#include "multibody/rnea.hpp"
#include "scene_simulation.hpp"

namespace nmdp {
namespace {

using test::repositorySimulation;

const std::vector<std::string> kHanging = {"robot.base=fixed", "contacts.points=[]",
                                           "controller.kp=0", "controller.kd=0"};

std::vector<std::string> hangingWith(std::vector<std::string> more) {
  std::vector<std::string> all = kHanging;
  all.insert(all.end(), more.begin(), more.end());
  return all;
}

// g(q): the joint torques that hold the robot still at q (RNEA at zero velocity and acceleration).
Eigen::VectorXd gravityTorque(const Simulation& sim, const Eigen::VectorXd& q) {
  Data data(sim.model());
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
  rnea(sim.model(), data, q, zero, zero);
  return data.tau;
}

TEST(Feedforward, TheGravityTorqueHoldsAHangingRobotStill) {
  Simulation held = repositorySimulation("quadruped_stand_flat.json", kHanging);
  Simulation falling = repositorySimulation("quadruped_stand_flat.json", kHanging);
  ASSERT_EQ(held.model().nq, 12) << "the legs' joints only: the base is welded";
  const Eigen::VectorXd q0 = held.state().q;
  held.setFeedforward(gravityTorque(held, q0));
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(held.step().converged) << "step " << i;
    ASSERT_TRUE(falling.step().converged) << "step " << i;
  }
  // Held: G(q₀) = g(q₀) − τ_ff vanishes at rest to round-off, so the solution is q₀ to round-off.
  EXPECT_LE((held.state().q - q0).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LE(held.state().qd.cwiseAbs().maxCoeff(), 1e-8);
  // Without it the legs swing down under gravity by far more in 0.5 s.
  EXPECT_GE((falling.state().q - q0).cwiseAbs().maxCoeff(), 0.05);
}

TEST(Feedforward, AnExtraTorqueGivesTheAccelerationInverseMassTimesTorque) {
  Simulation sim = repositorySimulation("quadruped_stand_flat.json", hangingWith({"integrator.dt=0.0001"}));
  const Eigen::VectorXd q0 = sim.state().q;
  const int n = sim.model().nq;
  Eigen::VectorXd extra(n);
  for (int j = 0; j < n; ++j) extra[j] = 0.5 * ((j % 3) - 1.0) + 0.1 * j;  // N·m, mixed signs
  sim.setFeedforward(gravityTorque(sim, q0) + extra);
  ASSERT_TRUE(sim.step().converged);
  Data data(sim.model());
  crba(sim.model(), data, q0);
  const Eigen::VectorXd expected = sim.dt() * data.H.llt().solve(extra);  // q̇₁ = h H⁻¹δτ from rest
  // Backward Euler evaluates H, g at q₁ = q₀ + h q̇₁: a relative change of O(h² ω²) ≈ 1e-6.
  EXPECT_LE((sim.state().qd - expected).cwiseAbs().maxCoeff(), 1e-5 * expected.cwiseAbs().maxCoeff())
      << "q̇₁ = " << sim.state().qd.transpose() << "\nh H⁻¹δτ = " << expected.transpose();
}

// setFeedforward replaces controller.tau_ff: a scene with tau_ff and a scene without it given the
// same vector step alike, bit for bit, and a zero vector removes the scene's.
TEST(Feedforward, ItReplacesTheScenesFeedforward) {
  Simulation plain = repositorySimulation("quadruped_trot_flat.json");
  const std::string joint = plain.model().bodies[8].joint_name;
  const std::vector<std::string> with_ff = {"controller.tau_ff={\"" + joint + "\": 3.5}"};
  Simulation scene_ff = repositorySimulation("quadruped_trot_flat.json", with_ff);
  ASSERT_EQ(scene_ff.system().gains.tau_ff[8], 3.5);
  Simulation set_ff = repositorySimulation("quadruped_trot_flat.json");
  set_ff.setFeedforward(scene_ff.system().gains.tau_ff);
  Simulation removed = repositorySimulation("quadruped_trot_flat.json", with_ff);
  removed.setFeedforward(Eigen::VectorXd::Zero(plain.model().nq));
  for (int i = 0; i < 6; ++i) {
    for (Simulation* s : {&plain, &scene_ff, &set_ff, &removed}) ASSERT_TRUE(s->step().converged) << "step " << i;
    EXPECT_EQ(set_ff.state().q, scene_ff.state().q) << "step " << i;
    EXPECT_EQ(removed.state().q, plain.state().q) << "step " << i;
  }
  EXPECT_NE(scene_ff.state().q, plain.state().q) << "3.5 N·m on a hip moves the robot";
}

TEST(Feedforward, BadVectorsAreRefusedByName) {
  Simulation sim = repositorySimulation("quadruped_trot_flat.json");
  const Model& model = sim.model();
  const int n = model.nq;
  const Eigen::VectorXd before = sim.system().gains.tau_ff;
  const auto message = [&](const Eigen::VectorXd& tau) {
    try {
      sim.setFeedforward(tau);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(Eigen::VectorXd::Zero(n - 1)),
            "Simulation::setFeedforward: tau has " + std::to_string(n - 1) + " entries, expected nq = " + std::to_string(n));
  Eigen::VectorXd nan = Eigen::VectorXd::Zero(n);
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message(nan), "Simulation::setFeedforward: tau[7] (" + model.bodies[7].joint_name + ") is not finite");
  Eigen::VectorXd on_base = Eigen::VectorXd::Zero(n);
  on_base[2] = 1.0;
  ASSERT_TRUE(model.bodies[2].is_base);
  EXPECT_EQ(message(on_base), "Simulation::setFeedforward: tau[2] (" + model.bodies[2].joint_name +
                                  ") is nonzero on an unactuated base coordinate");
  EXPECT_EQ(sim.system().gains.tau_ff, before) << "a refused vector changes nothing";
}

}  // namespace
}  // namespace nmdp
