// Gait targets (DESIGN.md 5): cubic Hermite keyframes whose velocity is the true time derivative,
// leg IK on the project's quadruped, A1 and Solo-12, and the stand / trot / jump generators; the
// planar legs of RoboSimian in the paper's configuration, standing from a bent nominal pose.
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "control/gait.hpp"
#include "control/hermite_spline.hpp"
#include "control/leg_ik.hpp"
#include "multibody/kinematics.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp::test {
namespace {

constexpr double kDerivativeStep = 1e-6;  // s, central differences in time

Eigen::VectorXd positionAt(const HermiteSpline& spline, double t) {
  Eigen::VectorXd p, v;
  spline.evaluate(t, p, v);
  return p;
}
Eigen::VectorXd velocityAt(const HermiteSpline& spline, double t) {
  Eigen::VectorXd p, v;
  spline.evaluate(t, p, v);
  return v;
}
Eigen::VectorXd centralVelocity(const HermiteSpline& spline, double t) {
  return (positionAt(spline, t + kDerivativeStep) - positionAt(spline, t - kDerivativeStep)) / (2 * kDerivativeStep);
}

// Non-uniform durations (0.1 s to 2.3 s) make a missing division by the duration obvious.
struct SplineCase {
  std::vector<double> times{-0.4, -0.3, 0.4, 2.7, 3.0};
  std::vector<Eigen::VectorXd> positions;
  SplineCase() {
    std::mt19937 rng(11);
    for (size_t k = 0; k < times.size(); ++k) positions.push_back(randomVector(rng, 3, 2.0));
  }
};

// Times to probe: keyframes, either side of them, and inside every segment.
std::vector<double> probeTimes(const std::vector<double>& knots) {
  std::vector<double> out;
  for (size_t k = 0; k < knots.size(); ++k) {
    out.push_back(knots[k]);
    out.push_back(knots[k] + 1e-4);
    out.push_back(knots[k] - 1e-4);
    if (k + 1 < knots.size())
      for (double s : {0.13, 0.5, 0.77}) out.push_back(knots[k] + s * (knots[k + 1] - knots[k]));
  }
  return out;
}

// ṗ against central differences of p. The spline is C¹ but not C² at the knots, so a difference
// straddling a knot is off by up to step·max|p̈|/2; that bound (p̈ from wider second differences
// either side) is added to the tolerance. A velocity that forgot to divide by the segment duration
// is off by O(|ṗ|), far beyond it.
void expectVelocityIsTimeDerivative(const HermiteSpline& spline, const std::vector<double>& times) {
  constexpr double wide = 1e-4;
  for (double t : times) {
    const Eigen::VectorXd v = velocityAt(spline, t), fd = centralVelocity(spline, t);
    double curvature = 0;
    for (double side : {-1.0, 1.0}) {
      const double c = t + side * 2 * wide;
      const Eigen::VectorXd second =
          (positionAt(spline, c + wide) - 2 * positionAt(spline, c) + positionAt(spline, c - wide)) / (wide * wide);
      curvature = std::max(curvature, second.cwiseAbs().maxCoeff());
    }
    const double tolerance = 1e-7 * std::max(1.0, fd.cwiseAbs().maxCoeff()) + kDerivativeStep * curvature;
    EXPECT_LT((v - fd).cwiseAbs().maxCoeff(), tolerance)
        << "t = " << t << "\nvelocity " << v.transpose() << "\ncentral difference " << fd.transpose();
  }
}

TEST(HermiteSpline, HitsKeyframesExactly) {
  const SplineCase c;
  for (SplineEndMode mode : {SplineEndMode::HoldEnds, SplineEndMode::Periodic}) {
    const HermiteSpline spline(c.times, c.positions, {}, mode, 4.1);
    for (size_t k = 0; k < c.times.size(); ++k)
      EXPECT_EQ(positionAt(spline, c.times[k]), c.positions[k]) << "keyframe " << k;
  }
}

TEST(HermiteSpline, VelocityIsTheTimeDerivativeOfPosition) {
  const SplineCase c;
  const HermiteSpline automatic(c.times, c.positions);
  expectVelocityIsTimeDerivative(automatic, probeTimes(c.times));

  std::mt19937 rng(5);
  std::vector<Eigen::VectorXd> velocities;
  for (size_t k = 0; k < c.times.size(); ++k) velocities.push_back(randomVector(rng, 3, 3.0));
  const HermiteSpline given(c.times, c.positions, velocities);
  // Holding the end positions with nonzero given end velocities makes ṗ jump at the two ends.
  std::vector<double> inside;
  for (double t : probeTimes(c.times))
    if (t > c.times.front() + 1e-5 && t < c.times.back() - 1e-5) inside.push_back(t);
  expectVelocityIsTimeDerivative(given, inside);
  for (size_t k = 0; k < c.times.size(); ++k) {
    EXPECT_EQ(given.slope(static_cast<int>(k)), velocities[k]);
    if (k > 0 && k + 1 < c.times.size()) {  // ends hold: velocity 0 from outside
      EXPECT_LT((velocityAt(given, c.times[k]) - velocities[k]).norm(), 1e-12) << "keyframe " << k;
    }
  }
}

TEST(HermiteSpline, PeriodicWrapIsSmoothAndRepeats) {
  const SplineCase c;
  const double period = 4.1;  // the wrap segment 3.0 → 3.7 is 0.7 s long
  const HermiteSpline spline(c.times, c.positions, {}, SplineEndMode::Periodic, period);
  ASSERT_EQ(spline.knotTimes().back(), c.times.front() + period);
  std::vector<double> probes = probeTimes(spline.knotTimes());
  for (double t : {-9.1, -4.5, 5.3, 12.0}) probes.push_back(t);
  expectVelocityIsTimeDerivative(spline, probes);
  for (double t : probes) {
    EXPECT_LT((positionAt(spline, t + period) - positionAt(spline, t)).norm(), 1e-12) << t;
    EXPECT_LT((positionAt(spline, t - 3 * period) - positionAt(spline, t)).norm(), 1e-12) << t;
    EXPECT_LT((velocityAt(spline, t + period) - velocityAt(spline, t)).norm(), 1e-9) << t;
  }
  EXPECT_LT((positionAt(spline, c.times.front() + period) - c.positions.front()).norm(), 1e-12);
}

TEST(HermiteSpline, AutomaticSlopesAreExactForQuadratics) {
  // p(t) = 3t² − t: the parabola slopes reproduce ṗ at interior keyframes whatever the spacing,
  // and a Hermite cubic with exact slopes reproduces the quadratic everywhere.
  const std::vector<double> times{0.0, 0.2, 0.9, 1.0, 2.5};
  std::vector<Eigen::VectorXd> positions;
  for (double t : times) positions.push_back(Eigen::VectorXd::Constant(1, 3 * t * t - t));
  const HermiteSpline spline(times, positions);
  for (int k = 1; k + 1 < static_cast<int>(times.size()); ++k)
    EXPECT_NEAR(spline.slope(k)[0], 6 * times[k] - 1, 1e-12) << "keyframe " << k;
  for (double t : {0.4, 0.95})
    EXPECT_NEAR(positionAt(spline, t)[0], 3 * t * t - t, 1e-12);
  // Uniform spacing: the Catmull–Rom slope.
  const HermiteSpline uniform({0, 1, 2}, {Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Constant(1, 5.0),
                                          Eigen::VectorXd::Constant(1, 2.0)});
  EXPECT_NEAR(uniform.slope(1)[0], (2.0 - 1.0) / 2.0, 1e-15);
}

TEST(HermiteSpline, HoldEndsOutsideTheKeyframes) {
  const SplineCase c;
  const HermiteSpline spline(c.times, c.positions);
  EXPECT_EQ(positionAt(spline, -10.0), c.positions.front());
  EXPECT_EQ(positionAt(spline, 10.0), c.positions.back());
  EXPECT_TRUE(velocityAt(spline, -10.0).isZero(0.0));
  EXPECT_TRUE(velocityAt(spline, 10.0).isZero(0.0));
  EXPECT_LT(velocityAt(spline, c.times.back() - 1e-9).norm(), 1e-6);  // continuous into the hold
  const HermiteSpline single({1.0}, {c.positions[0]});
  EXPECT_EQ(positionAt(single, 7.0), c.positions[0]);
  EXPECT_TRUE(velocityAt(single, 0.5).isZero(0.0));
}

TEST(HermiteSpline, RejectsBadKeyframes) {
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(2), b = Eigen::VectorXd::Ones(2), c = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(HermiteSpline({}, {}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 0.0}, {a, b}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a, c}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a, b}, {a}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a, b}, {}, SplineEndMode::Periodic, 1.0), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, NAN}, {a, b}), std::invalid_argument);
  try {
    HermiteSpline({0.0, 1.0, 0.5}, {a, b, a});
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("keyframe 2"), std::string::npos) << e.what();
  }
}

