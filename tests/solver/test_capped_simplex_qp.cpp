// The capped-simplex QP of the PGM (DESIGN.md 3): KKT conditions on random problems, brute force on
// tiny problems, warm start, no allocation after warm-up, degenerate cases (bench_solver_qp.cpp times
// the solves).
//
// Allocation counting (test_allocation_counter.hpp): as in test_no_allocation.cpp, the global
// operator new family is replaced and on glibc the malloc family is interposed; both count only
// while counting is on.
#include <cstdlib>
#include <iostream>

#include "random_qp_problems.hpp"
#include "solver/capped_simplex_qp.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp::test {
namespace {

std::vector<int> randomSizes(std::mt19937& rng) {
  std::uniform_int_distribution<int> contacts(1, 4), K(3, 26);
  std::vector<int> sizes(contacts(rng));
  for (int& s : sizes) s = K(rng);
  return sizes;
}

double objective(const QpProblem& p, const Eigen::VectorXd& dw) {
  return p.g.dot(dw) + 0.5 * dw.dot(p.Q * dw) + 0.5 * p.beta * dw.squaredNorm();
}

double kkt(const QpProblem& p, const CappedSimplexQp& qp, const Eigen::VectorXd& dw) {
  return kktResidual(p.Q, p.beta, p.g, p.w, p.sizes, dw, qp.boundMultipliers(), qp.capMultipliers());
}

// Brute force: every working set (each variable fixed at 0 or free, each cap active or not); the
// equality-constrained minimizer of each by a dense KKT solve; the lowest objective among the feasible.
Eigen::VectorXd bruteForce(const QpProblem& p) {
  const int n = p.n();
  const int C = static_cast<int>(p.sizes.size());
  Eigen::MatrixXd H = p.Q;
  H.diagonal().array() += p.beta;
  const Eigen::VectorXd c = p.g - H * p.w;
  std::vector<int> contact_of;
  for (int k = 0; k < C; ++k)
    for (int i = 0; i < p.sizes[k]; ++i) contact_of.push_back(k);
  double best = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_z = Eigen::VectorXd::Constant(n, std::nan(""));
  for (long mask = 0; mask < (1L << (n + C)); ++mask) {
    std::vector<int> free, caps;
    for (int i = 0; i < n; ++i)
      if (!(mask >> i & 1)) free.push_back(i);
    for (int k = 0; k < C; ++k)
      if (mask >> (n + k) & 1) caps.push_back(k);
    const int kf = static_cast<int>(free.size()), m = static_cast<int>(caps.size());
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(kf + m, kf + m);
    Eigen::VectorXd rhs(kf + m);
    for (int a = 0; a < kf; ++a) {
      for (int b = 0; b < kf; ++b) K(a, b) = H(free[a], free[b]);
      rhs[a] = -c[free[a]];
      for (int j = 0; j < m; ++j)
        if (contact_of[free[a]] == caps[j]) K(a, kf + j) = K(kf + j, a) = 1.0;
    }
    for (int j = 0; j < m; ++j) rhs[kf + j] = 1.0;
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    if (kf + m > 0) {
      Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
      if (!lu.isInvertible()) continue;
      const Eigen::VectorXd x = lu.solve(rhs);
      for (int a = 0; a < kf; ++a) z[free[a]] = x[a];
    }
    bool feasible = true;
    int offset = 0;
    for (int k = 0; k < C; ++k) {
      if (z.segment(offset, p.sizes[k]).sum() > 1.0 + 1e-12) feasible = false;
      offset += p.sizes[k];
    }
    if (z.minCoeff() < -1e-12 || !feasible) continue;
    const double f = 0.5 * z.dot(H * z) + c.dot(z);
    if (f < best) {
      best = f;
      best_z = z;
    }
  }
  return best_z - p.w;
}

TEST(CappedSimplexQp, KktOnRandomProblems) {
  std::mt19937 rng(12345);
  int with_caps = 0, with_bounds = 0, interior = 0, total_iterations = 0, total_factorizations = 0;
  double worst = 0;
  const int N = 600;
  for (int trial = 0; trial < N; ++trial) {
    const QpProblem p = randomProblem(rng, randomSizes(rng), 1e-4, 1e6);
    CappedSimplexQp qp(p.sizes);
    Eigen::VectorXd dw(p.n());
    const QpResult r = qp.solve(p.Q, p.beta, p.g, p.w, dw);
    ASSERT_EQ(r.status, QpStatus::Converged) << "trial " << trial << ": " << toString(r.status);
    const double res = kkt(p, qp, dw);
    EXPECT_LT(res, 1e-10) << "trial " << trial << " beta " << p.beta;
    worst = std::max(worst, res);
    total_iterations += r.iterations;
    total_factorizations += r.factorizations;
    bool any_cap = false, any_bound = false;
    for (auto b : qp.activeSet().cap) any_cap = any_cap || b;
    for (auto b : qp.activeSet().at_bound) any_bound = any_bound || b;
    with_caps += any_cap;
    with_bounds += any_bound;
    interior += !any_cap && !any_bound;
  }
  EXPECT_GT(with_caps, N / 10);
  EXPECT_GT(with_bounds, N / 10);
  EXPECT_GT(interior, N / 50);
  std::cout << "[ qp ] " << N << " problems: " << with_caps << " with caps active, " << with_bounds
            << " with bounds active, " << interior << " interior; mean iterations "
            << double(total_iterations) / N << " (" << double(total_factorizations) / N
            << " factorizations from scratch); worst KKT residual " << worst << "\n";
}

TEST(CappedSimplexQp, MatchesBruteForceOnSmallProblems) {
  std::mt19937 rng(777);
  const std::vector<std::vector<int>> shapes = {{4, 4}, {3, 5}, {8}, {3, 3}, {3}, {5, 3}};
  int agreements = 0;
  for (int trial = 0; trial < 240; ++trial) {
    const QpProblem p = randomProblem(rng, shapes[trial % shapes.size()], 1e-3, 1e4);
    CappedSimplexQp qp(p.sizes);
    Eigen::VectorXd dw(p.n());
    const QpResult r = qp.solve(p.Q, p.beta, p.g, p.w, dw);
    ASSERT_EQ(r.status, QpStatus::Converged);
    const Eigen::VectorXd ref = bruteForce(p);
    ASSERT_TRUE(ref.allFinite());
    const double scale = std::max(1.0, ref.cwiseAbs().maxCoeff());
    EXPECT_LT((dw - ref).cwiseAbs().maxCoeff() / scale, 1e-10) << "trial " << trial;
    EXPECT_LE(objective(p, dw), objective(p, ref) + 1e-12 * std::max(1.0, std::abs(objective(p, ref))));
    agreements += (dw - ref).cwiseAbs().maxCoeff() / scale < 1e-10;
  }
  EXPECT_EQ(agreements, 240);
}

TEST(CappedSimplexQp, WarmStartReusesTheActiveSet) {
  std::mt19937 rng(4242);
  long cold_total = 0, warm_total = 0;
  int warm_used = 0;
  const int N = 200;
  for (int trial = 0; trial < N; ++trial) {
    const QpProblem p = randomProblem(rng, randomSizes(rng), 1e-2, 1e4);
    CappedSimplexQp qp(p.sizes);
    Eigen::VectorXd dw(p.n());
    ASSERT_EQ(qp.solve(p.Q, p.beta, p.g, p.w, dw).status, QpStatus::Converged);
    const QpActiveSet previous = qp.activeSet();
    // a slightly perturbed problem (same w, slightly different Q and g)
    QpProblem next = p;
    next.Q *= 1.0 + 1e-7;
    next.g += randomVector(rng, p.n(), 1e-9 * (1.0 + p.g.cwiseAbs().maxCoeff()));
    Eigen::VectorXd dw_cold(p.n()), dw_warm(p.n());
    const QpResult cold = qp.solve(next.Q, next.beta, next.g, next.w, dw_cold);
    const double kkt_cold = kkt(next, qp, dw_cold);
    const QpResult warm = qp.solve(next.Q, next.beta, next.g, next.w, dw_warm, &previous);
    ASSERT_EQ(cold.status, QpStatus::Converged);
    ASSERT_EQ(warm.status, QpStatus::Converged);
    EXPECT_LT(kkt_cold, 1e-10);
    EXPECT_LT(kkt(next, qp, dw_warm), 1e-10);
    EXPECT_LT((dw_cold - dw_warm).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, dw_cold.cwiseAbs().maxCoeff()));
    EXPECT_LE(warm.iterations, cold.iterations) << "trial " << trial;
    cold_total += cold.iterations;
    warm_total += warm.iterations;
    warm_used += warm.warm_start_used;
  }
  EXPECT_LT(warm_total, cold_total);
  EXPECT_GT(warm_used, N * 9 / 10);
  std::cout << "[ qp ] warm start: " << warm_total << " iterations vs " << cold_total << " cold over " << N
            << " problems; warm active set used in " << warm_used << "\n";
}

