// Built-in gaits for any quadruped (DESIGN.md 5): stand, trot and jump.
//
// Each gait designs foot positions in the trunk frame (x forward, y left, z up; the root link
// frame), turns them into joint targets by leg IK (control/leg_ik.hpp) at keyframes, and
// interpolates those with cubic Hermite splines (control/hermite_spline.hpp). Base coordinates of
// the targets are ignored by the PD controller (zero gains); they hold the standing values (base
// height = standing height, everything else 0).
//
// Sizes are scaled to the robot by two lengths measured at q = 0 (the legs hanging straight):
//   leg length L        mean distance from a leg's first joint to its foot sphere centre;
//   straight height H0  mean height of the trunk origin above the feet's lowest points.
// A robot whose legs do not hang under it at q = 0 (RoboSimian's limbs stretch out level) stands
// from a bent StandParameters::nominal_q; its H0 means nothing, so its jump needs push_off_height.
#pragma once
#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <string>

#include "control/hermite_spline.hpp"
#include "control/leg_ik.hpp"

namespace nmdp {

// The standing pose every gait starts from and returns to.
struct StandParameters {
  // Height of the trunk origin above flat ground with all four feet on it, m.
  // Default: 0.8·H0, or the height of nominal_q's feet when nominal_q is given.
  std::optional<double> height;
  // Nominal joint vector (nq): its feet fix the horizontal foot positions (and the vertical ones
  // when height is unset) and it seeds the IK, so it picks the knee configuration. Empty: q = 0,
  // i.e. feet straight under the hips, knees bent backward (or as the URDF's limits require).
  Eigen::VectorXd nominal_q;
};

// How a swing foot leaves and meets the ground (trotFootDisplacement).
enum class SwingProfile {
  // The foot starts and stops at rest in the trunk frame (cosine profiles): it lands moving forward
  // with the trunk's speed, and the stance legs brake it.
  Cosine,
  // The foot leaves and lands at rest on the ground: moving backward in the trunk frame at the
  // stance speed, stride / (duty · period). Its forward travel ends ground_speed_share of the swing
  // before touch-down; from there it descends at the stance speed, so a foot that meets the ground
  // early (the trunk sunk into it or lower than planned) lands without sliding either.
  GroundSpeed,
};
const char* swingProfileName(SwingProfile profile);             // "cosine", "ground_speed"
SwingProfile parseSwingProfile(const std::string& name);        // throws std::invalid_argument listing the names

struct TrotParameters {
  std::optional<double> stride_length;  // m, foot travel relative to the trunk per step; default 0.25·L
  std::optional<double> step_height;    // m, foot lift at mid-swing; default 0.15·L
  double period = 0.5;                  // s, one full cycle (both diagonal pairs step once)
  double duty_factor = 0.5;             // fraction of the period a foot is on the ground, in (0, 1)
  SwingProfile swing_profile = SwingProfile::Cosine;
  // GroundSpeed only: share of the swing, at its end, spent descending at the stance speed, in
  // [0, 1). 0.15 starts it at about a fifth of the step height (z = h (1 − cos 2πs)/2).
  double ground_speed_share = 0.15;
  int keyframes_per_period = 16;        // IK keyframes (at least); phase events are always keyframes
  // s over which the targets blend in from the standing pose (control/start_ramp.hpp); 0: none,
  // the targets start half a stride away from the standing pose. makeGaitTarget only.
  double start_ramp = 0.0;
  // Heading and line feedback (control/heading_feedback.hpp); unset: on for a floating base, off
  // otherwise (a planar base can neither yaw nor drift sideways). makeGaitTarget only.
  std::optional<bool> heading_feedback;
};

struct JumpParameters {
  std::optional<double> crouch_depth;    // m the trunk is lowered from standing; default 0.25·L
  std::optional<double> push_off_height;  // m trunk height at full extension, > stand; default stand + 0.4·(H0 − stand)
  // s, one crouch–extend–land–pause cycle. 2 s gives a 240 ms push-off: with 1 s (90 ms) the
  // PD legs throw the project's quadruped and A1 0.6–0.8 m up and flip them at dt = 1 ms.
  double period = 2.0;
  double pause = 0.4;                    // s standing still at the end of each cycle
  // Shares of the moving time (period − pause): slow crouch, quick extension, rest to land.
  double crouch_share = 0.6;
  double extension_share = 0.15;
};

enum class GaitType { Stand, Trot, Jump };
const char* gaitTypeName(GaitType type);             // "stand", "trot", "jump"
GaitType parseGaitType(const std::string& name);     // throws std::invalid_argument listing the names

struct GaitParameters {
  GaitType type = GaitType::Stand;
  StandParameters stand;  // shared by all gaits
  TrotParameters trot;
  JumpParameters jump;
};

// The robot's standing pose, with the lengths used for default gait sizes.
struct StandingPose {
  Eigen::VectorXd q;                // nq: base at (0, 0, height) level, legs by IK
  double height = 0.0;              // trunk origin above the ground
  std::array<Vec3, 4> feet;         // foot sphere centres in the trunk frame at q, by LegId
  double leg_length = 0.0;          // L
  double straight_height = 0.0;     // H0
};

// Throws std::invalid_argument when the robot is not a quadruped or the pose is out of reach.
StandingPose standingPose(const Model& model, const QuadrupedLegs& legs, const StandParameters& stand);

// The parameters with every unset size replaced by its default for this robot.
TrotParameters withRobotDefaults(const TrotParameters& trot, const StandingPose& pose);
JumpParameters withRobotDefaults(const JumpParameters& jump, const StandingPose& pose);

// Foot displacement from its standing position (trunk frame) designed by the trot at phase
// u ∈ [0, 1) of the leg's own cycle: swing on [0, 1 − duty) (lift by step height, move forward by
// the stride, shaped by swing_profile), stance on [1 − duty, 1) (move back by the stride, on the
// ground). The diagonal pair front left + hind right has u = t/period, the other pair is half a
// period later.
Vec3 trotFootDisplacement(const TrotParameters& resolved, double u);
double trotLegPhase(const TrotParameters& resolved, LegId leg, double t);

// The trot's keyframes' response to a unit turn (control/heading_feedback.hpp), as joint targets
// on the trot's keyframe times (base entries 0): every foot target rotated about the trunk's
// vertical axis by w(u) rad, w(u) the stride's own profile for a unit stride (trotFootDisplacement's
// x with stride 1: +1/2 at touch-down, −1/2 at lift-off), so a turn c yaws the trunk by c per
// stance on feet that do not slip. By leg IK linearized with central differences.
struct TrotCorrectionModes {
  KeyframePdTarget turn;
};
TrotCorrectionModes makeTrotCorrectionModes(const Model& model, const TrotParameters& trot = {},
                                            const StandParameters& stand = {});

// Builders; all throw std::invalid_argument naming the parameter for invalid or unreachable sizes.
KeyframePdTarget makeStandTarget(const Model& model, const StandParameters& stand = {});
KeyframePdTarget makeTrotTarget(const Model& model, const TrotParameters& trot = {}, const StandParameters& stand = {});
KeyframePdTarget makeJumpTarget(const Model& model, const JumpParameters& jump = {}, const StandParameters& stand = {});
// The gait's targets; a trot with start_ramp > 0 blends in from the standing pose, and a trot with
// heading feedback (by default on a floating base) corrects its heading and line.
std::unique_ptr<PdTargetSource> makeGaitTarget(const Model& model, const GaitParameters& gait);

}  // namespace nmdp
