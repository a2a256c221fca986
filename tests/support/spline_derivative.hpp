// The time derivative of a HermiteSpline checked against central differences of its position,
// at the keyframes, either side of them and inside every segment.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "control/hermite_spline.hpp"

namespace nmdp::test {

inline constexpr double kDerivativeStep = 1e-6;  // s, central differences in time

inline Eigen::VectorXd positionAt(const HermiteSpline& spline, double t) {
  Eigen::VectorXd p, v;
  spline.evaluate(t, p, v);
  return p;
}
inline Eigen::VectorXd velocityAt(const HermiteSpline& spline, double t) {
  Eigen::VectorXd p, v;
  spline.evaluate(t, p, v);
  return v;
}
inline Eigen::VectorXd centralVelocity(const HermiteSpline& spline, double t) {
  return (positionAt(spline, t + kDerivativeStep) - positionAt(spline, t - kDerivativeStep)) / (2 * kDerivativeStep);
}

// Times to probe: keyframes, either side of them, and inside every segment.
inline std::vector<double> probeTimes(const std::vector<double>& knots) {
  std::vector<double> out;
  for (size_t k = 0; k < knots.size(); ++k) {
    out.push_back(knots[k]);
    out.push_back(knots[k] + 1e-4);
    out.push_back(knots[k] - 1e-4);
    if (k + 1 < knots.size())
      for (double s : {0.13, 0.5, 0.77}) out.push_back(knots[k] + s * (knots[k + 1] - knots[k]));
  }
  return out;
}

// ṗ against central differences of p. The spline is C¹ but not C² at the knots, so a difference
// straddling a knot is off by up to step·max|p̈|/2; that bound (p̈ from wider second differences
// either side) is added to the tolerance. A velocity that forgot to divide by the segment duration
// is off by O(|ṗ|), far beyond it.
inline void expectVelocityIsTimeDerivative(const HermiteSpline& spline, const std::vector<double>& times) {
  constexpr double wide = 1e-4;
  for (double t : times) {
    const Eigen::VectorXd v = velocityAt(spline, t), fd = centralVelocity(spline, t);
    double curvature = 0;
    for (double side : {-1.0, 1.0}) {
      const double c = t + side * 2 * wide;
      const Eigen::VectorXd second =
          (positionAt(spline, c + wide) - 2 * positionAt(spline, c) + positionAt(spline, c - wide)) / (wide * wide);
      curvature = std::max(curvature, second.cwiseAbs().maxCoeff());
    }
    const double tolerance = 1e-7 * std::max(1.0, fd.cwiseAbs().maxCoeff()) + kDerivativeStep * curvature;
    EXPECT_LT((v - fd).cwiseAbs().maxCoeff(), tolerance)
        << "t = " << t << "\nvelocity " << v.transpose() << "\ncentral difference " << fd.transpose();
  }
}

}  // namespace nmdp::test