// The same problem with the previous active set on the *same* w (a rejected PGM step: β changes).
TEST(CappedSimplexQp, WarmStartAfterBetaChange) {
  std::mt19937 rng(99);
  for (int trial = 0; trial < 100; ++trial) {
    const QpProblem p = randomProblem(rng, randomSizes(rng), 1e-2, 1e4);
    CappedSimplexQp qp(p.sizes);
    Eigen::VectorXd dw(p.n()), dw_cold(p.n()), dw_warm(p.n());
    ASSERT_EQ(qp.solve(p.Q, p.beta, p.g, p.w, dw).status, QpStatus::Converged);
    const QpActiveSet previous = qp.activeSet();
    const double beta = p.beta * 1.5;
    ASSERT_EQ(qp.solve(p.Q, beta, p.g, p.w, dw_cold).status, QpStatus::Converged);
    ASSERT_EQ(qp.solve(p.Q, beta, p.g, p.w, dw_warm, &previous).status, QpStatus::Converged);
    QpProblem q = p;
    q.beta = beta;
    EXPECT_LT(kkt(q, qp, dw_warm), 1e-10);
    EXPECT_LT((dw_cold - dw_warm).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, dw_cold.cwiseAbs().maxCoeff()));
  }
}

TEST(CappedSimplexQp, NoAllocationAfterWarmUp) {
  std::mt19937 rng(31);
  const std::vector<int> sizes = {26, 26, 26, 26};
  std::vector<QpProblem> problems;
  for (int i = 0; i < 8; ++i) problems.push_back(randomProblem(rng, sizes, 1e-3, 1e3));
  CappedSimplexQp qp(sizes);
  Eigen::VectorXd dw(104);
  QpActiveSet warm = qp.activeSet();
  int k = 0;
  const AllocationCount count = allocationsOf([&] {
    for (const QpProblem& p : problems) {
      qp.solve(p.Q, p.beta, p.g, p.w, dw);
      warm = qp.activeSet();  // same sizes: no reallocation
      qp.solve(p.Q, p.beta * 2, p.g, p.w, dw, &warm);
      ++k;
    }
  });
  EXPECT_EQ(count.total(), 0) << count.news << " operator new, " << count.mallocs << " malloc-family calls";
#if NMDP_COUNTS_MALLOC
  const AllocationCount check = allocationsOf([] {
    Eigen::MatrixXd m = Eigen::MatrixXd::Ones(20, 20);
    const void* volatile sink = m.data();
    (void)sink;
  });
  EXPECT_GE(check.mallocs, 1) << "Eigen allocations must be counted";
#endif
}

