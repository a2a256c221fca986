// AndersonAcceleration on linear chord iterations x ← x − M⁻¹(A x − b), the projection's situation:
// M is A with a few directions out of date, so plain steps converge linearly and slowly.
#include "solver/anderson_acceleration.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <random>

namespace nmdp {
namespace {

struct ChordProblem {
  Eigen::MatrixXd A, M_inverse;
  Eigen::VectorXd b, solution;
};

// A SPD; M = A − σ Σ u_i u_iᵀ with `stale` random directions, so I − M⁻¹A has rank `stale`.
ChordProblem chordProblem(int n, int stale, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd R(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) R(i, j) = normal(rng);
  ChordProblem p;
  p.A = R * R.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd M = p.A;
  for (int k = 0; k < stale; ++k) {
    Eigen::VectorXd u(n);
    for (int i = 0; i < n; ++i) u[i] = normal(rng);
    M -= sigma * u * u.transpose() / u.squaredNorm();
  }
  p.M_inverse = M.inverse();
  p.b.resize(n);
  for (int i = 0; i < n; ++i) p.b[i] = normal(rng);
  p.solution = p.A.ldlt().solve(p.b);
  return p;
}

// Iterations until ‖x − x*‖∞ < 1e-12 (at most `limit`), with or without acceleration.
int iterationsToConverge(const ChordProblem& p, AndersonAcceleration* anderson, int limit) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(p.b.size());
  Eigen::VectorXd step;
  for (int it = 0; it < limit; ++it) {
    if ((x - p.solution).lpNorm<Eigen::Infinity>() < 1e-12) return it;
    step = -p.M_inverse * (p.A * x - p.b);
    if (anderson) anderson->accelerate(x, step);
    x += step;
    EXPECT_TRUE(x.allFinite());
  }
  return limit;
}

TEST(AndersonAcceleration, RemovesTheStaleDirectionsOfAChordIteration) {
  for (int stale : {1, 2, 3}) {
    const ChordProblem p = chordProblem(18, stale, 0.5 * 18, 7 + stale);
    const int plain = iterationsToConverge(p, nullptr, 500);
    AndersonAcceleration anderson;
    anderson.resize(18, 3);
    const int accelerated = iterationsToConverge(p, &anderson, 500);
    // I − M⁻¹A has rank `stale`: with that many pairs the multisecant update is exact (GMRES-like),
    // so it converges in a few steps more than `stale`; the plain chord steps take tens.
    EXPECT_GT(plain, 15) << stale;
    EXPECT_LE(accelerated, stale + 3) << stale << " (plain: " << plain << ")";
  }
}

TEST(AndersonAcceleration, LeavesTheFirstStepAfterAResetAlone) {
  AndersonAcceleration anderson;
  anderson.resize(3, 2);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3), step(3), first(3), second(3);
  first << 1.0, 2.0, 3.0;
  second << 0.5, 1.0, 1.0;
  step = first;
  EXPECT_FALSE(anderson.accelerate(x, step));
  EXPECT_EQ(step, first);
  x = step;
  step = second;
  EXPECT_TRUE(anderson.accelerate(x, step));
  EXPECT_NE(step, second);
  anderson.reset();
  step = second;
  EXPECT_FALSE(anderson.accelerate(x, step));
  EXPECT_EQ(step, second);
}

TEST(AndersonAcceleration, WithoutMemoryChangesNothing) {
  AndersonAcceleration anderson;
  anderson.resize(2, 0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2), step = Eigen::VectorXd::Ones(2);
  for (int it = 0; it < 3; ++it) {
    EXPECT_FALSE(anderson.accelerate(x, step));
    EXPECT_EQ(step, Eigen::VectorXd::Ones(2));
    x += step;
  }
}

// One slow mode: plain steps shrink by r each time, every Δf is parallel to the first, and the
// first accelerated step lands on the fixed point (Aitken); later, parallel columns are dropped
// instead of making the least-squares problem singular.
TEST(AndersonAcceleration, OneSlowModeConvergesInOneAcceleratedStepAndParallelHistoryStaysFinite) {
  const double r = 0.9;
  Eigen::VectorXd target(2), direction(2);
  target << 3.0, -1.0;
  direction << 1.0 / std::sqrt(5.0), 2.0 / std::sqrt(5.0);
  AndersonAcceleration anderson;
  anderson.resize(2, 3);
  Eigen::VectorXd x = target + 5.0 * direction;
  Eigen::VectorXd step(2);
  for (int it = 0; it < 5; ++it) {
    step = -(1.0 - r) * (x - target);  // the error shrinks by r per plain step
    const bool accelerated = anderson.accelerate(x, step);
    EXPECT_EQ(accelerated, it > 0) << it;
    x += step;
    ASSERT_TRUE(x.allFinite()) << it;
    if (it >= 1) {
      EXPECT_LT((x - target).norm(), 1e-12) << it;
    }
  }
}

}  // namespace
}  // namespace nmdp
