// The default PD gains (control/default_gains.hpp): computed from H at the pose and the load the legs
// carry, the stated natural frequency and damping reproduced, the fallbacks, and the default A1 trot
// staying upright at 1 ms, where the mass-scaled gains let it fall.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "contact_models/coulomb_model.hpp"
#include "contact_models/registry.hpp"
#include "control/default_gains.hpp"
#include "control/gait.hpp"
#include "multibody/crba.hpp"
#include "multibody/feet.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

namespace nmdp {
namespace {

using test::quadrupedUrdf;
using test::sourcePath;

const double kOmega = 2.0 * M_PI * kDefaultGainFrequencyHz;

// ω = √(K_p/I) and ζ = K_d / (2√(K_p I)) of one joint with inertia I.
void expectFrequencyAndDamping(double kp, double kd, double inertia, const std::string& what) {
  EXPECT_NEAR(std::sqrt(kp / inertia), kOmega, 1e-12 * kOmega) << what;
  EXPECT_NEAR(kd / (2.0 * std::sqrt(kp * inertia)), kDefaultGainDampingRatio, 1e-12) << what;
}

TEST(DefaultGains, SingleJointOfKnownInertiaGetsTheStatedFrequencyAndDamping) {
  // tests/data/pendulum.urdf on a fixed base: I = m l² + 1e-6 = 1.000001 kg m² about the hinge; a
  // fixed base carries no load.
  UrdfOptions fixed;
  fixed.base = BaseType::Fixed;
  const Model model = loadUrdf(sourcePath("tests/data/pendulum.urdf"), fixed);
  ASSERT_EQ(model.nq, 1);
  for (double angle : {0.0, 0.7}) {  // the pivot inertia of a point bob does not change with the angle
    const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, angle);
    const GainInertia inertia = gainInertia(model, q);
    EXPECT_NEAR(inertia.subtree[0], 1.000001, 1e-12);
    EXPECT_EQ(inertia.load[0], 0.0);
    EXPECT_EQ(inertia.total[0], inertia.subtree[0]);
    const PdGains g = defaultPdGains(model, q);
    EXPECT_NEAR(g.kp[0], 1.000001 * kOmega * kOmega, 1e-9);
    EXPECT_NEAR(g.kd[0], 2.0 * kDefaultGainDampingRatio * kOmega * 1.000001, 1e-12);
    EXPECT_EQ(g.tau_ff[0], 0.0);
    expectFrequencyAndDamping(g.kp[0], g.kd[0], 1.000001, "pendulum");
  }
  // Any frequency and damping ratio asked for is the one reproduced.
  const PdGains slow = gainsForInertia(model, Eigen::VectorXd::Constant(1, 2.0), 1.5, 0.7);
  EXPECT_NEAR(std::sqrt(slow.kp[0] / 2.0), 2.0 * M_PI * 1.5, 1e-12);
  EXPECT_NEAR(slow.kd[0] / (2.0 * std::sqrt(slow.kp[0] * 2.0)), 0.7, 1e-12);
}

// The quadruped standing: I_j is H_jj from CRBA at the pose plus the load term, which is checked
// here against central differences of the foot positions (m/n)·‖Δp_f/Δθ_j‖².
TEST(DefaultGains, ComputedFromTheMassMatrixAndTheFootJacobianAtThePose) {
  const Model model = loadUrdf(quadrupedUrdf(), {});
  const Eigen::VectorXd q = standingPose(model, identifyQuadrupedLegs(model), {}).q;
  const GainInertia inertia = gainInertia(model, q);
  const PdGains g = defaultPdGains(model, q);
  Data data(model);
  crba(model, data, q);
  const std::vector<FootContact> feet = detectFeet(model);
  ASSERT_EQ(feet.size(), 4u);
  EXPECT_EQ(inertia.feet, 4);
  const double share = model.total_mass / 4.0;
  auto footPositions = [&](const Eigen::VectorXd& x) {
    Data d(model);
    forwardKinematics(model, d, x);
    std::vector<Vec3> out;
    for (const FootContact& f : feet) out.push_back(linkPoint(model, d, model.linkIndex(f.point.name), f.point.offset));
    return out;
  };
  int actuated = 0;
  for (int j = 0; j < model.nq; ++j) {
    const std::string& name = model.dof_names[j];
    if (model.bodies[j].is_base) {
      EXPECT_EQ(g.kp[j], 0.0) << name;
      EXPECT_EQ(g.kd[j], 0.0) << name;
      EXPECT_EQ(g.tau_ff[j], 0.0) << name;
      continue;
    }
    ++actuated;
    EXPECT_EQ(inertia.subtree[j], data.H(j, j)) << name;
    const double step = 1e-6;
    Eigen::VectorXd plus = q, minus = q;
    plus[j] += step;
    minus[j] -= step;
    const std::vector<Vec3> a = footPositions(plus), b = footPositions(minus);
    double load = 0.0;
    for (size_t f = 0; f < feet.size(); ++f) load += share * ((a[f] - b[f]) / (2 * step)).squaredNorm();
    EXPECT_GT(load, 0.0) << name << ": every leg joint carries its foot's load";
    EXPECT_NEAR(inertia.load[j], load, 1e-7 * load) << name;
    EXPECT_NEAR(inertia.total[j], inertia.subtree[j] + inertia.load[j], 1e-15) << name;
    EXPECT_GT(g.kp[j], 0.0) << name;
    EXPECT_GT(g.kd[j], 0.0) << name;
    EXPECT_EQ(g.tau_ff[j], 0.0) << name;
    expectFrequencyAndDamping(g.kp[j], g.kd[j], inertia.total[j], name);
  }
  EXPECT_EQ(actuated, 12);
  EXPECT_NO_THROW(validatePdGains(model, g));

  // The gains depend on the pose (the legs straight at q = 0 reflect the load differently), and a
  // fixed base drops the load term.
  EXPECT_NE(defaultPdGains(model, Eigen::VectorXd::Zero(model.nq)).kp, g.kp);
  UrdfOptions fixed;
  fixed.base = BaseType::Fixed;
  const Model welded = loadUrdf(quadrupedUrdf(), fixed);
  const GainInertia welded_inertia = gainInertia(welded, Eigen::VectorXd::Zero(welded.nq));
  EXPECT_EQ(welded_inertia.load, Eigen::VectorXd::Zero(welded.nq));
  EXPECT_EQ(welded_inertia.total, welded_inertia.subtree);
}

TEST(DefaultGains, RobotWithoutFeetGetsItsOwnInertiaAlone) {
  // The pendulum on a floating base: the trunk is the bob's link (the pivot is a massless,
  // geometry-free link with one child), so the robot has no legs and no feet.
  const Model model = loadUrdf(sourcePath("tests/data/pendulum.urdf"), {});
  ASSERT_TRUE(detectFeet(model).empty());
  const int hinge = model.dofIndex("hinge");
  ASSERT_GE(hinge, 0);
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq);
  const GainInertia inertia = gainInertia(model, q);
  EXPECT_EQ(inertia.feet, 0);
  EXPECT_EQ(inertia.load[hinge], 0.0);
  EXPECT_NEAR(inertia.total[hinge], 1.000001, 1e-12);
  PdGains g;
  ASSERT_NO_THROW(g = defaultPdGains(model, q));
  expectFrequencyAndDamping(g.kp[hinge], g.kd[hinge], 1.000001, "hinge");
  EXPECT_NO_THROW(validatePdGains(model, g));

