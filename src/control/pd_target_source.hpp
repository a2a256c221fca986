// Joint targets over time for the stable PD controller. The integrator asks for θ̄(t+h), θ̄̇(t+h)
// at the end of every sub-step, so a source must be a pure function of time.
#pragma once
#include "control/stable_pd.hpp"

namespace nmdp {

class PdTargetSource {
 public:
  virtual ~PdTargetSource() = default;
  // Writes θ̄(t) and θ̄̇(t) into out (both sized nq, allocated by the caller). Must not allocate.
  virtual void evaluate(double t, PdTarget& out) const = 0;
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
