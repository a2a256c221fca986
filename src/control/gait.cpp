#include "control/gait.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/named_enum.hpp"
#include "common/text.hpp"
#include "control/heading_feedback.hpp"
#include "control/start_ramp.hpp"

namespace nmdp {

namespace {

constexpr EnumName<GaitType> kGaitTypes[] = {{GaitType::Stand, "stand"}, {GaitType::Trot, "trot"}, {GaitType::Jump, "jump"}};
constexpr EnumName<SwingProfile> kSwingProfiles[] = {{SwingProfile::Cosine, "cosine"},
                                                     {SwingProfile::GroundSpeed, "ground_speed"}};

constexpr double kPi = 3.14159265358979323846;
constexpr double kDefaultStandShare = 0.8;       // standing height / straight height
constexpr double kDefaultStrideShare = 0.25;     // stride / leg length
constexpr double kDefaultStepHeightShare = 0.15;  // step height / leg length
constexpr double kDefaultCrouchShare = 0.25;     // crouch depth / leg length
constexpr double kDefaultPushOffShare = 0.4;     // of the way from standing to straight legs
constexpr double kSingularConditioning = 1e-2;   // σ_min/σ_max below this: a straight knee
constexpr double kBendAngle = 0.8;               // rad, knee bend of the seeds that leave a straight knee

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(what); }

void requirePositive(double value, const char* name) {
  if (!std::isfinite(value) || !(value > 0)) {
    std::ostringstream os;
    os << name << " must be positive and finite, got " << value;
    fail(os.str());
  }
}
void requireNonNegative(double value, const char* name) {
  if (!std::isfinite(value) || value < 0) {
    std::ostringstream os;
    os << name << " must be non-negative and finite, got " << value;
    fail(os.str());
  }
}

std::string describe(const Vec3& v) {
  std::ostringstream os;
  os << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return os.str();
}

// Sets the base coordinates to the standing values: vertical translation = height, the rest 0.
void setStandingBase(const Model& model, double height, Eigen::VectorXd& q) {
  for (int i = 0; i < model.nq; ++i) {
    const Body& body = model.bodies[i];
    if (!body.is_base) continue;
    const bool vertical = body.kind == JointKind::Prismatic && body.axis.isApprox(Vec3::UnitZ());
    q[i] = vertical ? height : 0.0;
  }
}

// Keeps the seed a little inside finite limits, so a straight knee just outside a limit
// (q = 0 with knee limits [−2.7, −0.5]) becomes a bent one.
void clampSeedIntoLimits(const Leg& leg, const JointLimits& limits, Eigen::VectorXd& q) {
  for (int j : leg.joints) {
    const double lower = limits.lower[j], upper = limits.upper[j];
    const double margin = std::isfinite(upper - lower) ? std::min(0.05, 0.1 * (upper - lower)) : 0.0;
    q[j] = std::clamp(q[j], lower + margin, upper - margin);
  }
}

// How far forward the leg's knee (the body of its last joint) sits relative to the midpoint of
// its first joint and foot, in the trunk frame; gaits prefer knees that point backward.
double kneeForwardness(const Model& model, LegIkSolver& ik, const Leg& leg, const Eigen::VectorXd& q) {
  const int knee_link = model.linkIndex(model.bodies[leg.joints.back()].name);
  const int hip_link = model.linkIndex(model.bodies[leg.joints.front()].name);
  const Vec3 knee = ik.linkPointInTrunk(knee_link, Vec3::Zero(), q);
  const Vec3 hip = ik.linkPointInTrunk(hip_link, Vec3::Zero(), q);
  return knee.x() - 0.5 * (hip.x() + ik.footInTrunk(leg, q).x());
}

// Solves one leg of q for a foot target; throws naming `what` when it cannot be reached.
void solveOrThrow(LegIkSolver& ik, const Leg& leg, LegId id, const Vec3& target, Eigen::VectorXd& q,
                  const std::string& what) {
  const LegIkResult result = ik.solve(leg, target, q);
  if (!result.converged)
    fail(what + ": the " + std::string(legIdName(id)) + " foot (" + leg.foot.name + ") cannot reach " +
         describe(target) + " m in the trunk frame (" + std::to_string(result.error) +
         " m short, joint limits or leg length); choose smaller sizes");
}

struct GaitContext {
  QuadrupedLegs legs;
  StandingPose pose;
};

GaitContext gaitContext(const Model& model, const StandParameters& stand) {
  GaitContext context{identifyQuadrupedLegs(model, stand.nominal_q), {}};
  context.pose = standingPose(model, context.legs, stand);
  return context;
}

}  // namespace