TEST(CappedSimplexQp, NoContactsIsAnEmptyConvergedStep) {
  CappedSimplexQp qp{std::vector<int>{}};
  Eigen::VectorXd dw(3);
  const QpResult r = qp.solve(Eigen::MatrixXd(0, 0), 1.0, Eigen::VectorXd(0), Eigen::VectorXd(0), dw);
  EXPECT_EQ(r.status, QpStatus::Converged);
  EXPECT_EQ(dw.size(), 0);
}

TEST(CappedSimplexQp, DegenerateCases) {
  std::mt19937 rng(5);
  const std::vector<int> sizes = {6, 4, 5};
  const int n = 15;
  // Q = 0: only the proximal term; the solution is the projection of w − g/β onto the capped simplices.
  for (int trial = 0; trial < 50; ++trial) {
    QpProblem p = randomProblem(rng, sizes, 1e-3, 1e3);
    p.Q.setZero();
    CappedSimplexQp qp(sizes);
    Eigen::VectorXd dw(n);
    ASSERT_EQ(qp.solve(p.Q, p.beta, p.g, p.w, dw).status, QpStatus::Converged);
    EXPECT_LT(kkt(p, qp, dw), 1e-12);
  }
  // g = 0: Δw = 0 whatever Q, β and (feasible) w.
  for (int trial = 0; trial < 50; ++trial) {
    QpProblem p = randomProblem(rng, sizes, 1e-4, 1e6);
    p.g.setZero();
    CappedSimplexQp qp(sizes);
    Eigen::VectorXd dw(n);
    ASSERT_EQ(qp.solve(p.Q, p.beta, p.g, p.w, dw).status, QpStatus::Converged);
    EXPECT_LT(dw.cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT(kkt(p, qp, dw), 1e-12);
  }
  // w at a vertex of every capped simplex.
  for (int trial = 0; trial < 50; ++trial) {
    QpProblem p = randomProblem(rng, sizes, 1e-4, 1e6);
    p.w.setZero();
    p.w[trial % 6] = 1.0;
    p.w[6 + trial % 4] = 1.0;
    p.w[10 + trial % 5] = 1.0;
    CappedSimplexQp qp(sizes);
    Eigen::VectorXd dw(n);
    ASSERT_EQ(qp.solve(p.Q, p.beta, p.g, p.w, dw).status, QpStatus::Converged);
    EXPECT_LT(kkt(p, qp, dw), 1e-10);
  }
  // An all-zero contact block (no coupling, no gradient, w_c = 0): Δw_c = 0.
  for (int trial = 0; trial < 50; ++trial) {
    QpProblem p = randomProblem(rng, sizes, 1e-4, 1e6);
    p.Q.middleRows(6, 4).setZero();
    p.Q.middleCols(6, 4).setZero();
    p.g.segment(6, 4).setZero();
    p.w.segment(6, 4).setZero();
    CappedSimplexQp qp(sizes);
    Eigen::VectorXd dw(n);
    ASSERT_EQ(qp.solve(p.Q, p.beta, p.g, p.w, dw).status, QpStatus::Converged);
    EXPECT_LT(kkt(p, qp, dw), 1e-10);
    EXPECT_EQ(dw.segment(6, 4).cwiseAbs().maxCoeff(), 0.0);
  }
  // A contact of size zero-gradient *and* all-zero Q overall with w = 0: nothing moves, no iteration
  // beyond the first.
  {
    CappedSimplexQp qp(sizes);
    Eigen::VectorXd dw(n);
    const QpResult r = qp.solve(Eigen::MatrixXd::Zero(n, n), 1.0, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), dw);
    EXPECT_EQ(r.status, QpStatus::Converged);
    EXPECT_EQ(dw.cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(CappedSimplexQp, ReportsBadInputAndNonConvexity) {
  const std::vector<int> sizes = {3, 3};
  CappedSimplexQp qp(sizes);
  Eigen::VectorXd dw(6);
  // wrong sizes
  EXPECT_EQ(qp.solve(Eigen::MatrixXd::Zero(5, 5), 1.0, Eigen::VectorXd::Zero(5), Eigen::VectorXd::Zero(5), dw).status,
            QpStatus::InvalidInput);
  // NaN
  Eigen::VectorXd g = Eigen::VectorXd::Ones(6);
  g[2] = std::nan("");
  EXPECT_EQ(qp.solve(Eigen::MatrixXd::Zero(6, 6), 1.0, g, Eigen::VectorXd::Zero(6), dw).status, QpStatus::InvalidInput);
  // β = 0 with Q = 0 and a descent direction: the restricted Hessian is singular
  g = -Eigen::VectorXd::Ones(6);
  EXPECT_EQ(qp.solve(Eigen::MatrixXd::Zero(6, 6), 0.0, g, Eigen::VectorXd::Zero(6), dw).status, QpStatus::NotConvex);
  // indefinite Q
  Eigen::MatrixXd Q = -Eigen::MatrixXd::Identity(6, 6);
  EXPECT_EQ(qp.solve(Q, 0.5, g, Eigen::VectorXd::Zero(6), dw).status, QpStatus::NotConvex);
  // iteration cap
  qp.options.max_iterations = 1;
  const QpResult r = qp.solve(Eigen::MatrixXd::Identity(6, 6), 1.0, g, Eigen::VectorXd::Zero(6), dw);
  EXPECT_EQ(r.status, QpStatus::MaxIterations);
}

}  // namespace
}  // namespace nmdp::test
