// CompletePivotingLu against Eigen::FullPivLU: the same pivots (so the same factors), the same rank
// on rank-deficient matrices, and solves of one and of many right-hand sides.
#include "solver/complete_pivoting_lu.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <limits>
#include <random>

namespace nmdp {
namespace {

Eigen::MatrixXd randomMatrix(std::mt19937& rng, int rows, int cols) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd a(rows, cols);
  for (Eigen::Index j = 0; j < a.cols(); ++j)
    for (Eigen::Index i = 0; i < a.rows(); ++i) a(i, j) = normal(rng);
  return a;
}

// P A Q from the recorded swaps.
Eigen::MatrixXd permuted(const CompletePivotingLu& lu, Eigen::MatrixXd a) {
  for (int k = 0; k < lu.size(); ++k) {
    a.row(k).swap(a.row(lu.rowSwaps()[k]));
    a.col(k).swap(a.col(lu.columnSwaps()[k]));
  }
  return a;
}

TEST(CompletePivotingLu, FactorsAsFullPivLuAndSolves) {
  std::mt19937 rng(11);
  for (int n : {1, 2, 5, 18, 40}) {
    // Badly scaled rows and columns, as ∂G/∂θ has (a base with 10 kg, a toe with 0.1 kg).
    Eigen::MatrixXd a = randomMatrix(rng, n, n);
    for (int i = 0; i < n; ++i) {
      a.row(i) *= std::pow(10.0, (i % 5) - 2);
      a.col((i * 7) % n) *= std::pow(10.0, (i % 3) - 1);
    }
    CompletePivotingLu lu;
    lu.resize(n);
    const Eigen::FullPivLU<Eigen::MatrixXd> eigen(a);
    EXPECT_EQ(lu.compute(a), n);
    EXPECT_EQ(lu.rank(), eigen.rank());
    const Eigen::MatrixXd& f = lu.matrixLU();
    EXPECT_LT((f - eigen.matrixLU()).norm(), 1e-13 * eigen.matrixLU().norm()) << "n = " << n << ": other pivots";
    const Eigen::MatrixXd L = f.triangularView<Eigen::UnitLower>();
    const Eigen::MatrixXd U = f.triangularView<Eigen::Upper>();
    EXPECT_LT((L * U - permuted(lu, a)).norm(), 1e-14 * a.norm()) << "n = " << n;

    const Eigen::VectorXd b = randomMatrix(rng, n, 1);
    Eigen::VectorXd x = b;
    lu.solveInPlace(x);
    EXPECT_LT((a * x - b).norm(), 1e-12 * a.norm() * x.norm()) << "n = " << n;
    EXPECT_LT((x - eigen.solve(b)).norm(), 1e-10 * x.norm()) << "n = " << n;

    const Eigen::MatrixXd B = randomMatrix(rng, n, 32);
    Eigen::MatrixXd X = B;
    lu.solveInPlace(X);
    EXPECT_LT((a * X - B).norm(), 1e-12 * a.norm() * X.norm()) << "n = " << n;
    for (Eigen::Index j = 0; j < B.cols(); ++j) {  // each column as a single right-hand side
      Eigen::VectorXd xj = B.col(j);
      lu.solveInPlace(xj);
      EXPECT_LT((X.col(j) - xj).norm(), 1e-13 * xj.norm()) << "n = " << n << ", column " << j;
    }
  }
}

TEST(CompletePivotingLu, RevealsTheRankAsFullPivLu) {
  std::mt19937 rng(12);
  const int n = 18;
  CompletePivotingLu lu;
  lu.resize(n);
  for (int r : {0, 1, 5, 17}) {
    const Eigen::MatrixXd a = randomMatrix(rng, n, r) * randomMatrix(rng, r, n);
    EXPECT_EQ(lu.compute(a), r);
    EXPECT_EQ(lu.rank(), Eigen::FullPivLU<Eigen::MatrixXd>(a).rank());
  }
  // A repeated row: rank n − 1, however small the round-off of its elimination.
  Eigen::MatrixXd a = randomMatrix(rng, n, n);
  a.row(7) = 3.0 * a.row(2);
  EXPECT_EQ(lu.compute(a), n - 1);
}

TEST(CompletePivotingLu, ANonFiniteEntryIsNotFullRank) {
  // The projection treats a rank-deficient ∂G/∂θ as divergence; a NaN or infinity must end there
  // rather than in a solve that returns NaN as if it were a step.
  std::mt19937 rng(13);
  const int n = 18;
  CompletePivotingLu lu;
  lu.resize(n);
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()})
    for (int where : {0, 77, 323}) {
      Eigen::MatrixXd a = randomMatrix(rng, n, n);
      a(where % n, where / n) = bad;
      EXPECT_LT(lu.compute(a), n) << bad << " at " << where;
    }
}

TEST(CompletePivotingLu, BreaksTiesAsFullPivLu) {
  // Equal candidates everywhere: the first in column-major order is the pivot.
  const int n = 6;
  CompletePivotingLu lu;
  lu.resize(n);
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n);
  a.col(0).swap(a.col(3));
  a(4, 1) = -1.0;  // as large in magnitude as the diagonal
  ASSERT_EQ(lu.compute(a), n);
  const Eigen::FullPivLU<Eigen::MatrixXd> eigen(a);
  EXPECT_EQ(lu.matrixLU(), eigen.matrixLU());
  EXPECT_EQ(Eigen::MatrixXd(permuted(lu, a)), Eigen::MatrixXd(eigen.permutationP() * a * eigen.permutationQ()));
}

}  // namespace
}  // namespace nmdp