const char* gaitTypeName(GaitType type) { return nameOf(kGaitTypes, type); }

GaitType parseGaitType(const std::string& name) {
  if (const auto type = enumFromName(kGaitTypes, name)) return *type;
  fail("unknown gait type '" + name + "' (valid: " + join(namesOf(kGaitTypes), ", ") + ")");
}

const char* swingProfileName(SwingProfile profile) { return nameOf(kSwingProfiles, profile); }

SwingProfile parseSwingProfile(const std::string& name) {
  if (const auto profile = enumFromName(kSwingProfiles, name)) return *profile;
  fail("unknown swing profile '" + name + "' (valid: " + join(namesOf(kSwingProfiles), ", ") + ")");
}

StandingPose standingPose(const Model& model, const QuadrupedLegs& legs, const StandParameters& stand) {
  if (stand.nominal_q.size() != 0 && (stand.nominal_q.size() != model.nq || !stand.nominal_q.allFinite()))
    fail("stand.nominal_q must hold " + std::to_string(model.nq) + " finite values, got " +
         std::to_string(stand.nominal_q.size()));
  if (stand.height) requirePositive(*stand.height, "stand.height");
  LegIkSolver ik(model, readJointLimits(model));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nq);
  const Eigen::VectorXd nominal = stand.nominal_q.size() ? stand.nominal_q : zero;

  StandingPose pose;
  std::array<Vec3, 4> nominal_feet;
  for (int id = 0; id < 4; ++id) {
    const Leg& leg = legs.legs[id];
    const Vec3 straight_foot = ik.footInTrunk(leg, zero);
    const Vec3 hip = ik.linkPointInTrunk(model.linkIndex(model.bodies[leg.joints.front()].name), Vec3::Zero(), zero);
    pose.leg_length += 0.25 * (straight_foot - hip).norm();
    pose.straight_height += 0.25 * (leg.foot.radius - straight_foot.z());
    nominal_feet[id] = ik.footInTrunk(leg, nominal);
  }
  if (stand.height) {
    pose.height = *stand.height;
  } else if (stand.nominal_q.size()) {
    pose.height = 0;
    for (int id = 0; id < 4; ++id) pose.height += 0.25 * (legs.legs[id].foot.radius - nominal_feet[id].z());
  } else {
    pose.height = kDefaultStandShare * pose.straight_height;
  }
  requirePositive(pose.height, "the standing height");

  pose.q = nominal;
  setStandingBase(model, pose.height, pose.q);
  for (int id = 0; id < 4; ++id) {
    const Leg& leg = legs.legs[id];
    const Vec3 target(nominal_feet[id].x(), nominal_feet[id].y(), leg.foot.radius - pose.height);
    Eigen::VectorXd seed = pose.q;
    clampSeedIntoLimits(leg, ik.limits(), seed);
    std::vector<Eigen::VectorXd> seeds{seed};
    if (ik.conditioning(leg, seed) < kSingularConditioning && leg.joints.size() >= 2) {
      // A straight knee: IK cannot tell which way to bend, so offer both (a symmetric two-link
      // bend that keeps the foot under the hip) and keep the reachable one with the rearmost knee.
      for (double sign : {1.0, -1.0}) {
        Eigen::VectorXd bent = seed;
        bent[leg.joints.back()] += sign * kBendAngle;
        bent[leg.joints[leg.joints.size() - 2]] -= sign * kBendAngle / 2;
        clampSeedIntoLimits(leg, ik.limits(), bent);
        seeds.push_back(bent);
      }
    }
    bool found = false;
    double best_forwardness = 0;
    Eigen::VectorXd best;
    for (Eigen::VectorXd& candidate : seeds) {
      if (!ik.solve(leg, target, candidate).converged) continue;
      if (ik.conditioning(leg, candidate) < kSingularConditioning) continue;  // stayed straight
      const double forwardness = kneeForwardness(model, ik, leg, candidate);
      if (!found || forwardness < best_forwardness - 1e-9) {
        found = true;
        best_forwardness = forwardness;
        best = candidate;
      }
    }
    if (!found)
      fail("stand: the " + std::string(legIdName(static_cast<LegId>(id))) + " foot (" + leg.foot.name +
           ") cannot reach " + describe(target) + " m in the trunk frame at standing height " +
           std::to_string(pose.height) + " m; choose another stand.height");
    for (int j : leg.joints) pose.q[j] = best[j];
    // Where the foot is, not where it was aimed (to IK tolerance, or off a planar leg's plane):
    // gaits move the feet from here, and a standing pose given as nominal_q reproduces itself.
    pose.feet[id] = ik.footInTrunk(leg, pose.q);
  }
  return pose;
}

