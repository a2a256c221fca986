// Cubic Hermite interpolation of joint-target keyframes (DESIGN.md 5).
//
// On the segment [t_k, t_{k+1}] of duration Δ = t_{k+1} − t_k, with s = (t − t_k)/Δ ∈ [0, 1],
//
//   p(t) = h00(s) p_k + h10(s) Δ m_k + h01(s) p_{k+1} + h11(s) Δ m_{k+1}
//   ṗ(t) = [h00'(s) p_k + h10'(s) Δ m_k + h01'(s) p_{k+1} + h11'(s) Δ m_{k+1}] / Δ
//
// where m_k are slopes in units per second. The division by Δ in ṗ is what the original code
// forgot: ṗ is the true time derivative of p, so a PD controller tracking (p, ṗ) is consistent.
//
// Slopes not given by the caller are the derivative at t_k of the parabola through the keyframes
// k−1, k, k+1:  m_k = (Δ_{k−1} d_k + Δ_k d_{k−1}) / (Δ_{k−1} + Δ_k), d_k = (p_{k+1} − p_k)/Δ_k,
// exact for quadratics and equal to Catmull–Rom's (p_{k+1} − p_{k−1})/(t_{k+1} − t_{k−1}) on a
// uniform grid. The end slopes are zero when holding, and wrap around when periodic.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "control/pd_target_source.hpp"

namespace nmdp {

// What the spline does outside its keyframes.
enum class SplineEndMode {
  // Before the first keyframe hold the first position, after the last hold the last one; both
  // with zero velocity (automatic end slopes are zero, so ṗ is continuous there; given nonzero end
  // velocities make ṗ jump at the ends).
  HoldEnds,
  // Repeat with the given period: after the last keyframe the spline returns to the first one at
  // t_0 + period (so the keyframes list one cycle without repeating the first at the end).
  Periodic,
};

class HermiteSpline {
 public:
  // times: strictly increasing, at least one keyframe. positions: one vector per keyframe, all of
  // one size. velocities: empty (automatic slopes) or one vector per keyframe. Periodic mode
  // requires period > t_last − t_0. Throws std::invalid_argument naming the offending keyframe.
  HermiteSpline(std::vector<double> times, const std::vector<Eigen::VectorXd>& positions,
                const std::vector<Eigen::VectorXd>& velocities = {}, SplineEndMode mode = SplineEndMode::HoldEnds,
                double period = 0.0);

  // p(t) and ṗ(t). Allocates nothing when position and velocity already have size dimension().
  void evaluate(double t, Eigen::VectorXd& position, Eigen::VectorXd& velocity) const;

  int dimension() const { return static_cast<int>(knot_positions_.rows()); }
  int keyframeCount() const { return keyframe_count_; }
  SplineEndMode mode() const { return mode_; }
  double period() const { return period_; }  // 0 unless periodic
  double startTime() const { return knot_times_.front(); }
  double endTime() const { return knot_times_.back(); }  // t_0 + period when periodic
  // Keyframe times, plus (periodic) the closing knot t_0 + period.
  const std::vector<double>& knotTimes() const { return knot_times_; }
  // Slope (units/s) at keyframe k, given or automatic.
  Eigen::VectorXd slope(int k) const { return knot_slopes_.col(k); }

 private:
  // Knots are the keyframes, plus (periodic) a copy of the first one at t_0 + period.
  std::vector<double> knot_times_;
  Eigen::MatrixXd knot_positions_;  // dimension × knots
  Eigen::MatrixXd knot_slopes_;     // dimension × knots, units per second
  int keyframe_count_ = 0;
  SplineEndMode mode_ = SplineEndMode::HoldEnds;
  double period_ = 0.0;
};

// Joint targets θ̄(t), θ̄̇(t) from keyframes of the full coordinate vector (size nq; base entries are
// ignored by the controller but must be finite). Loaded from files by the scene loader, built by
// the gait generators (control/gait.hpp).
class KeyframePdTarget final : public PdTargetSource {
 public:
  explicit KeyframePdTarget(HermiteSpline spline) : spline_(std::move(spline)) {}
  KeyframePdTarget(std::vector<double> times, const std::vector<Eigen::VectorXd>& positions,
                   const std::vector<Eigen::VectorXd>& velocities = {}, SplineEndMode mode = SplineEndMode::HoldEnds,
                   double period = 0.0)
      : spline_(std::move(times), positions, velocities, mode, period) {}

  void evaluate(double t, PdTarget& out) const override { spline_.evaluate(t, out.position, out.velocity); }

  const HermiteSpline& spline() const { return spline_; }

 private:
  HermiteSpline spline_;
};

}  // namespace nmdp
