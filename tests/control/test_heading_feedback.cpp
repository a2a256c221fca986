// Heading and line feedback of the floating-base trot (control/heading_feedback.hpp): the law's
// sign and size, and the foot targets it produces (a yawed trunk gets its stance feet swept back),
// on the project's quadruped, A1 and Solo-12.
#include <cmath>

#include "control/gait.hpp"
#include "control/heading_feedback.hpp"
#include "control/leg_ik.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

HeadingFeedbackGains unitGains() {
  HeadingFeedbackGains g;
  g.stance_time = 0.25;
  g.time_constant = 0.5;
  g.max_turn = 0.2;
  g.line_distance = 0.8;
  return g;
}

TEST(HeadingCorrection, TurnsAgainstTheYawError) {
  const HeadingFeedbackGains g = unitGains();
  TrunkState start, now;
  now.yaw = 0.04;  // turned left: the correction turns right, by T_s/τ of the error per stance
  EXPECT_DOUBLE_EQ(headingCorrection(g, start, now).turn, -0.5 * 0.04);
  now.yaw = -0.04;
  EXPECT_DOUBLE_EQ(headingCorrection(g, start, now).turn, 0.5 * 0.04);
  EXPECT_EQ(headingCorrection(g, start, now).heading, 0.0);  // on the line: the start heading
}

TEST(HeadingCorrection, YawErrorIsWrappedAcrossPi) {
  const HeadingFeedbackGains g = unitGains();
  TrunkState start, now;
  start.yaw = 3.1;
  now.yaw = -3.1;  // 0.083 rad to the left of the start heading, not 6.2 to the right
  EXPECT_NEAR(headingCorrection(g, start, now).turn, -0.5 * (2 * M_PI - 6.2), 1e-12);
}

TEST(HeadingCorrection, SteersBackTowardTheStartLine) {
  const HeadingFeedbackGains g = unitGains();
  TrunkState start, now;
  start.yaw = M_PI / 2;  // heading +y: "left" of the line is −x
  start.position = {1.0, 2.0};
  now.yaw = M_PI / 2;
  now.position = {1.0 - 0.02, 2.5};  // 2 cm left of the line, 0.5 m along it
  const HeadingCorrection c = headingCorrection(g, start, now);
  EXPECT_NEAR(c.offset, 0.02, 1e-15);
  EXPECT_NEAR(c.heading, M_PI / 2 - std::atan(0.02 / 0.8), 1e-15);  // aims right, back to the line
  EXPECT_NEAR(c.turn, -0.5 * std::atan(0.02 / 0.8), 1e-15);         // so it turns right
  now.yaw = c.heading;  // already aiming back: no turn
  EXPECT_NEAR(headingCorrection(g, start, now).turn, 0.0, 1e-15);
}

TEST(HeadingCorrection, IsCappedAtHalfAStride) {
  const HeadingFeedbackGains g = unitGains();
  TrunkState start, now;
  now.yaw = 1.5;
  EXPECT_EQ(headingCorrection(g, start, now).turn, -g.max_turn);
  now.yaw = -1.5;
  EXPECT_EQ(headingCorrection(g, start, now).turn, g.max_turn);
}

TEST(HeadingFeedbackGains, ComeFromTheGaitAndTheFeet) {
  const Model model = loadUrdf(quadrupedUrdf(), UrdfOptions{});
  const QuadrupedLegs legs = identifyQuadrupedLegs(model);
  const StandingPose pose = standingPose(model, legs, {});
  const TrotParameters trot = withRobotDefaults(TrotParameters{}, pose);
  const HeadingFeedbackGains g = headingFeedbackGains(trot, pose);
  EXPECT_DOUBLE_EQ(g.stance_time, trot.duty_factor * trot.period);
  EXPECT_DOUBLE_EQ(g.time_constant, trot.period);
  // The distance walked in 4 cycles at the nominal speed stride / (duty · period).
  EXPECT_DOUBLE_EQ(g.line_distance, 4 * trot.period * *trot.stride_length / (trot.duty_factor * trot.period));
  double reach = 0;
  for (const Vec3& f : pose.feet) reach = std::max(reach, std::hypot(f.x(), f.y()));
  EXPECT_DOUBLE_EQ(g.max_turn, *trot.stride_length / 2 / reach);
}