TrotParameters withRobotDefaults(const TrotParameters& trot, const StandingPose& pose) {
  TrotParameters out = trot;
  if (!out.stride_length) out.stride_length = kDefaultStrideShare * pose.leg_length;
  if (!out.step_height) out.step_height = kDefaultStepHeightShare * pose.leg_length;
  return out;
}

JumpParameters withRobotDefaults(const JumpParameters& jump, const StandingPose& pose) {
  JumpParameters out = jump;
  if (!out.crouch_depth) out.crouch_depth = kDefaultCrouchShare * pose.leg_length;
  if (!out.push_off_height)
    out.push_off_height = pose.height + kDefaultPushOffShare * std::max(0.0, pose.straight_height - pose.height);
  return out;
}

double trotLegPhase(const TrotParameters& trot, LegId leg, double t) {
  const double offset = (leg == kFrontLeft || leg == kHindRight) ? 0.0 : 0.5;
  const double u = t / trot.period + offset;
  return u - std::floor(u);
}

Vec3 trotFootDisplacement(const TrotParameters& trot, double u) {
  const double stride = *trot.stride_length, lift = *trot.step_height;
  const double swing = 1.0 - trot.duty_factor;
  if (u < swing) {  // the foot leaves and lands with zero vertical speed
    const double s = u / swing;
    const double z = lift * (1 - std::cos(2 * kPi * s)) / 2;
    if (trot.swing_profile == SwingProfile::Cosine) return {-stride / 2 + stride * (1 - std::cos(kPi * s)) / 2, 0.0, z};
    // dx/ds of the stance, so that the foot is at rest on the ground at both ends of the swing.
    const double slope = -stride * swing / trot.duty_factor;
    const double forward_end = 1.0 - trot.ground_speed_share;
    const double x_end = stride / 2 - slope * trot.ground_speed_share;  // where the forward travel ends
    if (s >= forward_end) return {x_end + slope * (s - forward_end), 0.0, z};
    // Cubic Hermite from (−stride/2, slope) to (x_end, slope) over [0, forward_end].
    const double v = s / forward_end, v2 = v * v, v3 = v2 * v, m = slope * forward_end;
    const double x = (2 * v3 - 3 * v2 + 1) * (-stride / 2) + (v3 - 2 * v2 + v) * m + (-2 * v3 + 3 * v2) * x_end +
                     (v3 - v2) * m;
    return {x, 0.0, z};
  }
  const double s = (u - swing) / trot.duty_factor;
  return {stride / 2 - stride * s, 0.0, 0.0};
}

KeyframePdTarget makeStandTarget(const Model& model, const StandParameters& stand) {
  const GaitContext context = gaitContext(model, stand);
  return KeyframePdTarget({0.0}, {context.pose.q}, {Eigen::VectorXd::Zero(model.nq)});
}

namespace {

// The trot's parameters with the robot's defaults, checked.
TrotParameters checkedTrot(const TrotParameters& trot_in, const StandingPose& pose) {
  const TrotParameters trot = withRobotDefaults(trot_in, pose);
  requirePositive(trot.period, "trot.period");
  requireNonNegative(*trot.stride_length, "trot.stride_length");
  requireNonNegative(*trot.step_height, "trot.step_height");
  if (!(trot.duty_factor > 0 && trot.duty_factor < 1)) fail("trot.duty_factor must lie in (0, 1)");
  if (trot.keyframes_per_period < 2) fail("trot.keyframes_per_period must be at least 2");
  if (!(trot.ground_speed_share >= 0 && trot.ground_speed_share < 1))
    fail("trot.ground_speed_share must lie in [0, 1)");
  return trot;
}

// Keyframe phases: every lift-off, mid-swing and touch-down of both pairs (and the end of the
// forward travel of a ground-speed swing), with the gaps between them subdivided to at least
// keyframes_per_period per cycle.
std::vector<double> trotKeyframePhases(const TrotParameters& trot) {
  const double swing = 1.0 - trot.duty_factor;
  std::vector<double> swing_events = {0.0, swing / 2, swing};
  if (trot.swing_profile == SwingProfile::GroundSpeed) swing_events.push_back(swing * (1.0 - trot.ground_speed_share));
  std::vector<double> events;
  for (double offset : {0.0, 0.5})
    for (double u : swing_events) {
      const double phase = u - offset;
      events.push_back(phase - std::floor(phase));
    }
  std::sort(events.begin(), events.end());
  events.erase(std::unique(events.begin(), events.end(), [](double a, double b) { return b - a < 1e-12; }), events.end());
  std::vector<double> phases;
  for (size_t e = 0; e < events.size(); ++e) {
    const double next = e + 1 < events.size() ? events[e + 1] : events.front() + 1.0;
    const int pieces = std::max(1, static_cast<int>(std::ceil((next - events[e]) * trot.keyframes_per_period - 1e-9)));
    for (int i = 0; i < pieces; ++i) phases.push_back(events[e] + (next - events[e]) * i / pieces);
  }
  return phases;
}

// Solves every leg of q for the trot's foot targets at time t (q seeds the IK).
void solveTrotKeyframe(LegIkSolver& ik, const GaitContext& context, const TrotParameters& trot, double t,
                       Eigen::VectorXd& q) {
  for (int id = 0; id < 4; ++id) {
    const LegId leg = static_cast<LegId>(id);
    const Vec3 target = context.pose.feet[id] + trotFootDisplacement(trot, trotLegPhase(trot, leg, t));
    solveOrThrow(ik, context.legs.legs[id], leg, target, q, "trot (stride_length, step_height)");
  }
}

}  // namespace

