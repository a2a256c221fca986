// Gait targets (DESIGN.md 5): leg IK on the project's quadruped, A1 and Solo-12, and the stand /
// trot / jump generators built on it, with the ground-speed swing; RoboSimian's planar legs:
// test_gait_robosimian.cpp; the keyframe splines: test_hermite_spline.cpp.
#include <algorithm>
#include <cmath>

#include "control/gait.hpp"
#include "control/hermite_spline.hpp"
#include "control/leg_ik.hpp"
#include "foot_displacements.hpp"
#include "multibody/kinematics.hpp"
#include "spline_derivative.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp::test {
namespace {

// --- legs and IK ------------------------------------------------------------------------------

struct QuadrupedCase {
  std::string name;
  std::string path;
  BaseType base;
  bool shared;
};
void PrintTo(const QuadrupedCase& c, std::ostream* os) { *os << c.name; }

class QuadrupedTest : public ::testing::TestWithParam<QuadrupedCase> {
 protected:
  void SetUp() override {
    if (GetParam().shared && !std::filesystem::exists(GetParam().path))
      GTEST_SKIP() << "../shared is absent (" << GetParam().path << "): skipping";
    UrdfOptions options;
    options.base = GetParam().base;
    model = loadUrdf(GetParam().path, options);
    legs = identifyQuadrupedLegs(model);
    pose = standingPose(model, legs, {});
  }
  Model model;
  QuadrupedLegs legs;
  StandingPose pose;
};

const std::vector<QuadrupedCase> kQuadrupeds{
    {"quadruped_floating", quadrupedUrdf(), BaseType::Floating, false},
    {"quadruped_fixed", quadrupedUrdf(), BaseType::Fixed, false},
    {"a1", sharedPath("robots/a1/urdf/a1.urdf"), BaseType::Floating, true},
    {"solo12", sharedPath("robots/solo12/urdf/solo12.urdf"), BaseType::Floating, true},
};

TEST_P(QuadrupedTest, LegsAreTheChainsFromTrunkToFeet) {
  const char* prefixes[4][2] = {{"FL", "FL"}, {"FR", "FR"}, {"RL", "HL"}, {"RR", "HR"}};
  for (int id = 0; id < 4; ++id) {
    const Leg& leg = legs.legs[id];
    const std::string& foot = leg.foot.name;
    EXPECT_TRUE(foot.rfind(prefixes[id][0], 0) == 0 || foot.rfind(prefixes[id][1], 0) == 0)
        << legIdName(static_cast<LegId>(id)) << " got " << foot;
    ASSERT_EQ(leg.joints.size(), 3u) << foot;
    LegIkSolver ik(model);
    EXPECT_TRUE(ik.planeNormal(leg, pose.q).isZero(0.0)) << foot << ": its foot moves in 3-D";
    for (int j : leg.joints) {
      EXPECT_FALSE(model.bodies[j].is_base);
      EXPECT_TRUE(model.isAncestor(j, leg.foot_body));
      EXPECT_EQ(model.bodies[j].joint_name.substr(0, 2), foot.substr(0, 2));
    }
  }
}

TEST_P(QuadrupedTest, IkReachesRandomReachableTargets) {
  const JointLimits limits = readJointLimits(model);
  LegIkSolver ik(model, limits);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> angle(-0.3, 0.3);
  int solved = 0;
  for (int trial = 0; trial < 20; ++trial) {
    // Any trunk pose: targets are relative to the trunk.
    Eigen::VectorXd base_pose = pose.q;
    for (int i = 0; i < model.nq; ++i)
      if (model.bodies[i].is_base) base_pose[i] += angle(rng);
    for (int id = 0; id < 4; ++id) {
      const Leg& leg = legs.legs[id];
      Eigen::VectorXd reference = base_pose;
      for (int j : leg.joints) reference[j] = std::clamp(reference[j] + angle(rng), limits.lower[j], limits.upper[j]);
      const Vec3 target = ik.footInTrunk(leg, reference);
      Eigen::VectorXd q = base_pose;
      const LegIkResult result = ik.solve(leg, target, q);
      EXPECT_TRUE(result.converged) << legIdName(static_cast<LegId>(id)) << " trial " << trial << ": " << result.error;
      EXPECT_LT((ik.footInTrunk(leg, q) - target).norm(), 1e-9);
      for (int i = 0; i < model.nq; ++i)
        if (std::find(leg.joints.begin(), leg.joints.end(), i) == leg.joints.end()) {
        EXPECT_EQ(q[i], base_pose[i]);
      }
      for (int j : leg.joints) {
        EXPECT_GE(q[j], limits.lower[j]);
        EXPECT_LE(q[j], limits.upper[j]);
      }
      solved += result.converged;
    }
  }
  EXPECT_EQ(solved, 80);
}

TEST_P(QuadrupedTest, StandingPosePutsFeetUnderTheHipsAtTheHeight) {
  LegIkSolver ik(model, readJointLimits(model));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nq);
  EXPECT_NEAR(pose.height, 0.8 * pose.straight_height, 1e-12);
  EXPECT_GT(pose.leg_length, 0.1);
  for (int id = 0; id < 4; ++id) {
    const Leg& leg = legs.legs[id];
    const Vec3 straight = ik.footInTrunk(leg, zero), foot = ik.footInTrunk(leg, pose.q);
    EXPECT_NEAR(foot.x(), straight.x(), 1e-9);
    EXPECT_NEAR(foot.y(), straight.y(), 1e-9);
    EXPECT_NEAR(foot.z() - leg.foot.radius, -pose.height, 1e-9);
    EXPECT_GT(ik.conditioning(leg, pose.q), 1e-2) << "knee left straight";
  }
  const KeyframePdTarget stand = makeStandTarget(model);
  PdTarget out{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
  stand.evaluate(3.7, out);
  EXPECT_LT((out.position - pose.q).norm(), 1e-12);
  EXPECT_TRUE(out.velocity.isZero(0.0));
  // A given height and a given nominal pose.
  StandParameters lower;
  lower.height = 0.7 * pose.straight_height;
  const StandingPose low = standingPose(model, legs, lower);
  for (int id = 0; id < 4; ++id)
    EXPECT_NEAR(ik.footInTrunk(legs.legs[id], low.q).z() - legs.legs[id].foot.radius, -*lower.height, 1e-9);
  StandParameters nominal;
  nominal.nominal_q = pose.q;
  const StandingPose same = standingPose(model, legs, nominal);
  EXPECT_NEAR(same.height, pose.height, 1e-9);
  EXPECT_LT((same.q - pose.q).norm(), 1e-7);
}

TEST_P(QuadrupedTest, TrotFeetTraceTheDesignedPath) {
  const TrotParameters trot = withRobotDefaults(TrotParameters{}, pose);
  EXPECT_NEAR(*trot.stride_length, 0.25 * pose.leg_length, 1e-15);
  EXPECT_NEAR(*trot.step_height, 0.15 * pose.leg_length, 1e-15);
  const KeyframePdTarget target = makeTrotTarget(model);
  const std::vector<double>& knots = target.spline().knotTimes();
  ASSERT_EQ(knots.size(), 17u);  // 16 keyframes + the closing knot
  LegIkSolver ik(model, readJointLimits(model));

  std::array<double, 4> x_min, x_max, z_max;
  x_min.fill(1e9), x_max.fill(-1e9), z_max.fill(-1e9);
  for (size_t k = 0; k + 1 < knots.size(); ++k) {
    const double t = knots[k];
    EXPECT_NEAR(t, trot.period * k / 16, 1e-15);
    const auto d = footDisplacements(model, legs, pose, ik, target, t);
    for (int id = 0; id < 4; ++id) {
      const Vec3 designed = trotFootDisplacement(trot, trotLegPhase(trot, static_cast<LegId>(id), t));
      EXPECT_LT((d[id] - designed).norm(), 1e-9) << legIdName(static_cast<LegId>(id)) << " t = " << t;
      x_min[id] = std::min(x_min[id], d[id].x());
      x_max[id] = std::max(x_max[id], d[id].x());
      z_max[id] = std::max(z_max[id], d[id].z());
      EXPECT_GE(d[id].z(), -1e-9);
    }
    // Diagonal pairs in phase, the two pairs half a period apart.
    EXPECT_LT((d[kFrontLeft] - d[kHindRight]).norm(), 1e-9);
    EXPECT_LT((d[kFrontRight] - d[kHindLeft]).norm(), 1e-9);
    const auto later = footDisplacements(model, legs, pose, ik, target, t + trot.period / 2);
    EXPECT_LT((later[kFrontRight] - d[kFrontLeft]).norm(), 1e-9);
  }
  for (int id = 0; id < 4; ++id) {
    EXPECT_NEAR(x_max[id] - x_min[id], *trot.stride_length, 1e-6) << legIdName(static_cast<LegId>(id));
    EXPECT_NEAR(z_max[id], *trot.step_height, 1e-6) << legIdName(static_cast<LegId>(id));
  }
  // Mid-swing of the front-left leg is a quarter period in.
  EXPECT_NEAR(footDisplacements(model, legs, pose, ik, target, trot.period / 4)[kFrontLeft].z(), *trot.step_height,
              1e-6);
  // The targets are periodic and their velocity is their time derivative.
  PdTarget a{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)}, b = a;
  for (double t : {0.01, 0.13, 0.3125, 0.49}) {
    target.evaluate(t, a);
    target.evaluate(t + 3 * trot.period, b);
    EXPECT_LT((a.position - b.position).norm(), 1e-12);
  }
  expectVelocityIsTimeDerivative(target.spline(), probeTimes(knots));
}