// --- the foot targets on the project's quadruped ------------------------------------------------

class HeadingFeedbackTargets : public ::testing::Test {
 protected:
  void SetUp() override {
    model = loadUrdf(quadrupedUrdf(), UrdfOptions{});  // floating base
    legs = identifyQuadrupedLegs(model);
    pose = standingPose(model, legs, {});
    GaitParameters gait;
    gait.type = GaitType::Trot;
    source = makeGaitTarget(model, gait);
    trot = withRobotDefaults(gait.trot, pose);
  }
  // The front left foot in the trunk frame under the source's targets at t.
  Vec3 frontLeftFoot(const PdTargetSource& s, double t) {
    PdTarget out{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
    s.evaluate(t, out);
    LegIkSolver ik(model, readJointLimits(model));
    return ik.footInTrunk(legs.legs[kFrontLeft], out.position);
  }
  Model model;
  QuadrupedLegs legs;
  StandingPose pose;
  TrotParameters trot;
  std::unique_ptr<PdTargetSource> source;
};

TEST_F(HeadingFeedbackTargets, OnByDefaultForAFloatingBaseAndIdleUntilObserved) {
  auto* feedback = dynamic_cast<HeadingFeedbackPdTarget*>(source.get());
  ASSERT_NE(feedback, nullptr);
  const KeyframePdTarget plain = makeTrotTarget(model, trot);
  PdTarget a{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)}, b = a;
  for (double t : {0.0, 0.13, 0.37}) {
    feedback->evaluate(t, a);
    plain.evaluate(t, b);
    EXPECT_EQ(a.position, b.position);  // bit for bit: no correction before the first observation
    EXPECT_EQ(a.velocity, b.velocity);
  }
  feedback->observeTrunk(TrunkState{}, TrunkState{});  // on heading, on the line: still none
  feedback->evaluate(0.13, a);
  plain.evaluate(0.13, b);
  EXPECT_EQ(a.position, b.position);
}

TEST_F(HeadingFeedbackTargets, AYawedTrunkGetsItsStanceFeetTurnedBack) {
  auto& feedback = dynamic_cast<HeadingFeedbackPdTarget&>(*source);
  const KeyframePdTarget plain = makeTrotTarget(model, trot);
  TrunkState start, now;
  now.yaw = 0.02;  // the trunk has turned left of its heading
  feedback.observeTrunk(start, now);
  const double c = feedback.correction().turn;
  ASSERT_LT(c, 0.0);
  EXPECT_NEAR(c, -feedback.gains().stance_time / feedback.gains().time_constant * 0.02, 1e-15);

  // Front left: touch-down at u = 1 − duty, lift-off at u = 1 (t = period).
  const double touch_down = (1 - trot.duty_factor) * trot.period, lift_off = trot.period;
  for (double t : {touch_down, lift_off}) {
    const Vec3 plain_foot = frontLeftFoot(plain, t), turned_foot = frontLeftFoot(feedback, t);
    const double w = t == touch_down ? 0.5 : -0.5;  // the stride's profile for a unit stride
    const Vec3 expected = w * c * Vec3(-plain_foot.y(), plain_foot.x(), 0.0);  // ẑ × foot, turned by w·c
    EXPECT_LT((turned_foot - plain_foot - expected).norm(), 0.02 * expected.norm()) << "t = " << t;
  }
  // Over the stance the foot sweeps −c > 0 about the trunk's vertical axis relative to the plain
  // trot: counter-clockwise in the trunk frame, so the trunk turns right (back to its heading) over
  // the planted foot.
  auto angle = [](const Vec3& p) { return std::atan2(p.y(), p.x()); };
  const double sweep = (angle(frontLeftFoot(feedback, lift_off)) - angle(frontLeftFoot(feedback, touch_down))) -
                       (angle(frontLeftFoot(plain, lift_off)) - angle(frontLeftFoot(plain, touch_down)));
  EXPECT_NEAR(sweep, -c, 0.02 * std::abs(c));
}