KeyframePdTarget makeTrotTarget(const Model& model, const TrotParameters& trot_in, const StandParameters& stand) {
  const GaitContext context = gaitContext(model, stand);
  const TrotParameters trot = checkedTrot(trot_in, context.pose);
  LegIkSolver ik(model, readJointLimits(model));
  std::vector<double> times;
  std::vector<Eigen::VectorXd> positions;
  Eigen::VectorXd q = context.pose.q;  // each keyframe's IK starts from the previous one
  for (double phase : trotKeyframePhases(trot)) {
    const double t = phase * trot.period;
    solveTrotKeyframe(ik, context, trot, t, q);
    times.push_back(t);
    positions.push_back(q);
  }
  return KeyframePdTarget(std::move(times), positions, {}, SplineEndMode::Periodic, trot.period);
}

TrotCorrectionModes makeTrotCorrectionModes(const Model& model, const TrotParameters& trot_in,
                                            const StandParameters& stand) {
  const GaitContext context = gaitContext(model, stand);
  const TrotParameters trot = checkedTrot(trot_in, context.pose);
  TrotParameters unit_stride = trot;
  unit_stride.stride_length = 1.0;
  // Central-difference step of the correction: foot moves of at most ~1e-4 m · (foot distance),
  // far above the IK tolerance (1e-11 m) and far below the leg's curvature scale.
  constexpr double kStep = 1e-4;
  LegIkSolver ik(model, readJointLimits(model));
  std::vector<double> times;
  std::vector<Eigen::VectorXd> turns;
  Eigen::VectorXd q = context.pose.q;  // the trot's own keyframes, as makeTrotTarget builds them
  for (double phase : trotKeyframePhases(trot)) {
    const double t = phase * trot.period;
    solveTrotKeyframe(ik, context, trot, t, q);
    Eigen::VectorXd turn = Eigen::VectorXd::Zero(model.nq);
    for (int id = 0; id < 4; ++id) {
      const LegId leg_id = static_cast<LegId>(id);
      const Leg& leg = context.legs.legs[id];
      const double u = trotLegPhase(trot, leg_id, t);
      const double w = trotFootDisplacement(unit_stride, u).x();
      const Vec3 target = context.pose.feet[id] + trotFootDisplacement(trot, u);
      const Vec3 move = w * Vec3(-target.y(), target.x(), 0.0);  // ẑ × target: rotation about the trunk z axis
      if (move.isZero()) continue;
      Eigen::VectorXd plus = q, minus = q;
      solveOrThrow(ik, leg, leg_id, target + kStep * move, plus, "trot heading feedback");
      solveOrThrow(ik, leg, leg_id, target - kStep * move, minus, "trot heading feedback");
      for (int j : leg.joints) turn[j] = (plus[j] - minus[j]) / (2 * kStep);
    }
    times.push_back(t);
    turns.push_back(turn);
  }
  return {KeyframePdTarget(std::move(times), turns, {}, SplineEndMode::Periodic, trot.period)};
}

