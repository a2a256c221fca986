// Blends a gait's joint targets in from the pose the robot starts in.
//
// A trot's targets at t = 0 put its feet half a stride fore and aft of the standing pose the robot
// starts in, and ask for the stance speed at once: a step in the PD target that the integrator
// turns into an impulse spread over its first step, so the start-up depends on dt. Over the ramp's
// duration T the targets are
//   θ̄_r(t) = θ_0 + r(t) (θ̄(t) − θ_0),   θ̄̇_r(t) = r(t) θ̄̇(t) + ṙ(t) (θ̄(t) − θ_0),
//   r(t) = (1 − cos(π t / T)) / 2,
// so they start at θ_0 at rest and join the gait with matching position and velocity at T.
// The blend is in joint space: for the foot displacements of a trot (a few tenths of a leg length)
// it moves the feet nearly by r times the gait's displacement.
#pragma once
#include <Eigen/Core>
#include <memory>

#include "control/pd_target_source.hpp"

namespace nmdp {

class StartRampPdTarget final : public PdTargetSource {
 public:
  // start: the pose θ_0 (size nq); duration T > 0 s. Throws std::invalid_argument otherwise.
  StartRampPdTarget(std::unique_ptr<PdTargetSource> gait, Eigen::VectorXd start, double duration);
  void evaluate(double t, PdTarget& out) const override;

 private:
  std::unique_ptr<PdTargetSource> gait_;
  Eigen::VectorXd start_;
  double duration_;
};

}  // namespace nmdp
