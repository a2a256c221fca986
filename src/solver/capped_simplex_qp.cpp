#include "solver/capped_simplex_qp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/named_enum.hpp"

namespace nmdp {

// Plain loops for the small (≤ n×n, n = Σ K_c ≈ 24) dense kernels: Eigen's dynamic-size triangular
// solve, blocked Cholesky and gemv spend more on dispatch and blocking than on flops at these sizes.
// L is column-major lower triangular with leading dimension ld.
namespace {

// x ← L⁻¹x (column oriented: contiguous axpys), starting at row `first` (x[0..first) is zero).
void lowerSolve(const double* L, Eigen::Index ld, int k, double* x, int first = 0) {
  for (int j = first; j < k; ++j) {
    const double* Lj = L + j * ld;
    const double xj = x[j] / Lj[j];
    x[j] = xj;
    for (int i = j + 1; i < k; ++i) x[i] -= Lj[i] * xj;
  }
}

// x ← L⁻ᵀx (row of Lᵀ = column of L: contiguous dots).
void lowerTransposeSolve(const double* L, Eigen::Index ld, int k, double* x) {
  for (int j = k - 1; j >= 0; --j) {
    const double* Lj = L + j * ld;
    double s = x[j];
    for (int i = j + 1; i < k; ++i) s -= Lj[i] * x[i];
    x[j] = s / Lj[j];
  }
}

// In-place Cholesky of the lower triangle (right looking). Fails on a pivot ≤ 0, as llt_inplace does.
bool cholesky(double* A, Eigen::Index ld, int k) {
  for (int j = 0; j < k; ++j) {
    double* Aj = A + j * ld;
    const double d = Aj[j];
    if (d <= 0.0) return false;
    const double ljj = std::sqrt(d);
    Aj[j] = ljj;
    for (int i = j + 1; i < k; ++i) Aj[i] /= ljj;
    for (int c = j + 1; c < k; ++c) {
      double* Ac = A + c * ld;
      const double lcj = Aj[c];
      for (int i = c; i < k; ++i) Ac[i] -= Aj[i] * lcj;
    }
  }
  return true;
}

// y ← Σ_j H(:, j) x_j over the columns j with x_j ≠ 0 (the others add exact zeros).
void sparseProduct(const Eigen::MatrixXd& H, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  const int n = static_cast<int>(H.rows());
  double* out = y.data();
  for (int i = 0; i < n; ++i) out[i] = 0.0;
  for (int j = 0; j < n; ++j) {
    const double xj = x[j];
    if (xj == 0.0) continue;
    const double* Hj = H.data() + static_cast<Eigen::Index>(j) * n;
    for (int i = 0; i < n; ++i) out[i] += Hj[i] * xj;
  }
}

// Whether all entries are finite: x − x is 0 for finite x and NaN otherwise (one vectorizable sum
// instead of Eigen's element-wise allFinite, which costs more than the rest of a warm solve).
bool allFinite(const double* x, Eigen::Index size) {
  double s = 0;
  for (Eigen::Index i = 0; i < size; ++i) s += x[i] - x[i];
  return s == 0;
}

constexpr EnumName<QpStatus> kQpStatuses[] = {{QpStatus::Converged, "converged"},
                                              {QpStatus::MaxIterations, "max_iterations"},
                                              {QpStatus::NotConvex, "not_convex"},
                                              {QpStatus::InvalidInput, "invalid_input"}};

}  // namespace

const char* toString(QpStatus status) { return nameOf(kQpStatuses, status); }

void CappedSimplexQp::resize(const std::vector<int>& contact_sizes) {
  sizes_ = contact_sizes;
  const int C = static_cast<int>(sizes_.size());
  offsets_.assign(C + 1, 0);
  for (int c = 0; c < C; ++c) offsets_[c + 1] = offsets_[c] + std::max(0, sizes_[c]);
  n_ = offsets_[C];
  contact_of_.assign(n_, 0);
  for (int c = 0; c < C; ++c)
    for (int i = offsets_[c]; i < offsets_[c + 1]; ++i) contact_of_[i] = c;
  active_.at_bound.assign(n_, 0);
  active_.cap.assign(C, 0);
  H_.setZero(n_, n_);
  w_.setZero(n_);
  g_.setZero(n_);
  d_.setZero(n_);
  ds_.setZero(n_);
  z_.setZero(n_);
  zs_.setZero(n_);
  p_.setZero(n_);
  grad_.setZero(n_);
  lambda_.setZero(n_);
  nu_.setZero(C);
  free_.clear();
  free_.reserve(n_);
  capped_.clear();
  capped_.reserve(C);
  cap_index_.assign(C, -1);
  L_.setZero(n_, n_);
  U_.setZero(n_, std::max(C, 1));
  S_.setZero(std::max(C, 1), std::max(C, 1));
  y_.setZero(n_);
  t_.setZero(n_);
  xf_.setZero(n_);
  hx_.setZero(n_);
  r_.setZero(n_);
  x0_.setZero(n_);
  nuv_.setZero(std::max(C, 1));
  rc_.setZero(std::max(C, 1));
  rnu_.setZero(std::max(C, 1));
}

void CappedSimplexQp::buildLists() {
  free_.clear();
  for (int i = 0; i < n_; ++i)
    if (!active_.at_bound[i]) free_.push_back(i);
  factor_valid_ = false;
  buildCaps();
}

void CappedSimplexQp::buildCaps() {
  capped_.clear();
  const int C = contacts();
  for (int c = 0; c < C; ++c) {
    cap_index_[c] = -1;
    if (active_.cap[c]) {
      cap_index_[c] = static_cast<int>(capped_.size());
      capped_.push_back(c);
    }
  }
}

// Solves  M x + Eᵀν = r,  E x = rc  with M = H_SS = L Lᵀ (L in L_), V = L⁻¹Eᵀ (in U_) and the Schur
// complement S = E M⁻¹ Eᵀ = VᵀV (factor in S_):  y = L⁻¹r,  ν = S⁻¹(Vᵀy − rc),  x = L⁻ᵀ(y − Vν).
// Input r in y_.head(k), rc in rnu_.head(m); output x in y_.head(k), ν in nuv_.head(m).
void CappedSimplexQp::solveReduced() {
  const int k = static_cast<int>(free_.size());
  const int m = static_cast<int>(capped_.size());
  double* x = y_.data();
  lowerSolve(L_.data(), L_.outerStride(), k, x);
  if (m > 0) {
    double* nu = nuv_.data();
    for (int j = 0; j < m; ++j) {
      const double* Vj = U_.data() + j * U_.outerStride();
      double s = 0;
      for (int a = 0; a < k; ++a) s += Vj[a] * x[a];
      nu[j] = s - rnu_[j];
    }
    lowerSolve(S_.data(), S_.outerStride(), m, nu);
    lowerTransposeSolve(S_.data(), S_.outerStride(), m, nu);
    for (int j = 0; j < m; ++j) {
      const double* Vj = U_.data() + j * U_.outerStride();
      const double nj = nu[j];
      for (int a = 0; a < k; ++a) x[a] -= Vj[a] * nj;
    }
  }
  lowerTransposeSolve(L_.data(), L_.outerStride(), k, x);
}

bool CappedSimplexQp::factorWorkingSet(int k, int m) {
  if (!factor_valid_) {
    for (int b = 0; b < k; ++b)
      for (int a = b; a < k; ++a) L_(a, b) = H_(free_[a], free_[b]);
    if (!cholesky(L_.data(), L_.outerStride(), k)) return false;
    factor_valid_ = true;
    updates_since_factor_ = 0;
    ++factorizations_;
  }
  if (m == 0) return true;
  U_.topLeftCorner(k, m).setZero();
  for (int a = 0; a < k; ++a) {
    const int j = cap_index_[contact_of_[free_[a]]];
    if (j >= 0) U_(a, j) = 1.0;
  }
  for (int j = 0; j < m; ++j) {  // V = L⁻¹Eᵀ, from the column's first nonzero (zeros above stay zero)
    double* Vj = U_.data() + j * U_.outerStride();
    int first = 0;
    while (first < k && Vj[first] == 0.0) ++first;
    lowerSolve(L_.data(), L_.outerStride(), k, Vj, first);
  }
  for (int a = 0; a < m; ++a) {
    const double* Va = U_.data() + a * U_.outerStride();
    for (int b = 0; b <= a; ++b) {
      const double* Vb = U_.data() + b * U_.outerStride();
      double s = 0;
      for (int r = 0; r < k; ++r) s += Va[r] * Vb[r];
      S_(a, b) = s;
    }
  }
  return cholesky(S_.data(), S_.outerStride(), m);
}

// Displacement form d = z − w (exact Δw = 0 when g = 0, no cancellation against w):
//   H_SS d_S + Eᵀν = −g_S + H_SF w_F,   E d_S = 1 − E w_S   (fixed: d_F = −w_F),
// with one step of iterative refinement if options.refine.
void CappedSimplexQp::solveDisplacement(int k, int m) {
  bool any_fixed_nonzero = false;
  for (int i = 0; i < n_; ++i) {
    xf_[i] = active_.at_bound[i] ? w_[i] : 0.0;
    any_fixed_nonzero = any_fixed_nonzero || xf_[i] != 0.0;
  }
  if (any_fixed_nonzero) sparseProduct(H_, xf_, hx_);
  for (int a = 0; a < k; ++a) {
    const int ia = free_[a];
    const double s = any_fixed_nonzero ? hx_[ia] - g_[ia] : -g_[ia];
    r_[a] = s;
    y_[a] = s;
  }
  rc_.head(m).setOnes();
  for (int a = 0; a < k; ++a) {
    const int j = cap_index_[contact_of_[free_[a]]];
    if (j >= 0) rc_[j] -= w_[free_[a]];
  }
  rnu_.head(m) = rc_.head(m);
  solveReduced();
  for (int a = 0; a < k; ++a) x0_[a] = y_[a];
  for (int j = 0; j < m; ++j) nu_[j] = nuv_[j];  // compressed until finalize
  if (!options.refine) return;
  // residual r − H_SS x − Eᵀν, rc − E x
  xf_.setZero();
  for (int a = 0; a < k; ++a) xf_[free_[a]] = x0_[a];
  sparseProduct(H_, xf_, hx_);
  for (int a = 0; a < k; ++a) {
    const int ia = free_[a];
    double s = r_[a] - hx_[ia];
    const int j = cap_index_[contact_of_[ia]];
    if (j >= 0) s -= nu_[j];
    y_[a] = s;
  }
  rnu_.head(m) = rc_.head(m);
  for (int a = 0; a < k; ++a) {
    const int j = cap_index_[contact_of_[free_[a]]];
    if (j >= 0) rnu_[j] -= x0_[a];
  }
  solveReduced();
  for (int a = 0; a < k; ++a) x0_[a] += y_[a];
  for (int j = 0; j < m; ++j) nu_[j] += nuv_[j];
}

bool CappedSimplexQp::solveEqp() {
  const int k = static_cast<int>(free_.size());
  const int m = static_cast<int>(capped_.size());
  zs_.setZero();
  ds_ = -w_;
  if (k == 0) return m == 0;
  if (!factorWorkingSet(k, m)) return false;
  solveDisplacement(k, m);
  for (int i = 0; i < n_; ++i)
    if (active_.at_bound[i]) ds_[i] = -w_[i];
  for (int a = 0; a < k; ++a) {
    ds_[free_[a]] = x0_[a];
    zs_[free_[a]] = w_[free_[a]] + x0_[a];
  }
  return true;
}

// Variable i leaves the free set: delete its row and column from the Cholesky factor of H_SS
// (shift, then a rank-one update of the trailing block with the deleted column below the diagonal).
void CappedSimplexQp::removeFree(int i) {
  const int k = static_cast<int>(free_.size());
  int pos = 0;
  while (pos < k && free_[pos] != i) ++pos;
  if (pos == k) return;
  free_.erase(free_.begin() + pos);
  if (!factor_valid_) return;
  const int r = k - 1 - pos;  // size of the trailing block
  for (int a = 0; a < r; ++a) t_[a] = L_(pos + 1 + a, pos);
  for (int a = pos + 1; a < k; ++a) {
    for (int b = 0; b < pos; ++b) L_(a - 1, b) = L_(a, b);
    for (int b = pos + 1; b <= a; ++b) L_(a - 1, b - 1) = L_(a, b);
  }
  // rank-one update  L33 L33ᵀ + t tᵀ  in place (rows/cols pos .. pos + r − 1)
  for (int j = 0; j < r; ++j) {
    const int jj = pos + j;
    const double Ljj = L_(jj, jj);
    const double rr = std::hypot(Ljj, t_[j]);
    const double c = rr / Ljj, s = t_[j] / Ljj;
    L_(jj, jj) = rr;
    for (int a = j + 1; a < r; ++a) {
      const double l = (L_(pos + a, jj) + s * t_[a]) / c;
      t_[a] = c * t_[a] - s * l;
      L_(pos + a, jj) = l;
    }
  }
  ++updates_since_factor_;
}

// Variable i joins the free set: append a row to the factor (refactor later if it is not safe).
void CappedSimplexQp::appendFree(int i) {
  const int k = static_cast<int>(free_.size());
  free_.push_back(i);
  if (!factor_valid_) return;
  if (updates_since_factor_ >= refactor_period_) {
    factor_valid_ = false;
    return;
  }
  auto l = t_.head(k);
  for (int a = 0; a < k; ++a) l[a] = H_(free_[a], i);
  lowerSolve(L_.data(), L_.outerStride(), k, l.data());
  const double d2 = H_(i, i) - l.squaredNorm();
  if (!(d2 > 1e-8 * std::abs(H_(i, i)))) {  // (nearly) dependent: factor from scratch
    factor_valid_ = false;
    return;
  }
  L_.row(k).head(k) = l.transpose();
  L_(k, k) = std::sqrt(d2);
  ++updates_since_factor_;
}

void CappedSimplexQp::computeGradient() {
  sparseProduct(H_, d_, grad_);
  grad_ += g_;
}

bool CappedSimplexQp::warmMinimizerFeasible(double feas_tol) const {
  for (int c = 0; c < contacts(); ++c) {
    double s = 0;
    for (int i = offsets_[c]; i < offsets_[c + 1]; ++i) {
      if (zs_[i] < -feas_tol) return false;
      s += zs_[i];
    }
    if (!active_.cap[c] && s > 1.0 + feas_tol) return false;
  }
  return true;
}

bool CappedSimplexQp::startAt(const Eigen::VectorXd& w, const QpActiveSet* warm, double feas_tol, QpResult& result) {
  const int n = n_;
  const int C = contacts();
  // Feasible starting point: w, repaired.
  z_ = w;
  for (int c = 0; c < C; ++c) {
    auto zc = z_.segment(offsets_[c], sizes_[c]);
    zc = zc.cwiseMax(0.0);
    const double s = zc.sum();
    if (s > 1.0) zc /= s;
  }
  d_ = z_ - w_;
  const bool warm_ok = warm && static_cast<int>(warm->at_bound.size()) == n && static_cast<int>(warm->cap.size()) == C;
  if (warm_ok) {
    for (int i = 0; i < n; ++i) active_.at_bound[i] = warm->at_bound[i] ? 1 : 0;
    for (int c = 0; c < C; ++c) {
      bool any_free = false;
      for (int i = offsets_[c]; i < offsets_[c + 1]; ++i) any_free = any_free || !active_.at_bound[i];
      active_.cap[c] = (warm->cap[c] && any_free) ? 1 : 0;
    }
    buildLists();
    ++result.iterations;
    if (solveEqp() && warmMinimizerFeasible(feas_tol)) {
      for (int i = 0; i < n; ++i) {
        d_[i] = zs_[i] > 0.0 ? ds_[i] : -w_[i];
        z_[i] = std::max(zs_[i], 0.0);
      }
      result.warm_start_used = true;
      return true;
    }
    // keep the part of the warm set that is active at the start point
    for (int i = 0; i < n; ++i) active_.at_bound[i] = (warm->at_bound[i] && z_[i] <= 0.0) ? 1 : 0;
    factor_valid_ = false;
  } else {
    for (int i = 0; i < n; ++i) active_.at_bound[i] = z_[i] <= 0.0 ? 1 : 0;
  }
  for (int c = 0; c < C; ++c) {
    const double s = z_.segment(offsets_[c], sizes_[c]).sum();
    bool any_free = false;
    for (int i = offsets_[c]; i < offsets_[c + 1]; ++i) any_free = any_free || !active_.at_bound[i];
    const bool active_here = s >= 1.0 - 8 * std::numeric_limits<double>::epsilon() * std::max(1, sizes_[c]);
    // cold: every cap active at the start point; warm: only those of the warm set
    active_.cap[c] = (active_here && any_free && (!warm_ok || warm->cap[c])) ? 1 : 0;
  }
  return false;
}

bool CappedSimplexQp::stepTowardMinimizer(QpResult& result) {
  // ratio test along p = zs − z
  double alpha = 1.0;
  int block_bound = -1, block_cap = -1;
  for (int i : free_) {
    p_[i] = ds_[i] - d_[i];
    if (p_[i] < 0) {
      const double t = std::max(0.0, z_[i]) / -p_[i];
      if (t < alpha) {
        alpha = t;
        block_bound = i;
        block_cap = -1;
      }
    }
  }
  for (int c = 0; c < contacts(); ++c) {
    if (active_.cap[c]) continue;
    double sp = 0, sz = 0;
    for (int i = offsets_[c]; i < offsets_[c + 1]; ++i) {
      if (active_.at_bound[i]) continue;
      sp += p_[i];
      sz += z_[i];
    }
    if (sp > 0) {
      const double t = std::max(0.0, 1.0 - sz) / sp;
      if (t < alpha) {
        alpha = t;
        block_cap = c;
        block_bound = -1;
      }
    }
  }
  if (block_bound < 0 && block_cap < 0) {
    d_ = ds_;
    z_ = zs_;
    return true;
  }
  for (int i : free_) {
    d_[i] += alpha * p_[i];
    z_[i] = w_[i] + d_[i];
  }
  ++result.active_set_changes;
  if (block_bound >= 0) {
    z_[block_bound] = 0.0;
    d_[block_bound] = -w_[block_bound];
    active_.at_bound[block_bound] = 1;
    removeFree(block_bound);
  } else {
    active_.cap[block_cap] = 1;
  }
  return false;
}

bool CappedSimplexQp::dropConstraint(double dual_tol, QpResult& result) {
  computeGradient();
  double most_negative = -dual_tol;
  int drop_bound = -1, drop_cap = -1;
  for (int i = 0; i < n_; ++i) {
    if (!active_.at_bound[i]) continue;
    const int j = cap_index_[contact_of_[i]];
    const double lam = grad_[i] + (j >= 0 ? nu_[j] : 0.0);
    if (lam < most_negative) {
      most_negative = lam;
      drop_bound = i;
      drop_cap = -1;
    }
  }
  for (int j = 0; j < static_cast<int>(capped_.size()); ++j) {
    if (nu_[j] < most_negative) {
      most_negative = nu_[j];
      drop_cap = capped_[j];
      drop_bound = -1;
    }
  }
  if (drop_bound < 0 && drop_cap < 0) return false;
  ++result.active_set_changes;
  if (drop_bound >= 0) {
    active_.at_bound[drop_bound] = 0;
    appendFree(drop_bound);
  } else {
    active_.cap[drop_cap] = 0;
  }
  return true;
}

// Final multipliers over the final working set (from the last solve; recomputed if a drop happened).
void CappedSimplexQp::finishMultipliers(const QpResult& result) {
  if (result.status != QpStatus::Converged) {
    buildLists();
    if (result.status == QpStatus::NotConvex || !solveEqp()) nu_.head(capped_.size()).setZero();
    computeGradient();
  }
  const int m = static_cast<int>(capped_.size());
  for (int j = 0; j < m; ++j) nuv_[j] = nu_[j];
  nu_.setZero();
  for (int j = 0; j < m; ++j) nu_[capped_[j]] = nuv_[j];
  for (int i = 0; i < n_; ++i)
    lambda_[i] = active_.at_bound[i] ? grad_[i] + (active_.cap[contact_of_[i]] ? nu_[contact_of_[i]] : 0.0) : 0.0;
}

QpResult CappedSimplexQp::solve(const Eigen::MatrixXd& Q, double beta, const Eigen::VectorXd& g,
                                const Eigen::VectorXd& w, Eigen::VectorXd& dw, const QpActiveSet* warm) {
  QpResult result;
  const int n = n_;
  if (Q.rows() != n || Q.cols() != n || g.size() != n || w.size() != n || !(beta >= 0) || !std::isfinite(beta) ||
      !allFinite(Q.data(), Q.size()) || !allFinite(g.data(), g.size()) || !allFinite(w.data(), w.size())) {
    result.status = QpStatus::InvalidInput;
    return result;
  }
  if (dw.size() != n) dw.resize(n);
  if (n == 0) {  // no contacts: the empty step is optimal
    result.status = QpStatus::Converged;
    return result;
  }
  const int max_iterations = options.max_iterations > 0 ? options.max_iterations : 10 * n + 50;

  H_ = Q;
  H_.diagonal().array() += beta;
  w_ = w;
  g_ = g;
  scale_ = std::max(H_.cwiseAbs().maxCoeff(), g_.cwiseAbs().maxCoeff());
  if (!(scale_ > 0)) scale_ = 1.0;
  const double dual_tol = options.dual_tolerance * scale_;
  const double feas_tol = options.feasibility_tolerance;

  factor_valid_ = false;
  factorizations_ = 0;
  bool at_minimizer = startAt(w, warm, feas_tol, result);
  result.status = QpStatus::MaxIterations;
  while (true) {
    if (!at_minimizer) {
      if (result.iterations >= max_iterations) break;
      if (factor_valid_)
        buildCaps();
      else
        buildLists();
      ++result.iterations;
      if (!solveEqp()) {
        result.status = QpStatus::NotConvex;
        break;
      }
      if (!stepTowardMinimizer(result)) continue;
    }
    // At the minimizer of the working set: multipliers.
    at_minimizer = false;
    if (!dropConstraint(dual_tol, result)) {
      result.status = QpStatus::Converged;
      break;
    }
  }
  finishMultipliers(result);
  dw = d_;
  result.factorizations = factorizations_;
  return result;
}

double kktResidual(const Eigen::MatrixXd& Q, double beta, const Eigen::VectorXd& g, const Eigen::VectorXd& w,
                   const std::vector<int>& contact_sizes, const Eigen::VectorXd& dw, const Eigen::VectorXd& lambda,
                   const Eigen::VectorXd& nu) {
  const int n = static_cast<int>(g.size());
  Eigen::MatrixXd H = Q;
  H.diagonal().array() += beta;
  const double scale = std::max({1.0, H.cwiseAbs().maxCoeff(), g.cwiseAbs().maxCoeff()});
  const Eigen::VectorXd z = w + dw;
  Eigen::VectorXd r = g + H * dw - lambda;
  double worst = 0;
  int offset = 0;
  for (std::size_t c = 0; c < contact_sizes.size(); ++c) {
    const int K = contact_sizes[c];
    r.segment(offset, K).array() += nu[c];
    const double s = z.segment(offset, K).sum();
    worst = std::max(worst, s - 1.0);
    worst = std::max(worst, -nu[c] / scale);
    worst = std::max(worst, std::abs(nu[c] * (1.0 - s)) / scale);
    offset += K;
  }
  if (offset != n) return std::numeric_limits<double>::infinity();
  worst = std::max(worst, r.cwiseAbs().maxCoeff() / scale);
  for (int i = 0; i < n; ++i) {
    worst = std::max(worst, -z[i]);
    worst = std::max(worst, -lambda[i] / scale);
    worst = std::max(worst, std::abs(lambda[i] * z[i]) / scale);
  }
  return worst;
}

}  // namespace nmdp
