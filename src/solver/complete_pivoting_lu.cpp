#include "solver/complete_pivoting_lu.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define NMDP_LU_AVX2 1
#endif

namespace nmdp {
namespace {

// The kernels below compute exactly what plain scalar loops compute: the same multiply-subtract
// per element, rounded once with FMA (GCC contracts a scalar x − v·f, as in solveColumn, into one;
// the AVX path does it explicitly), and maxima of magnitudes, which are exact in any order. A NaN
// is skipped by the maxima in both, as std::max(largest, NaN) keeps largest. The AVX path does
// whole 4-wide chunks and leaves the last count mod 4 entries to the scalar loop: masked stores
// take fewer instructions, but loads from them cannot be forwarded and stall compute().
#ifdef NMDP_LU_AVX2
__m256d magnitude(__m256d x) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), x); }

// max(|x|, largest), keeping largest when x is NaN (the second operand wins on NaN).
__m256d maxMagnitude(__m256d x, __m256d largest) { return _mm256_max_pd(magnitude(x), largest); }

double horizontalMax(__m256d v) {
  const __m128d half = _mm_max_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_max_sd(half, _mm_unpackhi_pd(half, half)));
}
#endif

// x − v·f, rounded once where the AVX path is compiled, as it is there.
inline double subtractProduct(double x, double v, double f) {
#ifdef NMDP_LU_AVX2
  return std::fma(-v, f, x);
#else
  return x - v * f;
#endif
}

// y[i] = x[i] for i < count; returns the largest |x[i]|.
double copyAndMeasure(const double* x, double* y, int count) {
  int i = 0;
  double largest = 0.0;
#ifdef NMDP_LU_AVX2
  __m256d chunk_largest = _mm256_setzero_pd();
  for (; i + 4 <= count; i += 4) {
    const __m256d xi = _mm256_loadu_pd(x + i);
    _mm256_storeu_pd(y + i, xi);
    chunk_largest = maxMagnitude(xi, chunk_largest);
  }
  largest = horizontalMax(chunk_largest);
#endif
  for (; i < count; ++i) {
    y[i] = x[i];
    largest = std::max(largest, std::abs(x[i]));
  }
  return largest;
}

// Swaps x[i] and y[i] for i < count.
void swapEntries(double* x, double* y, int count) {
  int i = 0;
#ifdef NMDP_LU_AVX2
  for (; i + 4 <= count; i += 4) {
    const __m256d xi = _mm256_loadu_pd(x + i);
    _mm256_storeu_pd(x + i, _mm256_loadu_pd(y + i));
    _mm256_storeu_pd(y + i, xi);
  }
#endif
  std::swap_ranges(x + i, x + count, y + i);
}

// x[i] -= v[i]·f for i < count; returns the largest |x[i]| afterwards.
double subtractScaledAndMeasure(double* x, const double* v, double f, int count) {
  int i = 0;
  double largest = 0.0;
#ifdef NMDP_LU_AVX2
  const __m256d scale = _mm256_set1_pd(f);
  __m256d chunk_largest = _mm256_setzero_pd();
  for (; i + 4 <= count; i += 4) {
    const __m256d xi = _mm256_fnmadd_pd(_mm256_loadu_pd(v + i), scale, _mm256_loadu_pd(x + i));
    _mm256_storeu_pd(x + i, xi);
    chunk_largest = maxMagnitude(xi, chunk_largest);
  }
  largest = horizontalMax(chunk_largest);
#endif
  for (; i < count; ++i) {
    x[i] = subtractProduct(x[i], v[i], f);
    largest = std::max(largest, std::abs(x[i]));
  }
  return largest;
}

// Rows of `width` right-hand sides: y[c] -= x[c]·f and y[c] /= d.
template <int width>
[[gnu::always_inline]] inline void subtractScaledRow(double* y, const double* x, double f) {
#ifdef NMDP_LU_AVX2
  static_assert(width % 4 == 0, "whole AVX registers");
  const __m256d scale = _mm256_set1_pd(f);
  for (int c = 0; c < width; c += 4)
    _mm256_storeu_pd(y + c, _mm256_fnmadd_pd(_mm256_loadu_pd(x + c), scale, _mm256_loadu_pd(y + c)));
#else
  for (int c = 0; c < width; ++c) y[c] -= x[c] * f;
#endif
}

