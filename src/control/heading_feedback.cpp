#include "control/heading_feedback.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nmdp {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Gait cycles the trunk needs, at the trot's nominal speed, to walk the look-ahead distance: the
// line is regained over about this many cycles, slower than the heading (about one), so the two
// loops do not fight.
constexpr double kLineCycles = 4.0;

double wrapAngle(double angle) { return angle - 2 * kPi * std::floor((angle + kPi) / (2 * kPi)); }

}  // namespace

HeadingFeedbackGains headingFeedbackGains(const TrotParameters& trot, const StandingPose& pose) {
  if (!trot.stride_length) throw std::invalid_argument("heading feedback: the trot's stride is not resolved");
  HeadingFeedbackGains gains;
  gains.stance_time = trot.duty_factor * trot.period;
  gains.time_constant = trot.period;
  double reach = 0.0;  // the farthest standing foot from the trunk's vertical axis
  for (const Vec3& foot : pose.feet) reach = std::max(reach, std::hypot(foot.x(), foot.y()));
  gains.max_turn = reach > 0 ? *trot.stride_length / 2 / reach : 0.0;
  gains.line_distance = kLineCycles * *trot.stride_length / trot.duty_factor;
  return gains;
}

HeadingCorrection headingCorrection(const HeadingFeedbackGains& gains, const TrunkState& start, const TrunkState& now) {
  const Eigen::Vector2d lateral(-std::sin(start.yaw), std::cos(start.yaw));  // left of the start heading
  HeadingCorrection c;
  c.offset = lateral.dot(now.position - start.position);
  c.heading = start.yaw - (gains.line_distance > 0 ? std::atan(c.offset / gains.line_distance) : 0.0);
  const double error = wrapAngle(now.yaw - c.heading);
  const double share = gains.stance_time / gains.time_constant;
  c.turn = std::clamp(-share * error, -gains.max_turn, gains.max_turn);
  return c;
}

HeadingFeedbackPdTarget::HeadingFeedbackPdTarget(std::unique_ptr<PdTargetSource> trot, KeyframePdTarget turn,
                                                 HeadingFeedbackGains gains)
    : trot_(std::move(trot)), turn_(std::move(turn)), gains_(gains) {
  if (!trot_) throw std::invalid_argument("heading feedback: no trot to correct");
  if (!(gains_.time_constant > 0 && gains_.stance_time > 0))
    throw std::invalid_argument("heading feedback: the stance time and the time constant must be positive");
  const int n = turn_.spline().dimension();
  mode_.position = Eigen::VectorXd::Zero(n);
  mode_.velocity = Eigen::VectorXd::Zero(n);
}

void HeadingFeedbackPdTarget::evaluate(double t, PdTarget& out) const {
  trot_->evaluate(t, out);
  if (correction_.turn == 0.0) return;
  turn_.evaluate(t, mode_);
  out.position += correction_.turn * mode_.position;
  out.velocity += correction_.turn * mode_.velocity;
}

void HeadingFeedbackPdTarget::observeTrunk(const TrunkState& start, const TrunkState& now) {
  correction_ = headingCorrection(gains_, start, now);
}

}  // namespace nmdp