  // A robot of base coordinates only (the box) gets zero gains and does not fail.
  const Model box = loadUrdf(sourcePath("tests/data/box.urdf"), {});
  const PdGains none = defaultPdGains(box, Eigen::VectorXd::Zero(box.nq));
  EXPECT_EQ(none.kp, Eigen::VectorXd::Zero(box.nq));
  EXPECT_EQ(none.kd, Eigen::VectorXd::Zero(box.nq));
}

TEST(DefaultGains, BadPoseIsRejected) {
  const Model model = loadUrdf(quadrupedUrdf(), {});
  EXPECT_THROW(gainInertia(model, Eigen::VectorXd::Zero(model.nq - 1)), std::invalid_argument);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq);
  q[model.nq - 1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(defaultPdGains(model, q), std::invalid_argument);
}

// A1 with nothing but its URDF (floating base, auto feet, Coulomb, flat ground, the built-in trot,
// every gain and the K measure by default) trots at dt = 1 ms for 3 s: every step converges, the
// torso stays within 0.5–1.5× its start height with |roll|, |pitch| < 1 rad, and it walks forward.
// With the mass-scaled gains (kd = 0.137) the same run tips over at about 1.7 s.
TEST(DefaultGains, A1TrotsUprightAtOneMillisecond) {
  NMDP_REQUIRE_SHARED("robots/a1/urdf/a1.urdf");
  const std::string scene_path = sourcePath("tests/data/a1_default_trot.json");  // named in messages only
  const nlohmann::json scene = {{"robot", {{"urdf", test::sharedPath("robots/a1/urdf/a1.urdf")}, {"base", "floating"}}},
                                {"contacts", {{"points", "auto"}, {"model", {{"type", "coulomb"}}}}},
                                {"terrain", {{"type", "plane"}}},
                                {"integrator", {{"dt", 0.001}}},
                                {"controller", {{"gait", {{"type", "trot"}}}}},
                                {"duration", 3.0}};
  ContactModelRegistry models;  // Coulomb only: this test links no libtorch
  models.add("coulomb", kCoulombParameters, makeCoulombModel);
  Simulation sim = buildSimulation(parseScene(scene, scene_path), models);
  EXPECT_EQ(sim.system().gains.kd, defaultPdGains(sim.model(), sim.initialConfiguration()).kd);
  EXPECT_EQ(sim.options().kinetic_energy, KineticEnergyMeasure::FullBodyPd);
  ASSERT_EQ(sim.dt(), 0.001);

  Vec3 p0, p, rpy;
  sim.basePose(p0, rpy);
  const long steps = sim.scheduledSteps();
  for (long i = 1; i <= steps; ++i) {
    const StepStats stats = sim.step();
    ASSERT_TRUE(stats.converged) << "step " << i << ": " << toString(stats.status);
    sim.basePose(p, rpy);
    ASSERT_GT(p.z(), 0.5 * p0.z()) << "t = " << sim.time();
    ASSERT_LT(p.z(), 1.5 * p0.z()) << "t = " << sim.time();
    ASSERT_LT(std::abs(rpy.x()), 1.0) << "roll at t = " << sim.time();
    ASSERT_LT(std::abs(rpy.y()), 1.0) << "pitch at t = " << sim.time();
  }
  EXPECT_GT(p.x() - p0.x(), 0.5) << "the trot walks forward";
}

}  // namespace
}  // namespace nmdp