TEST_P(QuadrupedTest, TrotWithOtherDutyFactorAndSizes) {
  TrotParameters trot;
  trot.duty_factor = 0.6;
  trot.stride_length = 0.1 * pose.leg_length;
  trot.step_height = 0.1 * pose.leg_length;
  trot.period = 0.8;
  const KeyframePdTarget target = makeTrotTarget(model, trot);
  LegIkSolver ik(model, readJointLimits(model));
  for (double t : target.spline().knotTimes()) {
    const auto d = footDisplacements(model, legs, pose, ik, target, t);
    for (int id = 0; id < 4; ++id)
      EXPECT_LT((d[id] - trotFootDisplacement(trot, trotLegPhase(trot, static_cast<LegId>(id), t))).norm(), 1e-9);
  }
  // Mid-swing (phase 0.2 of FL's cycle) and lift-off/touch-down are keyframes.
  EXPECT_NEAR(footDisplacements(model, legs, pose, ik, target, 0.2 * trot.period)[kFrontLeft].z(), *trot.step_height,
              1e-9);
}

TEST_P(QuadrupedTest, JumpCrouchesToTheDepth) {
  const JumpParameters jump = withRobotDefaults(JumpParameters{}, pose);
  const KeyframePdTarget target = makeJumpTarget(model);
  LegIkSolver ik(model, readJointLimits(model));
  const double moving = jump.period - jump.pause;
  const double crouch_end = jump.crouch_share * moving, extension_end = crouch_end + jump.extension_share * moving;
  // Feet rise towards the trunk by the crouch depth (the trunk lowers), and stay under the hips.
  const auto crouched = footDisplacements(model, legs, pose, ik, target, crouch_end);
  const auto extended = footDisplacements(model, legs, pose, ik, target, extension_end);
  for (int id = 0; id < 4; ++id) {
    EXPECT_LT((crouched[id] - Vec3(0, 0, *jump.crouch_depth)).norm(), 1e-9) << legIdName(static_cast<LegId>(id));
    EXPECT_NEAR(extended[id].x(), 0, 1e-6);
    EXPECT_LT(extended[id].z(), 0) << "push-off extends the legs";
  }
  // Standing at the start and through the pause, with zero velocity.
  PdTarget out{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
  for (double t : {0.0, moving, moving + jump.pause / 2, jump.period, 5 * jump.period}) {
    target.evaluate(t, out);
    EXPECT_LT((out.position - pose.q).norm(), 1e-12) << t;
    EXPECT_LT(out.velocity.norm(), 1e-12) << t;
  }
  expectVelocityIsTimeDerivative(target.spline(), probeTimes(target.spline().knotTimes()));
}

TEST_P(QuadrupedTest, GaitTargetsEvaluateWithoutAllocating) {
  for (GaitType type : {GaitType::Stand, GaitType::Trot, GaitType::Jump}) {
    GaitParameters gait;
    gait.type = type;
    gait.trot.start_ramp = 0.3;  // t runs through the ramp and past its end
    const std::unique_ptr<PdTargetSource> source = makeGaitTarget(model, gait);
    PdTarget out{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
    double t = -0.2;
    const AllocationCount count = allocationsOf([&] {
      for (int i = 0; i < 50; ++i, t += 0.0173) source->evaluate(t, out);
    });
    EXPECT_EQ(count.total(), 0) << gaitTypeName(type) << ": " << count.news << " operator new, " << count.mallocs
                                << " malloc";
  }
}

// With a start ramp the trot starts in the standing pose the robot starts in, at rest, instead of
// half a stride away from it, and is the plain trot from the ramp's end on. In between the feet
// move by about r(t) times the trot's displacement (the blend is in joint space).
TEST_P(QuadrupedTest, TrotStartRampBlendsInFromTheStandingPose) {
  GaitParameters gait;
  gait.type = GaitType::Trot;
  gait.trot.start_ramp = gait.trot.period;
  const std::unique_ptr<PdTargetSource> ramped = makeGaitTarget(model, gait);
  const KeyframePdTarget plain = makeTrotTarget(model);
  PdTarget a{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)}, b = a;
  ramped->evaluate(0.0, a);
  EXPECT_LT((a.position - pose.q).norm(), 1e-12);
  EXPECT_LT(a.velocity.norm(), 1e-12);
  plain.evaluate(0.0, b);
  EXPECT_GT((b.position - pose.q).norm(), 0.05) << "without the ramp the trot starts away from standing";
  for (double t : {gait.trot.period, 1.3 * gait.trot.period, 4.0}) {
    ramped->evaluate(t, a);
    plain.evaluate(t, b);
    EXPECT_EQ(a.position, b.position) << t;
    EXPECT_EQ(a.velocity, b.velocity) << t;
  }
  const TrotParameters trot = withRobotDefaults(TrotParameters{}, pose);
  LegIkSolver ik(model, readJointLimits(model));
  double worst = 0;
  for (int i = 1; i < 20; ++i) {
    const double t = gait.trot.start_ramp * i / 20;
    const double r = (1 - std::cos(M_PI * t / gait.trot.start_ramp)) / 2;
    const auto d = footDisplacements(model, legs, pose, ik, *ramped, t);
    for (int id = 0; id < 4; ++id) {
      const Vec3 designed = trotFootDisplacement(trot, trotLegPhase(trot, static_cast<LegId>(id), t));
      worst = std::max(worst, (d[id] - r * designed).norm());
    }
  }
  // Nominally at most 0.33 % of the leg length (1.1-1.5 mm) on all four robots.
  EXPECT_LT(worst, 0.01 * pose.leg_length) << worst / pose.leg_length;
  gait.trot.start_ramp = -0.1;
  EXPECT_THROW(makeGaitTarget(model, gait), std::invalid_argument);
}

TEST_P(QuadrupedTest, UnreachableSizesAreRejected) {
  TrotParameters trot;
  trot.step_height = 2 * pose.straight_height;
  try {
    makeTrotTarget(model, trot);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot reach"), std::string::npos) << e.what();
  }
  JumpParameters jump;
  jump.crouch_depth = 2 * pose.height;
  EXPECT_THROW(makeJumpTarget(model, jump), std::invalid_argument);
  trot = {};
  trot.duty_factor = 1.0;
  EXPECT_THROW(makeTrotTarget(model, trot), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Robots, QuadrupedTest, ::testing::ValuesIn(kQuadrupeds),
                         [](const auto& info) { return info.param.name; });

// --- RoboSimian in the paper's configuration ----------------------------------------------------
// Planar base, joints 2, 4, 6 of each limb active: every limb is a planar 3R chain (parallel
// axes, ~ world y), stretched out level at q = 0, so it stands only from a bent nominal pose. The
// pose is the one of models/scenes/robosimian_walk_planar.json (robot.initial.joints).

// The ground-speed swing: the foot leaves and meets the ground at the stance's speed (dx/du =
// −stride/duty, at rest on the ground when the trunk keeps the plan's pace), descends its last
// ground_speed_share at that speed, lifts exactly as the cosine swing does, and joins the stance
// continuously; the cosine swing instead stops in the trunk frame at both ends.
TEST(Gait, GroundSpeedSwingMeetsTheGroundAtTheStanceSpeed) {
  for (double duty : {0.5, 0.6}) {
    for (double share : {0.0, 0.15, 0.3}) {
      TrotParameters trot;
      trot.stride_length = 0.2;
      trot.step_height = 0.1;
      trot.duty_factor = duty;
      trot.swing_profile = SwingProfile::GroundSpeed;
      trot.ground_speed_share = share;
      TrotParameters cosine = trot;
      cosine.swing_profile = SwingProfile::Cosine;
      const double swing = 1 - duty, stance_slope = -0.2 / duty, du = 1e-6;
      auto slope = [&](const TrotParameters& t, double u) {
        return (trotFootDisplacement(t, u + du).x() - trotFootDisplacement(t, u - du).x()) / (2 * du);
      };
      const std::string where = "duty " + std::to_string(duty) + ", share " + std::to_string(share);
      // Continuous with the stance at lift-off (u = 0, the stance's end wraps to 1) and touch-down.
      EXPECT_NEAR(trotFootDisplacement(trot, 0.0).x(), -0.1, 1e-12) << where;
      EXPECT_NEAR(trotFootDisplacement(trot, swing - 1e-12).x(), 0.1, 1e-9) << where;
      EXPECT_NEAR(trotFootDisplacement(trot, swing).x(), 0.1, 1e-12) << where;
      EXPECT_NEAR(slope(trot, 2 * du), stance_slope, 1e-4) << where;
      EXPECT_NEAR(slope(trot, swing - 2 * du), stance_slope, 1e-4) << where;
      EXPECT_NEAR(slope(trot, 0.5 * (swing + 1)), stance_slope, 1e-6) << where;  // the stance itself
      EXPECT_NEAR(slope(cosine, 2 * du), 0.0, 1e-4) << where;
      EXPECT_NEAR(slope(cosine, swing - 2 * du), 0.0, 1e-4) << where;
      // The last share of the swing moves at the stance speed throughout.
      if (share > 0) {
        for (double f : {0.2, 0.5, 0.8})
          EXPECT_NEAR(slope(trot, swing * (1 - share * f)), stance_slope, 1e-6) << where << " f " << f;
      }
      // The height is the cosine swing's, and the foot goes forward (beyond +stride/2, to come back).
      double x_max = -1;
      for (int i = 0; i <= 200; ++i) {
        const double u = swing * i / 200;
        EXPECT_NEAR(trotFootDisplacement(trot, u).z(), trotFootDisplacement(cosine, u).z(), 1e-15) << where;
        x_max = std::max(x_max, trotFootDisplacement(trot, u).x());
      }
      // It arrives at the end of its forward travel moving backward, so it has been beyond it.
      EXPECT_GT(x_max, 0.1 + 0.2 * swing / duty * share + 1e-4) << where;
    }
  }
}

TEST_P(QuadrupedTest, GroundSpeedTrotKeyframesFollowTheDesign) {
  TrotParameters trot;
  trot.swing_profile = SwingProfile::GroundSpeed;
  trot.ground_speed_share = 0.2;
  const KeyframePdTarget target = makeTrotTarget(model, trot);
  const TrotParameters resolved = withRobotDefaults(trot, pose);
  LegIkSolver ik(model, readJointLimits(model));
  const std::vector<double>& knots = target.spline().knotTimes();
  // The end of the forward travel (phase 0.5 · 0.8 = 0.4 of FL's cycle) is a keyframe.
  EXPECT_TRUE(std::any_of(knots.begin(), knots.end(), [&](double t) { return std::abs(t - 0.4 * trot.period) < 1e-12; }));
  for (size_t k = 0; k + 1 < knots.size(); ++k) {
    const auto d = footDisplacements(model, legs, pose, ik, target, knots[k]);
    for (int id = 0; id < 4; ++id) {
      const Vec3 designed = trotFootDisplacement(resolved, trotLegPhase(resolved, static_cast<LegId>(id), knots[k]));
      EXPECT_LT((d[id] - designed).norm(), 1e-9) << legIdName(static_cast<LegId>(id)) << " t = " << knots[k];
    }
  }
  trot.ground_speed_share = 1.0;
  EXPECT_THROW(makeTrotTarget(model, trot), std::invalid_argument);
}

TEST(Gait, ParsesSwingProfileNames) {
  EXPECT_EQ(parseSwingProfile("cosine"), SwingProfile::Cosine);
  EXPECT_EQ(parseSwingProfile("ground_speed"), SwingProfile::GroundSpeed);
  EXPECT_THROW(parseSwingProfile("ground-speed"), std::invalid_argument);
}

TEST(Gait, ParsesTypeNames) {
  EXPECT_EQ(parseGaitType("trot"), GaitType::Trot);
  EXPECT_EQ(parseGaitType("jump"), GaitType::Jump);
  EXPECT_EQ(parseGaitType("stand"), GaitType::Stand);
  EXPECT_THROW(parseGaitType("gallop"), std::invalid_argument);
}

}  // namespace
}  // namespace nmdp::test
