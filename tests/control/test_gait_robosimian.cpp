// Gait targets on RoboSimian in the paper's configuration (../shared): planar legs, standing from
// a bent nominal pose, IK in the legs' plane, and the trot and the jump from that pose.
#include <fstream>
#include <nlohmann/json.hpp>

#include "control/gait.hpp"
#include "control/leg_ik.hpp"
#include "foot_displacements.hpp"
#include "multibody/kinematics.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

const char* kRoboSimian = "robots/robosimian/robosimian_caesar_new_all_active.urdf";

class RoboSimianPaperTest : public ::testing::Test {
 protected:
  void SetUp() override {
    NMDP_REQUIRE_SHARED(kRoboSimian);
    UrdfOptions options;
    options.base = BaseType::Planar;
    for (int limb = 1; limb <= 4; ++limb)
      for (int j : {0, 1, 3, 5, 7}) options.locked_joints["limb" + std::to_string(limb) + "_joint" + std::to_string(j)] = 0.0;
    model = loadUrdf(sharedPath(kRoboSimian), options);
    std::ifstream scene(sourcePath("models/scenes/robosimian_walk_planar.json"));
    const nlohmann::json joints = nlohmann::json::parse(scene).at("robot").at("initial").at("joints");
    nominal = Eigen::VectorXd::Zero(model.nq);
    for (auto it = joints.begin(); it != joints.end(); ++it) nominal[model.dofIndex(it.key())] = it.value().get<double>();
    legs = identifyQuadrupedLegs(model, nominal);
    stand.nominal_q = nominal;
  }
  Model model;
  Eigen::VectorXd nominal;
  QuadrupedLegs legs;
  StandParameters stand;
};

TEST_F(RoboSimianPaperTest, LegsArePlanarAndStandOnlyFromTheBentPose) {
  ASSERT_EQ(model.nq, 15);
  LegIkSolver ik(model, readJointLimits(model));
  for (const Leg& leg : legs.legs) {
    ASSERT_EQ(leg.joints.size(), 3u) << leg.foot.name;
    const Vec3 normal = ik.planeNormal(leg, nominal);
    EXPECT_NEAR(normal.norm(), 1.0, 1e-12) << leg.foot.name;
    EXPECT_GT(std::abs(normal.y()), 0.99) << leg.foot.name << ": the limbs move in the sagittal plane";
    // A planar 3R Jacobian has rank 2: conditioning is measured in its plane, so a bent limb is
    // regular and the level, straight limb of q = 0 singular.
    EXPECT_GT(ik.conditioning(leg, nominal), 1e-2) << leg.foot.name;
    EXPECT_LT(ik.conditioning(leg, Eigen::VectorXd::Zero(model.nq)), 1e-6) << leg.foot.name;
  }
  try {
    standingPose(model, identifyQuadrupedLegs(model), {});
    ADD_FAILURE() << "RoboSimian stood from q = 0, where its limbs stretch out level";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot reach"), std::string::npos) << e.what();
  }

  // From the bent pose: the feet keep their place in the limbs' planes and all stand at the mean
  // height of the nominal feet, which is the standing height.
  const StandingPose pose = standingPose(model, legs, stand);
  double mean_height = 0;
  for (const Leg& leg : legs.legs) mean_height += 0.25 * (leg.foot.radius - ik.footInTrunk(leg, nominal).z());
  EXPECT_NEAR(pose.height, mean_height, 1e-12);
  EXPECT_GT(pose.height, 0.5) << "standing like a table, the trunk well above the ground";
  for (int id = 0; id < 4; ++id) {
    const Leg& leg = legs.legs[id];
    const Vec3 foot = ik.footInTrunk(leg, pose.q), nominal_foot = ik.footInTrunk(leg, nominal);
    const Vec3 normal = ik.planeNormal(leg, pose.q);
    EXPECT_NEAR(foot.z() - leg.foot.radius, -pose.height, 1e-9) << leg.foot.name;
    // The nominal foot lowered to the ground, reached in the plane the limb moves in.
    const Vec3 aimed(nominal_foot.x(), nominal_foot.y(), leg.foot.radius - pose.height);
    EXPECT_LT(((foot - aimed) - normal * normal.dot(foot - aimed)).norm(), 1e-9) << leg.foot.name;
    EXPECT_EQ(pose.feet[id], foot) << leg.foot.name;
    EXPECT_GT(ik.conditioning(leg, pose.q), 1e-2) << leg.foot.name;
  }
  EXPECT_LT((pose.q.tail(12) - nominal.tail(12)).cwiseAbs().maxCoeff(), 1e-3) << "the nominal feet are level to µm";
}

