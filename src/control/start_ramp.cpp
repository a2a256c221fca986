#include "control/start_ramp.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nmdp {

StartRampPdTarget::StartRampPdTarget(std::unique_ptr<PdTargetSource> gait, Eigen::VectorXd start, double duration)
    : gait_(std::move(gait)), start_(std::move(start)), duration_(duration) {
  if (!gait_) throw std::invalid_argument("start ramp: no gait to ramp in");
  if (!(std::isfinite(duration_) && duration_ > 0))
    throw std::invalid_argument("start ramp: duration must be positive and finite");
  if (!start_.allFinite()) throw std::invalid_argument("start ramp: the start pose has a non-finite entry");
}

void StartRampPdTarget::evaluate(double t, PdTarget& out) const {
  gait_->evaluate(t, out);
  if (t >= duration_) return;
  const double s = std::max(t, 0.0) / duration_;
  const double r = (1 - std::cos(M_PI * s)) / 2;
  const double r_dot = M_PI * std::sin(M_PI * s) / (2 * duration_);
  // Velocity first: it needs the gait's own position.
  out.velocity = r * out.velocity + r_dot * (out.position - start_);
  out.position = start_ + r * (out.position - start_);
}

}  // namespace nmdp
