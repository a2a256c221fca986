// Joint targets over time for the stable PD controller. The integrator asks for θ̄(t+h), θ̄̇(t+h)
// at the end of every sub-step, so a source must be a pure function of time within a step. A
// source with feedback (control/heading_feedback.hpp) is shown the trunk's state once before each
// step and stays a pure function of time until the next one.
#pragma once
#include <Eigen/Core>

#include "control/stable_pd.hpp"

namespace nmdp {

// The trunk's heading and place on the ground: what heading and line feedback read.
struct TrunkState {
  double yaw = 0.0;                                    // rad, ZYX yaw of the root link
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // m, world x, y of the root link
};

class PdTargetSource {
 public:
  virtual ~PdTargetSource() = default;
  // Writes θ̄(t) and θ̄̇(t) into out (both sized nq, allocated by the caller). Must not allocate.
  virtual void evaluate(double t, PdTarget& out) const = 0;
  // True for a source that wants observeTrunk before every step (a floating base's trot).
  virtual bool observesTrunk() const { return false; }
  // The trunk at the start of the run (its heading and line are the commanded ones) and now.
  // Called between steps; must not allocate.
  virtual void observeTrunk(const TrunkState& /*start*/, const TrunkState& /*now*/) {}
};

// A fixed pose held with zero target velocity.
class ConstantPdTarget final : public PdTargetSource {
 public:
  explicit ConstantPdTarget(Eigen::VectorXd position) : position_(std::move(position)) {}
  void evaluate(double, PdTarget& out) const override {
    out.position = position_;
    out.velocity.setZero();
  }

 private:
  Eigen::VectorXd position_;
};

// A target position and velocity held until replaced: what a policy sets at every control step
// (Simulation::setTargets from Python's set_targets). The velocity is the target's rate in the PD
// law, not the derivative of the held position.
class HeldPdTarget final : public PdTargetSource {
 public:
  HeldPdTarget(Eigen::VectorXd position, Eigen::VectorXd velocity)
      : position_(std::move(position)), velocity_(std::move(velocity)) {}
  void evaluate(double, PdTarget& out) const override {
    out.position = position_;
    out.velocity = velocity_;
  }

 private:
  Eigen::VectorXd position_, velocity_;
};

}  // namespace nmdp