TEST_F(RoboSimianPaperTest, IkReachesInPlaneTargetsAndIgnoresTheOutOfPlaneComponent) {
  const JointLimits limits = readJointLimits(model);
  LegIkSolver ik(model, limits);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> angle(-0.3, 0.3);
  for (int trial = 0; trial < 10; ++trial) {
    for (const Leg& leg : legs.legs) {
      Eigen::VectorXd reference = nominal;
      for (int j : leg.joints) reference[j] += angle(rng);
      const Vec3 target = ik.footInTrunk(leg, reference);
      const Vec3 normal = ik.planeNormal(leg, nominal);
      Eigen::VectorXd q = nominal;
      const LegIkResult result = ik.solve(leg, target, q);
      EXPECT_TRUE(result.converged) << leg.foot.name << " trial " << trial << ": " << result.error;
      EXPECT_LT((ik.footInTrunk(leg, q) - target).norm(), 1e-9) << leg.foot.name;
      // 5 cm off the plane: unreachable along the normal, reached in the plane.
      Eigen::VectorXd off = nominal;
      const LegIkResult off_result = ik.solve(leg, target + 0.05 * normal, off);
      EXPECT_TRUE(off_result.converged) << leg.foot.name << ": " << off_result.error;
      EXPECT_LT((ik.footInTrunk(leg, off) - target).norm(), 1e-9) << leg.foot.name;
    }
  }
}

TEST_F(RoboSimianPaperTest, TrotAndJumpFromTheBentPose) {
  const StandingPose pose = standingPose(model, legs, stand);
  LegIkSolver ik(model, readJointLimits(model));
  TrotParameters trot_in;
  trot_in.period = 1.0;
  const TrotParameters trot = withRobotDefaults(trot_in, pose);
  const KeyframePdTarget walk = makeTrotTarget(model, trot_in, stand);
  // In each limb's plane the foot follows the designed path exactly at the keyframes.
  for (double t : walk.spline().knotTimes()) {
    const std::array<Vec3, 4> d = footDisplacements(model, legs, pose, ik, walk, t);
    for (int id = 0; id < 4; ++id) {
      const Vec3 miss = d[id] - trotFootDisplacement(trot, trotLegPhase(trot, static_cast<LegId>(id), t));
      const Vec3 normal = ik.planeNormal(legs.legs[id], pose.q);
      EXPECT_LT((miss - normal * normal.dot(miss)).norm(), 1e-9) << legIdName(static_cast<LegId>(id)) << " t = " << t;
    }
  }

  // The default push-off comes from the straight-leg height at q = 0, meaningless here: an
  // actionable error rather than a jump that does not leave the ground.
  try {
    makeJumpTarget(model, {}, stand);
    ADD_FAILURE() << "the default jump of a robot whose legs do not hang at q = 0 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("give push_off_height"), std::string::npos) << e.what();
  }
  JumpParameters jump;
  jump.crouch_depth = 0.15;
  jump.push_off_height = pose.height + 0.15;
  const KeyframePdTarget leap = makeJumpTarget(model, jump, stand);
  const double crouch_end = jump.crouch_share * (jump.period - jump.pause);
  const std::array<Vec3, 4> crouched = footDisplacements(model, legs, pose, ik, leap, crouch_end);
  for (int id = 0; id < 4; ++id) {
    const Vec3 normal = ik.planeNormal(legs.legs[id], pose.q);
    const Vec3 miss = crouched[id] - Vec3(0, 0, 0.15);
    EXPECT_LT((miss - normal * normal.dot(miss)).norm(), 1e-9) << legIdName(static_cast<LegId>(id));
  }
}

}  // namespace
}  // namespace nmdp::test
