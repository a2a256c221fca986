// Random problems for the capped-simplex QP of the PGM (solver/capped_simplex_qp.hpp): feasible
// points of every kind and gradients that push toward the caps, the bounds or the interior, drawn
// alike by the tests (test_capped_simplex_qp.cpp) and the benchmark (bench_solver_qp.cpp).
#pragma once
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "random_values.hpp"

namespace nmdp::test {

struct QpProblem {
  std::vector<int> sizes;
  Eigen::MatrixXd Q;
  double beta = 1.0;
  Eigen::VectorXd g, w;
  int n() const { return static_cast<int>(g.size()); }
};

inline double logUniform(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
  return std::exp(u(rng));
}

// A random feasible w for one contact: zero, a vertex, on the cap, interior, or sparse interior.
inline void randomFeasibleBlock(std::mt19937& rng, Eigen::Ref<Eigen::VectorXd> wc) {
  std::uniform_int_distribution<int> kind(0, 4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int K = static_cast<int>(wc.size());
  wc.setZero();
  switch (kind(rng)) {
    case 0: break;
    case 1: wc[std::uniform_int_distribution<int>(0, K - 1)(rng)] = 1.0; break;
    case 2:
      for (int i = 0; i < K; ++i) wc[i] = u(rng);
      wc /= wc.sum();
      break;
    case 3:
      for (int i = 0; i < K; ++i) wc[i] = u(rng);
      wc *= u(rng) / wc.sum();
      break;
    default:
      for (int i = 0; i < K; ++i) wc[i] = u(rng) < 0.5 ? 0.0 : u(rng);
      if (wc.sum() > 0) wc *= u(rng) / wc.sum();
  }
}

inline QpProblem randomProblem(std::mt19937& rng, const std::vector<int>& sizes, double beta_lo, double beta_hi) {
  QpProblem p;
  p.sizes = sizes;
  int n = 0;
  for (int K : sizes) n += K;
  std::uniform_int_distribution<int> rows(1, n + 6);
  const int m = rows(rng);
  const Eigen::MatrixXd A = randomVector(rng, m * n, 1.0).reshaped(m, n);
  p.Q = logUniform(rng, 1e-2, 1e2) * A.transpose() * A;
  p.Q = 0.5 * (p.Q + p.Q.transpose()).eval();
  p.beta = logUniform(rng, beta_lo, beta_hi);
  // gradient: random, with a shift that pushes toward the caps (negative), the bounds (positive) or
  // a small gradient relative to the curvature (interior solutions)
  const double gscale = logUniform(rng, 1e-3, 1e3);
  p.g = randomVector(rng, n, gscale);
  std::uniform_int_distribution<int> shift(0, 3);
  switch (shift(rng)) {
    case 0: p.g.array() -= 2 * gscale; break;
    case 1: p.g.array() += 0.5 * gscale; break;
    case 2: p.g *= 1e-6 * (p.beta + 1.0) / gscale; break;
    default: break;
  }
  p.w.setZero(n);
  int offset = 0;
  for (int K : sizes) {
    randomFeasibleBlock(rng, p.w.segment(offset, K));
    offset += K;
  }
  return p;
}

}  // namespace nmdp::test