TEST_F(HeadingFeedbackTargets, ATrunkLeftOfItsLineGetsItsFeetTurnedRight) {
  auto& feedback = dynamic_cast<HeadingFeedbackPdTarget&>(*source);
  TrunkState start, now;
  now.position = {0.3, 0.01};  // 1 cm left of the line, facing along it
  feedback.observeTrunk(start, now);
  EXPECT_LT(feedback.correction().turn, 0.0);
  EXPECT_NEAR(feedback.correction().turn,
              -feedback.gains().stance_time / feedback.gains().time_constant * std::atan(0.01 / feedback.gains().line_distance),
              1e-15);
}

TEST(HeadingFeedbackDefaults, OffForAPlanarBaseAndWhenTurnedOff) {
  UrdfOptions planar;
  planar.base = BaseType::Planar;
  const Model planar_model = loadUrdf(quadrupedUrdf(), planar);
  GaitParameters gait;
  gait.type = GaitType::Trot;
  EXPECT_EQ(dynamic_cast<HeadingFeedbackPdTarget*>(makeGaitTarget(planar_model, gait).get()), nullptr);
  gait.trot.heading_feedback = true;
  EXPECT_THROW(makeGaitTarget(planar_model, gait), std::invalid_argument);

  const Model floating = loadUrdf(quadrupedUrdf(), UrdfOptions{});
  gait.trot.heading_feedback = false;
  EXPECT_EQ(dynamic_cast<HeadingFeedbackPdTarget*>(makeGaitTarget(floating, gait).get()), nullptr);
}

// --- the correction modes on every quadruped ------------------------------------------------------

struct ModeRobot {
  std::string name, path;
  bool shared;
};
void PrintTo(const ModeRobot& r, std::ostream* os) { *os << r.name; }

class CorrectionModes : public ::testing::TestWithParam<ModeRobot> {};

// A small step along the turn mode moves every foot as it should: turned about the trunk's
// vertical axis by w(u) per unit, w the unit stride's profile.
TEST_P(CorrectionModes, MoveTheFeetAsTheyShould) {
  if (GetParam().shared && !std::filesystem::exists(GetParam().path)) GTEST_SKIP() << GetParam().path << " absent";
  const Model model = loadUrdf(GetParam().path, UrdfOptions{});
  const QuadrupedLegs legs = identifyQuadrupedLegs(model);
  const StandingPose pose = standingPose(model, legs, {});
  const TrotParameters trot = withRobotDefaults(TrotParameters{}, pose);
  TrotParameters unit = trot;
  unit.stride_length = 1.0;
  const KeyframePdTarget plain = makeTrotTarget(model, trot);
  const TrotCorrectionModes modes = makeTrotCorrectionModes(model, trot);
  LegIkSolver ik(model, readJointLimits(model));
  const double step = 1e-3;
  PdTarget base{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)}, mode = base;
  for (int k = 0; k < 16; ++k) {
    const double t = trot.period * k / 16;
    plain.evaluate(t, base);
    {
      modes.turn.evaluate(t, mode);
      const Eigen::VectorXd moved = base.position + step * mode.position;
      for (int id = 0; id < 4; ++id) {
        const Vec3 foot = ik.footInTrunk(legs.legs[id], base.position);
        const double w = trotFootDisplacement(unit, trotLegPhase(trot, static_cast<LegId>(id), t)).x();
        const Vec3 expected = step * w * Vec3(-foot.y(), foot.x(), 0.0);
        const Vec3 actual = ik.footInTrunk(legs.legs[id], moved) - foot;
        EXPECT_LT((actual - expected).norm(), 0.02 * step * 0.5 + 1e-9)
            << "t = " << t << " leg " << id << ": " << actual.transpose() << " vs "
            << expected.transpose() << " |mode| " << mode.position.cwiseAbs().maxCoeff();
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, CorrectionModes,
                         ::testing::Values(ModeRobot{"quadruped", quadrupedUrdf(), false},
                                           ModeRobot{"a1", sharedPath("robots/a1/urdf/a1.urdf"), true},
                                           ModeRobot{"solo12", sharedPath("robots/solo12/urdf/solo12.urdf"), true}),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace nmdp::test