template <int width>
[[gnu::always_inline]] inline void divideRow(double* y, double d) {
#ifdef NMDP_LU_AVX2
  const __m256d divisor = _mm256_set1_pd(d);
  for (int c = 0; c < width; c += 4) _mm256_storeu_pd(y + c, _mm256_div_pd(_mm256_loadu_pd(y + c), divisor));
#else
  for (int c = 0; c < width; ++c) y[c] /= d;
#endif
}

// x[i] /= d for i < count.
void divide(double* x, double d, int count) {
  int i = 0;
#ifdef NMDP_LU_AVX2
  const __m256d divisor = _mm256_set1_pd(d);
  for (; i + 4 <= count; i += 4) _mm256_storeu_pd(x + i, _mm256_div_pd(_mm256_loadu_pd(x + i), divisor));
#endif
  for (; i < count; ++i) x[i] /= d;
}

// The first i < count with |x[i]| == magnitude (> 0), or count − 1 if there is none.
int firstOfMagnitude(const double* x, double magnitude_sought, int count) {
#ifdef NMDP_LU_AVX2
  const __m256d sought = _mm256_set1_pd(magnitude_sought);
  int i = 0;
  for (; i + 4 <= count; i += 4) {
    const int equal = _mm256_movemask_pd(_mm256_cmp_pd(magnitude(_mm256_loadu_pd(x + i)), sought, _CMP_EQ_OQ));
    if (equal != 0) return i + __builtin_ctz(static_cast<unsigned>(equal));
  }
#else
  int i = 0;
#endif
  while (i < count - 1 && std::abs(x[i]) != magnitude_sought) ++i;
  return i;
}

}  // namespace

void CompletePivotingLu::resize(int n) {
  n_ = n;
  rank_ = 0;
  lu_.setZero(n, n);
  row_swap_.assign(n, 0);
  column_swap_.assign(n, 0);
  column_max_.setZero(n);
  row_order_.assign(n, 0);
  column_order_.assign(n, 0);
  block_.setZero(kWideBlock * n);
}

int CompletePivotingLu::compute(const Eigen::MatrixXd& a) {
  eigen_assert(a.rows() == n_ && a.cols() == n_);
  const int n = n_;
  double* m = lu_.data();
  const auto col = [&](int j) { return m + static_cast<std::ptrdiff_t>(j) * n; };
  // The largest remaining entry is in the first column holding it (then its first row): the
  // search over columns is carried along with the measuring of each column.
  int pivot_col = 0;
  for (int j = 0; j < n; ++j) {
    column_max_[j] = copyAndMeasure(a.data() + static_cast<std::ptrdiff_t>(j) * n, col(j), n);
    if (column_max_[j] > column_max_[pivot_col]) pivot_col = j;
  }
  double max_pivot = 0.0;
  int nonzero_pivots = n;
  for (int k = 0; k < n; ++k) {
    const double biggest = column_max_[pivot_col];
    if (!(biggest > 0.0)) {  // the rest is zero (or NaN: no pivot, rank stops here)
      nonzero_pivots = k;
      for (int i = k; i < n; ++i) row_swap_[i] = column_swap_[i] = i;
      break;
    }
    const int pivot_row = k + firstOfMagnitude(col(pivot_col) + k, biggest, n - k);
    max_pivot = std::max(max_pivot, biggest);
    row_swap_[k] = pivot_row;
    column_swap_[k] = pivot_col;
    // The column swap first, then the row swap: they commute. The row swap is a pass of its own:
    // fused into the elimination, its scalar stores would be reloaded at once by the vector loads,
    // which cannot be forwarded from them and stall (the instructions saved cost 2× the time).
    if (pivot_col != k) {
      swapEntries(col(k), col(pivot_col), n);
      std::swap(column_max_[k], column_max_[pivot_col]);
    }
    if (pivot_row != k)
      for (int j = 0; j < n; ++j) std::swap(col(j)[k], col(j)[pivot_row]);
    double* l = col(k);
    divide(l + k + 1, l[k], n - k - 1);
    // Eliminate and measure each trailing column for the next pivot in the same pass.
    for (int j = k + 1; j < n; ++j) {
      double* c = col(j);
      column_max_[j] = subtractScaledAndMeasure(c + k + 1, l + k + 1, c[k], n - k - 1);
    }
    pivot_col = k + 1;
    for (int j = k + 2; j < n; ++j)
      if (column_max_[j] > column_max_[pivot_col]) pivot_col = j;
  }
  const double threshold = n * std::numeric_limits<double>::epsilon() * max_pivot;
  rank_ = 0;
  for (int i = 0; i < nonzero_pivots; ++i) rank_ += std::abs(lu_(i, i)) > threshold;
  return rank_;
}