KeyframePdTarget makeJumpTarget(const Model& model, const JumpParameters& jump_in, const StandParameters& stand) {
  const GaitContext context = gaitContext(model, stand);
  const JumpParameters jump = withRobotDefaults(jump_in, context.pose);
  requirePositive(jump.period, "jump.period");
  requireNonNegative(jump.pause, "jump.pause");
  requireNonNegative(*jump.crouch_depth, "jump.crouch_depth");
  requirePositive(*jump.push_off_height, "jump.push_off_height");
  requirePositive(jump.crouch_share, "jump.crouch_share");
  requirePositive(jump.extension_share, "jump.extension_share");
  if (!(jump.pause < jump.period)) fail("jump.pause must be shorter than jump.period");
  if (!(jump.crouch_share + jump.extension_share < 1)) fail("jump.crouch_share + jump.extension_share must be below 1");
  if (!(*jump.crouch_depth < context.pose.height)) fail("jump.crouch_depth must be below the standing height");
  if (!(*jump.push_off_height > context.pose.height)) {
    std::ostringstream os;
    os << "jump.push_off_height (" << *jump.push_off_height << " m) must be above the standing height ("
       << context.pose.height << " m): the legs push the trunk up to it";
    if (!jump_in.push_off_height)
      os << "; its default comes from the straight-leg height at q = 0 (" << context.pose.straight_height
         << " m), which is no higher for a robot whose legs do not hang under it at q = 0: give push_off_height";
    fail(os.str());
  }

  LegIkSolver ik(model, readJointLimits(model));
  // Feet stay under the hips; only their height in the trunk frame changes.
  auto pose_at_height = [&](double height, Eigen::VectorXd q, bool best_effort) {
    for (int id = 0; id < 4; ++id) {
      const Leg& leg = context.legs.legs[id];
      Vec3 target = context.pose.feet[id];
      target.z() = leg.foot.radius - height;
      if (best_effort)
        ik.solve(leg, target, q);  // as far as the legs and limits allow
      else
        solveOrThrow(ik, leg, static_cast<LegId>(id), target, q, "jump (crouch_depth)");
    }
    setStandingBase(model, context.pose.height, q);
    return q;
  };
  const Eigen::VectorXd crouched = pose_at_height(context.pose.height - *jump.crouch_depth, context.pose.q, false);
  const Eigen::VectorXd extended = pose_at_height(*jump.push_off_height, context.pose.q, true);

  const double moving = jump.period - jump.pause;
  const double crouch_end = jump.crouch_share * moving;
  const double extension_end = crouch_end + jump.extension_share * moving;
  std::vector<double> times{0.0, crouch_end, extension_end};
  std::vector<Eigen::VectorXd> positions{context.pose.q, crouched, extended};
  if (jump.pause > 0) {  // land at the end of the motion and hold until the cycle wraps
    times.push_back(moving);
    positions.push_back(context.pose.q);
  }
  // Every keyframe is a turning point or a rest: zero velocity (smooth-step between poses).
  const std::vector<Eigen::VectorXd> velocities(times.size(), Eigen::VectorXd::Zero(model.nq));
  return KeyframePdTarget(std::move(times), positions, velocities, SplineEndMode::Periodic, jump.period);
}

std::unique_ptr<PdTargetSource> makeGaitTarget(const Model& model, const GaitParameters& gait) {
  switch (gait.type) {
    case GaitType::Stand: return std::make_unique<KeyframePdTarget>(makeStandTarget(model, gait.stand));
    case GaitType::Trot: {
      requireNonNegative(gait.trot.start_ramp, "trot.start_ramp");
      std::unique_ptr<PdTargetSource> trot = std::make_unique<KeyframePdTarget>(makeTrotTarget(model, gait.trot, gait.stand));
      if (gait.trot.start_ramp > 0)
        trot = std::make_unique<StartRampPdTarget>(std::move(trot), gaitContext(model, gait.stand).pose.q,
                                                   gait.trot.start_ramp);
      if (!gait.trot.heading_feedback.value_or(model.base == BaseType::Floating)) return trot;
      if (model.base != BaseType::Floating) fail("trot.heading_feedback needs a floating base");
      const GaitContext context = gaitContext(model, gait.stand);
      return std::make_unique<HeadingFeedbackPdTarget>(std::move(trot), makeTrotCorrectionModes(model, gait.trot, gait.stand).turn,
                                                       headingFeedbackGains(withRobotDefaults(gait.trot, context.pose), context.pose));
    }
    case GaitType::Jump: return std::make_unique<KeyframePdTarget>(makeJumpTarget(model, gait.jump, gait.stand));
  }
  fail("unknown gait type");
}

}  // namespace nmdp
