#include "solver/local_error.hpp"

#include <algorithm>
#include <cmath>


namespace nmdp {

LocalError::LocalError(const Model& model) {
  error_.setZero(model.nq);
  displacement_.setZero(model.nq);
  product_.setZero(model.nq);
  sqrt_mass_ = std::sqrt(std::max(model.total_mass, 0.0));
}

double LocalError::normalized(const LocalErrorStep& s, const Eigen::MatrixXd& H, double accuracy) {
  const double h = s.h;
  if (s.order == 2) {
    const double omega = h / s.h_prev;
    const double C = (1 + omega) * (1 + omega) / (6 * omega * (1 + 2 * omega));
    // 2 v[t_{n+1}, t_n, t_{n−1}] = 2 ((v_{n+1} − v_n)/h − (v_n − v_{n−1})/h_prev) / (h + h_prev)
    const double scale = C * h * h * h * 2.0 / (h + s.h_prev);
    error_ = scale * ((*s.v_after - *s.v_before) / h - (*s.v_before - *s.v_prev) / s.h_prev);
  } else {
    error_ = 0.5 * h * (*s.v_after - *s.v_before);
  }
  displacement_ = *s.q_after - *s.q_before;
  product_.noalias() = H * error_;
  const double e = std::sqrt(std::max(error_.dot(product_), 0.0));
  product_.noalias() = H * displacement_;
  const double d = std::sqrt(std::max(displacement_.dot(product_), 0.0));
  return e / (accuracy * (d + sqrt_mass_ * kFloorLength));
}

double LocalError::nextStep(double h, double err, int order) {
  constexpr double kSafety = 0.9, kLeast = 0.2, kMost = 2.0;
  if (!(err > 0)) return kMost * h;
  const double factor = kSafety * std::pow(err, -1.0 / (order + 1));
  return h * std::clamp(factor, kLeast, kMost);
}

}  // namespace nmdp
