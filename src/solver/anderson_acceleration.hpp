// Anderson acceleration (type II, Walker & Ni 2011) of a fixed-point iteration x ← x + f(x).
//
// The projection's chord steps f = −M⁻¹G(x), with M a factorization of ∂G/∂θ at an older iterate,
// converge linearly at a steady rate (the stiff contact term of M is out of date). From the last few pairs (Δx, Δf) this finds the combination of recent steps whose
// residual is smallest, which removes those slow modes: a multisecant update of M⁻¹ that costs a
// few dot products instead of a new Jacobian.
//
//   γ = argmin ‖f_k − ΔF γ‖₂,   step = f_k − (ΔX + ΔF) γ.
//
// The least-squares problem is solved by modified Gram–Schmidt on ΔF, newest column first, and a
// column that is (nearly) a combination of newer ones is dropped: steady linear convergence makes
// successive Δf almost parallel. Buffers are sized by resize(); accelerate() allocates nothing.
#pragma once
#include <Eigen/Core>

namespace nmdp {

class AndersonAcceleration {
 public:
  static constexpr int kMaxMemory = 4;

  void resize(int n, int memory);
  void reset();  // forget the history (a new iteration map, e.g. a new factorization)

  // Records the iterate x and its plain step f = `step`, then replaces `step` by the accelerated
  // step. Returns whether it changed the step (false while there is no usable history).
  bool accelerate(const Eigen::VectorXd& x, Eigen::VectorXd& step);

 private:
  int memory_ = 0;  // pairs kept
  int stored_ = 0;  // pairs held, ≤ memory_
  int newest_ = -1;  // column of the newest pair (a ring buffer)
  bool has_previous_ = false;
  Eigen::VectorXd previous_x_, previous_f_;
  Eigen::MatrixXd dx_, df_;  // n × memory_: Δx and Δf pairs
  Eigen::MatrixXd q_;        // n × memory_: orthonormal basis of the kept Δf columns
  Eigen::Matrix<double, kMaxMemory, kMaxMemory> r_;
  int kept_[kMaxMemory] = {};
};

}  // namespace nmdp