TEST(KeyframePdTarget, EvaluatesTheSplineWithoutAllocating) {
  const SplineCase c;
  const KeyframePdTarget target(c.times, c.positions, {}, SplineEndMode::Periodic, 4.1);
  const PdTargetSource& source = target;
  PdTarget out{Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3)};
  double t = 0.0;
  const AllocationCount count = allocationsOf([&] {
    for (int i = 0; i < 100; ++i, t += 0.0731) source.evaluate(t, out);
  });
  EXPECT_EQ(count.total(), 0) << count.news << " operator new, " << count.mallocs << " malloc";
  source.evaluate(c.times[2], out);
  EXPECT_EQ(out.position, c.positions[2]);
}

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

// Foot displacements from standing, by FK of the target joints with the trunk fixed.
std::array<Vec3, 4> footDisplacements(const Model& model, const QuadrupedLegs& legs, const StandingPose& pose,
                                      LegIkSolver& ik, const PdTargetSource& source, double t) {
  PdTarget out{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
  source.evaluate(t, out);
  std::array<Vec3, 4> d;
  for (int id = 0; id < 4; ++id) d[id] = ik.footInTrunk(legs.legs[id], out.position) - pose.feet[id];
  return d;
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
  // Measured 2026-11-23: at most 0.33 % of the leg length (1.1-1.5 mm) on all four robots.
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
