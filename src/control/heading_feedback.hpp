// Heading and line feedback for the trot on a floating base.
//
// The trot's foot targets are fixed in the trunk frame, so nothing brings a floating trunk back
// when its feet slip or push unevenly: it walks off in whatever direction it comes to face. The
// feedback turns the feet the way a turning trot does: over a stance, foot targets rotated about
// the trunk's vertical axis from +c/2 to −c/2 yaw the trunk by c on feet that do not slip; the
// swing brings them back (the turn follows the stride's own profile, so it is zero at mid-stance
// and mid-swing and the feet lift and land where the stride puts them).
//
// The heading to hold leans back toward the start line (through the start position along the
// start heading, the commanded ones), as a pure-pursuit steering law:
//   ψ_ref = ψ_0 − atan(e_y / D),   D = kLineCycles · stride / duty,
// e_y the trunk's offset to the left of the line and D the distance the trot walks in kLineCycles
// cycles at its nominal speed stride / (duty · period): the line is regained over about that many
// cycles. Per stance (duration T_s = duty · period) the turn is
//   c = −(T_s / τ) wrap(ψ − ψ_ref),
// with τ = one gait period: the heading error decays over about two stances. |c| is capped so
// that no foot turns by more than half a stride. The line is held through the heading, not by
// side-stepping: sideways foot shifts pump the trot's roll sway (on A1, feet 0.26 m apart)
// until it rolls over.
//
// The turn enters the joint targets linearly: the trot's keyframes' response to a unit turn is
// precomputed by leg IK (makeTrotCorrectionModes), so a step costs one spline evaluation more and
// allocates nothing.
#pragma once
#include <memory>

#include "control/gait.hpp"
#include "control/pd_target_source.hpp"

namespace nmdp {

struct HeadingFeedbackGains {
  double stance_time = 0.0;     // T_s, s
  double time_constant = 0.0;   // τ, s
  double max_turn = 0.0;        // rad per stance
  double line_distance = 0.0;   // D, m (0: hold the start heading only)
};
// The gains of the resolved trot (every size set) for the robot's standing feet.
HeadingFeedbackGains headingFeedbackGains(const TrotParameters& resolved, const StandingPose& pose);

struct HeadingCorrection {
  double offset = 0.0;   // e_y, m to the left of the start line
  double heading = 0.0;  // ψ_ref, rad
  double turn = 0.0;     // c, rad per stance (positive: turns the trunk left)
};
HeadingCorrection headingCorrection(const HeadingFeedbackGains& gains, const TrunkState& start, const TrunkState& now);

// The trot's targets plus c · turn, with the correction of the last observeTrunk (none before
// the first).
class HeadingFeedbackPdTarget final : public PdTargetSource {
 public:
  // turn: makeTrotCorrectionModes(...).turn of the same trot.
  HeadingFeedbackPdTarget(std::unique_ptr<PdTargetSource> trot, KeyframePdTarget turn, HeadingFeedbackGains gains);
  void evaluate(double t, PdTarget& out) const override;
  bool observesTrunk() const override { return true; }
  void observeTrunk(const TrunkState& start, const TrunkState& now) override;

  const HeadingCorrection& correction() const { return correction_; }
  const HeadingFeedbackGains& gains() const { return gains_; }

 private:
  std::unique_ptr<PdTargetSource> trot_;
  KeyframePdTarget turn_;
  HeadingFeedbackGains gains_;
  HeadingCorrection correction_;
  mutable PdTarget mode_;  // evaluate's scratch (nq), so that a step allocates nothing
};

}  // namespace nmdp
