#include "solver/anderson_acceleration.hpp"

#include <algorithm>
#include <cmath>

namespace nmdp {

namespace {
// A Δf column whose component orthogonal to the newer ones is below this fraction of its norm is
// dropped: the least-squares problem would be ill-conditioned (its γ large and meaningless).
constexpr double kDropRatio = 1e-4;
}  // namespace

void AndersonAcceleration::resize(int n, int memory) {
  memory_ = std::clamp(memory, 0, kMaxMemory);
  previous_x_.setZero(n);
  previous_f_.setZero(n);
  dx_.setZero(n, memory_);
  df_.setZero(n, memory_);
  q_.setZero(n, memory_);
  reset();
}

void AndersonAcceleration::reset() {
  stored_ = 0;
  newest_ = -1;
  has_previous_ = false;
}

bool AndersonAcceleration::accelerate(const Eigen::VectorXd& x, Eigen::VectorXd& step) {
  if (memory_ == 0) return false;
  if (has_previous_) {
    newest_ = (newest_ + 1) % memory_;
    dx_.col(newest_) = x - previous_x_;
    df_.col(newest_) = step - previous_f_;
    stored_ = std::min(stored_ + 1, memory_);
  }
  previous_x_ = x;
  previous_f_ = step;
  has_previous_ = true;
  // Modified Gram–Schmidt on the Δf columns, newest first.
  int kept = 0;
  for (int age = 0; age < stored_; ++age) {
    const int column = (newest_ - age + memory_) % memory_;
    auto v = q_.col(kept);
    v = df_.col(column);
    const double norm = v.norm();
    if (!(norm > 0.0)) continue;
    for (int i = 0; i < kept; ++i) {
      r_(i, kept) = q_.col(i).dot(v);
      v -= r_(i, kept) * q_.col(i);
    }
    const double orthogonal = v.norm();
    if (!(orthogonal > kDropRatio * norm)) continue;
    r_(kept, kept) = orthogonal;
    v /= orthogonal;
    kept_[kept++] = column;
  }
  if (kept == 0) return false;
  // γ = R⁻¹ Qᵀ f by back substitution.
  double gamma[kMaxMemory];
  for (int i = kept - 1; i >= 0; --i) {
    double s = q_.col(i).dot(previous_f_);
    for (int j = i + 1; j < kept; ++j) s -= r_(i, j) * gamma[j];
    gamma[i] = s / r_(i, i);
  }
  for (int i = 0; i < kept; ++i) {
    if (!std::isfinite(gamma[i])) return false;
  }
  for (int i = 0; i < kept; ++i) {
    step.noalias() -= gamma[i] * dx_.col(kept_[i]);
    step.noalias() -= gamma[i] * df_.col(kept_[i]);
  }
  return true;
}

}  // namespace nmdp
