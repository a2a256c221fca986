// CompletePivotingLu against Eigen::FullPivLU: the same pivots (so the same factors), the same rank
// on rank-deficient matrices, and solves of one and of many right-hand sides and with Aᵀ; and against plain
// loops of the same algorithm, bit for bit.
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

    // The adjoint solve: Aᵀ y = b, against FullPivLU's factorization of Aᵀ.
    Eigen::VectorXd y = b;
    lu.solveTransposeInPlace(y);
    EXPECT_LT((a.transpose() * y - b).norm(), 1e-12 * a.norm() * y.norm()) << "n = " << n;
    const Eigen::VectorXd y_eigen = Eigen::FullPivLU<Eigen::MatrixXd>(a.transpose()).solve(b);
    EXPECT_LT((y - y_eigen).norm(), 1e-10 * y.norm()) << "n = " << n;

    const Eigen::MatrixXd B = randomMatrix(rng, n, 32);
    Eigen::MatrixXd X = B;
    lu.solveInPlace(X);
    EXPECT_LT((a * X - B).norm(), 1e-12 * a.norm() * X.norm()) << "n = " << n;
    for (Eigen::Index j = 0; j < B.cols(); ++j) {  // each column as a single right-hand side
      Eigen::VectorXd xj = B.col(j);
      lu.solveInPlace(xj);
      EXPECT_EQ(X.col(j), xj) << "n = " << n << ", column " << j;
    }
  }
}

// The algorithm as plain loops: a full search for each pivot, row and column swaps, elimination,
// substitutions one column at a time. CompletePivotingLu fuses and vectorizes these steps (with
// AVX2 where available, on blocks of right-hand sides) without changing any operation on an entry.
struct PlainLu {
  explicit PlainLu(const Eigen::MatrixXd& a) : lu(a), row_swap(a.rows()), column_swap(a.rows()) {
    const int n = static_cast<int>(a.rows());
    double max_pivot = 0.0;
    int nonzero_pivots = n;
    for (int k = 0; k < n; ++k) {
      int pivot_row = k, pivot_col = k;
      double biggest = 0.0;
      for (int j = k; j < n; ++j)
        for (int i = k; i < n; ++i)
          if (std::abs(lu(i, j)) > biggest) biggest = std::abs(lu(pivot_row = i, pivot_col = j));
      if (!(biggest > 0.0)) {
        nonzero_pivots = k;
        for (int i = k; i < n; ++i) row_swap[i] = column_swap[i] = i;
        break;
      }
      max_pivot = std::max(max_pivot, biggest);
      row_swap[k] = pivot_row;
      column_swap[k] = pivot_col;
      lu.row(k).swap(lu.row(pivot_row));
      lu.col(k).swap(lu.col(pivot_col));
      for (int i = k + 1; i < n; ++i) lu(i, k) /= lu(k, k);
      for (int j = k + 1; j < n; ++j)
        for (int i = k + 1; i < n; ++i) lu(i, j) -= lu(i, k) * lu(k, j);
    }
    for (int i = 0; i < nonzero_pivots; ++i)
      rank += std::abs(lu(i, i)) > n * std::numeric_limits<double>::epsilon() * max_pivot;
  }

  Eigen::VectorXd solve(Eigen::VectorXd x) const {
    const int n = static_cast<int>(x.size());
    for (int k = 0; k < n; ++k) std::swap(x[k], x[row_swap[k]]);
    for (int k = 0; k < n; ++k)
      for (int i = k + 1; i < n; ++i) x[i] -= lu(i, k) * x[k];
    for (int k = n - 1; k >= 0; --k) {
      x[k] /= lu(k, k);
      for (int i = 0; i < k; ++i) x[i] -= lu(i, k) * x[k];
    }
    for (int k = n - 1; k >= 0; --k) std::swap(x[k], x[column_swap[k]]);
    return x;
  }

  Eigen::MatrixXd lu;
  std::vector<int> row_swap, column_swap;
  int rank = 0;
};

TEST(CompletePivotingLu, MatchesPlainLoopsBitForBit) {
  std::mt19937 rng(14);
  std::uniform_int_distribution<int> small(-2, 2);
  for (int n = 1; n <= 40; ++n) {
    CompletePivotingLu lu;
    lu.resize(n);
    const int r = n / 2;
    Eigen::MatrixXd ties(n, n);  // small integers: equal candidates for most pivots
    for (Eigen::Index i = 0; i < ties.size(); ++i) ties(i) = small(rng);
    for (const Eigen::MatrixXd& a : {randomMatrix(rng, n, n), Eigen::MatrixXd(randomMatrix(rng, n, r) * randomMatrix(rng, r, n)), ties}) {
      const PlainLu plain(a);
      EXPECT_EQ(lu.compute(a), plain.rank) << "n = " << n;
      EXPECT_EQ(lu.rowSwaps(), plain.row_swap) << "n = " << n;
      EXPECT_EQ(lu.columnSwaps(), plain.column_swap) << "n = " << n;
      EXPECT_EQ(lu.matrixLU(), plain.lu) << "n = " << n;
      if (plain.rank < n) continue;
      // One column, a partial block, whole blocks of both widths; inside a taller matrix.
      for (int m : {1, 3, 8, 13, 24, 37}) {
        const Eigen::MatrixXd B = randomMatrix(rng, n, m);
        Eigen::MatrixXd taller = randomMatrix(rng, n + 2, m);
        taller.topRows(n) = B;
        const Eigen::MatrixXd below = taller.bottomRows(2);
        lu.solveInPlace(taller.topRows(n));
        EXPECT_EQ(taller.bottomRows(2), below) << "n = " << n << ", m = " << m;
        for (int j = 0; j < m; ++j)
          EXPECT_EQ(taller.col(j).head(n), plain.solve(B.col(j))) << "n = " << n << ", m = " << m << ", column " << j;
      }
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
