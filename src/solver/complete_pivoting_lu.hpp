// LU factorization with complete pivoting, P A Q = L U, for the small dense ∂G/∂θ of one step
// (n = 18 for a quadruped, 40 for RoboSimian). It is rank-revealing like Eigen::FullPivLU, with the
// same pivot order (the largest remaining entry, the first in column-major order on a tie) and the
// same rank rule: a pivot counts when |U_ii| > n·ε·|U_00|. It exists because FullPivLU's generic
// visitor and block updates cost ~33 k instructions on an 18 × 18 matrix, a sixth of a step: here
// the search for the next pivot is fused with the previous elimination (one pass over the trailing
// block per column instead of two), both in AVX2 where available, and the solves are plain
// substitutions. The buffers are sized by resize(); compute() and solveInPlace() allocate nothing.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace nmdp {

class CompletePivotingLu {
 public:
  void resize(int n);

  // Factors the n × n matrix a (n as given to resize()); returns the rank.
  int compute(const Eigen::MatrixXd& a);
  int rank() const { return rank_; }
  int size() const { return n_; }

  // x ← A⁻¹ x for the n rows of x (a vector or any number of columns). Only meaningful at full rank.
  // Several columns are solved together, on rows of up to kWideBlock of them copied to a buffer.
  // Each column gets the same result, bit for bit, as when solved alone.
  void solveInPlace(Eigen::Ref<Eigen::MatrixXd> x);

  // x ← A⁻ᵀ x for one vector (the adjoint solve). Only meaningful at full rank.
  void solveTransposeInPlace(Eigen::Ref<Eigen::VectorXd> x) const;

  const Eigen::MatrixXd& matrixLU() const { return lu_; }  // L below the diagonal (unit), U on and above
  // Step k swapped rows k and row_swap[k], and columns k and column_swap[k].
  const std::vector<int>& rowSwaps() const { return row_swap_; }
  const std::vector<int>& columnSwaps() const { return column_swap_; }

 private:
  void solveColumn(double* x) const;
  template <int width>
  void substituteRows(double* t) const;
  template <int width>
  void solveBlock(double* x, std::ptrdiff_t stride, int columns);

  // Right-hand sides solved together: 24 (∂G/∂θ's) while there are as many, then 8.
  static constexpr int kWideBlock = 24, kNarrowBlock = 8;

  int n_ = 0, rank_ = 0;
  Eigen::MatrixXd lu_;
  std::vector<int> row_swap_, column_swap_;
  Eigen::VectorXd column_max_;  // largest |entry| of each trailing column, from the last elimination
  std::vector<int> row_order_, column_order_;  // P and Q as gathers: row i of P x is row row_order_[i] of x
  Eigen::VectorXd block_;  // n rows of up to kWideBlock right-hand sides
};

}  // namespace nmdp
