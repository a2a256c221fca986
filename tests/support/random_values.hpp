// Random test values without GoogleTest, so that bench/ can draw the same inputs as the tests.
#pragma once
#include <Eigen/Dense>
#include <random>

namespace nmdp::test {

// n values uniform in [−scale, scale].
inline Eigen::VectorXd randomVector(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

}  // namespace nmdp::test
