#include "solver/complete_pivoting_lu.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace nmdp {

void CompletePivotingLu::resize(int n) {
  n_ = n;
  rank_ = 0;
  lu_.setZero(n, n);
  row_swap_.assign(n, 0);
  column_swap_.assign(n, 0);
  column_max_.setZero(n);
}

int CompletePivotingLu::compute(const Eigen::MatrixXd& a) {
  const int n = n_;
  lu_ = a;
  double* m = lu_.data();
  const auto col = [&](int j) { return m + static_cast<std::ptrdiff_t>(j) * n; };
  for (int j = 0; j < n; ++j) {
    double largest = 0.0;
    const double* c = col(j);
    for (int i = 0; i < n; ++i) largest = std::max(largest, std::abs(c[i]));
    column_max_[j] = largest;
  }
  double max_pivot = 0.0;
  int nonzero_pivots = n;
  for (int k = 0; k < n; ++k) {
    // The largest remaining entry: the first column holding it, then its first row.
    int pivot_col = k;
    for (int j = k + 1; j < n; ++j)
      if (column_max_[j] > column_max_[pivot_col]) pivot_col = j;
    const double biggest = column_max_[pivot_col];
    if (!(biggest > 0.0)) {  // the rest is zero (or NaN: no pivot, rank stops here)
      nonzero_pivots = k;
      for (int i = k; i < n; ++i) row_swap_[i] = column_swap_[i] = i;
      break;
    }
    int pivot_row = k;
    {
      const double* c = col(pivot_col);
      while (pivot_row < n - 1 && std::abs(c[pivot_row]) != biggest) ++pivot_row;
    }
    max_pivot = std::max(max_pivot, biggest);
    row_swap_[k] = pivot_row;
    column_swap_[k] = pivot_col;
    if (pivot_row != k)
      for (int j = 0; j < n; ++j) std::swap(col(j)[k], col(j)[pivot_row]);
    if (pivot_col != k) {
      std::swap_ranges(col(k), col(k) + n, col(pivot_col));
      std::swap(column_max_[k], column_max_[pivot_col]);
    }
    double* l = col(k);
    const double pivot = l[k];
    for (int i = k + 1; i < n; ++i) l[i] /= pivot;
    // Eliminate and measure each trailing column for the next pivot in the same pass.
    for (int j = k + 1; j < n; ++j) {
      double* c = col(j);
      const double u = c[k];
      double largest = 0.0;
      for (int i = k + 1; i < n; ++i) {
        c[i] -= l[i] * u;
        largest = std::max(largest, std::abs(c[i]));
      }
      column_max_[j] = largest;
    }
  }
  const double threshold = n * std::numeric_limits<double>::epsilon() * max_pivot;
  rank_ = 0;
  for (int i = 0; i < nonzero_pivots; ++i) rank_ += std::abs(lu_(i, i)) > threshold;
  return rank_;
}

void CompletePivotingLu::solveColumn(double* x) const {
  // x ← Q U⁻¹ L⁻¹ P x.
  const int n = n_;
  const double* m = lu_.data();
  for (int k = 0; k < n; ++k)
    if (row_swap_[k] != k) std::swap(x[k], x[row_swap_[k]]);
  for (int k = 0; k < n; ++k) {
    const double xk = x[k];
    const double* l = m + static_cast<std::ptrdiff_t>(k) * n;
    for (int i = k + 1; i < n; ++i) x[i] -= l[i] * xk;
  }
  for (int k = n - 1; k >= 0; --k) {
    const double* u = m + static_cast<std::ptrdiff_t>(k) * n;
    x[k] /= u[k];
    const double xk = x[k];
    for (int i = 0; i < k; ++i) x[i] -= u[i] * xk;
  }
  for (int k = n - 1; k >= 0; --k)
    if (column_swap_[k] != k) std::swap(x[k], x[column_swap_[k]]);
}

void CompletePivotingLu::solveInPlace(Eigen::Ref<Eigen::MatrixXd> x) {
  if (x.cols() == 1) return solveColumn(x.data());
  // The same steps as solveColumn, each on a whole row of x at once (a column of xᵀ).
  const int n = n_;
  const Eigen::Index m = x.cols();
  for (int k = 0; k < n; ++k)
    if (row_swap_[k] != k) x.row(k).swap(x.row(row_swap_[k]));
  transposed_ = x.transpose();
  const double* lu = lu_.data();
  double* t = transposed_.data();
  const auto row = [&](int i) { return t + static_cast<std::ptrdiff_t>(i) * m; };
  for (int k = 0; k < n; ++k) {
    const double* l = lu + static_cast<std::ptrdiff_t>(k) * n;
    const double* xk = row(k);
    for (int i = k + 1; i < n; ++i) {
      const double f = l[i];
      double* xi = row(i);
      for (Eigen::Index j = 0; j < m; ++j) xi[j] -= f * xk[j];
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    const double* u = lu + static_cast<std::ptrdiff_t>(k) * n;
    double* xk = row(k);
    const double d = u[k];
    for (Eigen::Index j = 0; j < m; ++j) xk[j] /= d;
    for (int i = 0; i < k; ++i) {
      const double f = u[i];
      double* xi = row(i);
      for (Eigen::Index j = 0; j < m; ++j) xi[j] -= f * xk[j];
    }
  }
  x = transposed_.transpose();
  for (int k = n - 1; k >= 0; --k)
    if (column_swap_[k] != k) x.row(k).swap(x.row(column_swap_[k]));
}


}  // namespace nmdp
