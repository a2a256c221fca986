#include "control/hermite_spline.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace nmdp {

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("keyframes: " + what); }

// Derivative at the middle point of the parabola through (−before, a), (0, b), (after, c).
Eigen::VectorXd parabolaSlope(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& c,
                              double before, double after) {
  const Eigen::VectorXd incoming = (b - a) / before, outgoing = (c - b) / after;
  return (before * outgoing + after * incoming) / (before + after);
}

}  // namespace

HermiteSpline::HermiteSpline(std::vector<double> times, const std::vector<Eigen::VectorXd>& positions,
                             const std::vector<Eigen::VectorXd>& velocities, SplineEndMode mode, double period)
    : knot_times_(std::move(times)), mode_(mode) {
  const int count = static_cast<int>(knot_times_.size());
  if (count == 0) fail("at least one keyframe is needed");
  if (static_cast<int>(positions.size()) != count)
    fail(std::to_string(count) + " times but " + std::to_string(positions.size()) + " position vectors");
  if (!velocities.empty() && static_cast<int>(velocities.size()) != count)
    fail(std::to_string(count) + " times but " + std::to_string(velocities.size()) + " velocity vectors");
  const Eigen::Index dim = positions.front().size();
  for (int k = 0; k < count; ++k) {
    const std::string where = "keyframe " + std::to_string(k);
    if (!std::isfinite(knot_times_[k])) fail(where + ": time is not finite");
    if (k > 0 && !(knot_times_[k] > knot_times_[k - 1])) fail(where + ": times must be strictly increasing");
    if (positions[k].size() != dim)
      fail(where + ": " + std::to_string(positions[k].size()) + " positions, expected " + std::to_string(dim));
    if (!positions[k].allFinite()) fail(where + ": positions are not finite");
    if (!velocities.empty()) {
      if (velocities[k].size() != dim)
        fail(where + ": " + std::to_string(velocities[k].size()) + " velocities, expected " + std::to_string(dim));
      if (!velocities[k].allFinite()) fail(where + ": velocities are not finite");
    }
  }
  keyframe_count_ = count;
  if (mode == SplineEndMode::Periodic) {
    if (!std::isfinite(period) || !(period > knot_times_.back() - knot_times_.front()))
      fail("the period (" + std::to_string(period) + " s) must exceed the span of the keyframe times (" +
           std::to_string(knot_times_.back() - knot_times_.front()) + " s)");
    period_ = period;
  }

  const int knots = mode == SplineEndMode::Periodic ? count + 1 : count;
  knot_positions_.resize(dim, knots);
  knot_slopes_.resize(dim, knots);
  for (int k = 0; k < count; ++k) knot_positions_.col(k) = positions[k];

  for (int k = 0; k < count; ++k) {
    if (!velocities.empty()) {
      knot_slopes_.col(k) = velocities[k];
    } else if (mode == SplineEndMode::Periodic) {
      const int prev = (k + count - 1) % count, next = (k + 1) % count;
      const double before = k > 0 ? knot_times_[k] - knot_times_[prev] : knot_times_[0] + period - knot_times_[prev];
      const double after = k + 1 < count ? knot_times_[next] - knot_times_[k] : knot_times_[0] + period - knot_times_[k];
      knot_slopes_.col(k) = parabolaSlope(positions[prev], positions[k], positions[next], before, after);
    } else if (k == 0 || k == count - 1) {
      knot_slopes_.col(k).setZero();  // hold: ṗ continuous into the constant ends
    } else {
      knot_slopes_.col(k) = parabolaSlope(positions[k - 1], positions[k], positions[k + 1],
                                          knot_times_[k] - knot_times_[k - 1], knot_times_[k + 1] - knot_times_[k]);
    }
  }
  if (mode == SplineEndMode::Periodic) {  // the closing knot repeats keyframe 0 one period later
    knot_times_.push_back(knot_times_.front() + period);
    knot_positions_.col(count) = knot_positions_.col(0);
    knot_slopes_.col(count) = knot_slopes_.col(0);
  }
}

void HermiteSpline::evaluate(double t, Eigen::VectorXd& position, Eigen::VectorXd& velocity) const {
  const Eigen::Index dim = knot_positions_.rows();
  if (position.size() != dim) position.resize(dim);
  if (velocity.size() != dim) velocity.resize(dim);
  const int last = static_cast<int>(knot_times_.size()) - 1;

  double local = t;
  if (mode_ == SplineEndMode::Periodic) {
    local = knot_times_.front() + std::fmod(t - knot_times_.front(), period_);
    if (local < knot_times_.front()) local += period_;
    if (local >= knot_times_[last]) local = knot_times_.front();  // fmod round-off at a whole period
  } else if (!(t > knot_times_.front()) || !(t < knot_times_[last])) {
    position = t > knot_times_.front() ? knot_positions_.col(last) : knot_positions_.col(0);
    velocity.setZero();
    return;
  }

  // Segment k with t_k ≤ local < t_{k+1}.
  const auto upper = std::upper_bound(knot_times_.begin(), knot_times_.end(), local);
  const int k = std::clamp(static_cast<int>(upper - knot_times_.begin()) - 1, 0, last - 1);
  const double duration = knot_times_[k + 1] - knot_times_[k];
  const double s = (local - knot_times_[k]) / duration;
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  const double dh00 = 6 * s2 - 6 * s, dh10 = 3 * s2 - 4 * s + 1, dh01 = -dh00, dh11 = 3 * s2 - 2 * s;
  const auto p0 = knot_positions_.col(k), p1 = knot_positions_.col(k + 1);
  const auto m0 = knot_slopes_.col(k), m1 = knot_slopes_.col(k + 1);
  position = h00 * p0 + (h10 * duration) * m0 + h01 * p1 + (h11 * duration) * m1;
  // d/dt = (1/Δ) d/ds; the slope terms carry Δ, which cancels.
  velocity = (dh00 / duration) * p0 + dh10 * m0 + (dh01 / duration) * p1 + dh11 * m1;
}

}  // namespace nmdp