template <int width>
void CompletePivotingLu::substituteRows(double* t) const {
  // t ← U⁻¹ L⁻¹ t, t with n rows of `width`.
  const int n = n_;
  const double* m = lu_.data();
  const auto row = [&](int i) { return t + static_cast<std::ptrdiff_t>(i) * width; };
  for (int k = 0; k < n; ++k) {
    const double* l = m + static_cast<std::ptrdiff_t>(k) * n;
    for (int i = k + 1; i < n; ++i) subtractScaledRow<width>(row(i), row(k), l[i]);
  }
  for (int k = n - 1; k >= 0; --k) {
    const double* u = m + static_cast<std::ptrdiff_t>(k) * n;
    divideRow<width>(row(k), u[k]);
    for (int i = 0; i < k; ++i) subtractScaledRow<width>(row(i), row(k), u[i]);
  }
}

template <int width>
void CompletePivotingLu::solveBlock(double* x, std::ptrdiff_t stride, int columns) {
  // Rows of P x into block_, substitution, rows of the result into x through Q. The columns of
  // block_ past `columns` hold whatever earlier blocks left: computed along, never copied back.
  const int n = n_;
  double* t = block_.data();
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < columns; ++c) t[i * width + c] = x[c * stride + row_order_[i]];
  substituteRows<width>(t);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < columns; ++c) x[c * stride + i] = t[column_order_[i] * width + c];
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

void CompletePivotingLu::solveTransposeInPlace(Eigen::Ref<Eigen::VectorXd> v) const {
  // A = Pᵀ L U Qᵀ, so x ← Pᵀ L⁻ᵀ U⁻ᵀ Qᵀ x: the steps of solveColumn transposed, in reverse order.
  const int n = n_;
  const double* m = lu_.data();
  double* x = v.data();
  for (int k = 0; k < n; ++k)
    if (column_swap_[k] != k) std::swap(x[k], x[column_swap_[k]]);
  for (int k = 0; k < n; ++k) {  // Uᵀ is lower triangular; column k of U is row k of Uᵀ
    const double* u = m + static_cast<std::ptrdiff_t>(k) * n;
    double s = x[k];
    for (int i = 0; i < k; ++i) s -= u[i] * x[i];
    x[k] = s / u[k];
  }
  for (int k = n - 1; k >= 0; --k) {  // Lᵀ is unit upper triangular
    const double* l = m + static_cast<std::ptrdiff_t>(k) * n;
    double s = x[k];
    for (int i = k + 1; i < n; ++i) s -= l[i] * x[i];
    x[k] = s;
  }
  for (int k = n - 1; k >= 0; --k)
    if (row_swap_[k] != k) std::swap(x[k], x[row_swap_[k]]);
}

void CompletePivotingLu::solveInPlace(Eigen::Ref<Eigen::MatrixXd> x) {
  if (x.cols() == 1) return solveColumn(x.data());
  // Several columns: blocks of them are gathered, P applied on the way, into rows of contiguous
  // entries, where each step of a substitution is one multiple of a row subtracted from another;
  // Q is applied on the way back. Per element, the operations are those of solveColumn.
  const int n = n_;
  for (int i = 0; i < n; ++i) row_order_[i] = i;
  for (int k = 0; k < n; ++k) std::swap(row_order_[k], row_order_[row_swap_[k]]);
  for (int i = 0; i < n; ++i) column_order_[i] = i;
  for (int k = n - 1; k >= 0; --k) std::swap(column_order_[k], column_order_[column_swap_[k]]);
  const std::ptrdiff_t stride = x.outerStride();
  Eigen::Index j = 0;
  // A constant count for whole blocks, for unrolled copies; the widest rows have the least
  // overhead per entry.
  for (; j + kWideBlock <= x.cols(); j += kWideBlock) solveBlock<kWideBlock>(x.col(j).data(), stride, kWideBlock);
  for (; j + kNarrowBlock <= x.cols(); j += kNarrowBlock)
    solveBlock<kNarrowBlock>(x.col(j).data(), stride, kNarrowBlock);
  if (j < x.cols()) solveBlock<kNarrowBlock>(x.col(j).data(), stride, static_cast<int>(x.cols() - j));
}

}  // namespace nmdp
