// The capped-simplex QP of the PGM at the quadruped's size (4 contacts × 26 vertices, the published
// RBF model): 50 random problems solved cold, then warm-started from each one's own active set with
// β × 1.01 (as the next outer iteration does). Counters: QP iterations per solve.
#include <benchmark/benchmark.h>

#include <vector>

#include "solver/capped_simplex_qp.hpp"
#include "tests/support/random_qp_problems.hpp"

namespace {
using namespace nmdp;

struct QpBatch {
  std::vector<test::QpProblem> problems;
  std::vector<QpActiveSet> active_sets;  // of each problem's cold solve
};

const QpBatch& fourByTwentySix() {
  static const QpBatch batch = [] {
    QpBatch b;
    CappedSimplexQp qp(std::vector<int>{26, 26, 26, 26});
    std::mt19937 rng(2024);
    const std::vector<int> sizes = {26, 26, 26, 26};
    Eigen::VectorXd dw(104);
    for (int i = 0; i < 50; ++i) {
      b.problems.push_back(test::randomProblem(rng, sizes, 1e-2, 1e3));
      const test::QpProblem& p = b.problems.back();
      qp.solve(p.Q, p.beta, p.g, p.w, dw);
      b.active_sets.push_back(qp.activeSet());
    }
    return b;
  }();
  return batch;
}

void run(benchmark::State& state, bool warm) {
  CappedSimplexQp qp(std::vector<int>{26, 26, 26, 26});
  const QpBatch& batch = fourByTwentySix();
  Eigen::VectorXd dw(104);
  long iterations = 0, solves = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < batch.problems.size(); ++i) {
      const test::QpProblem& p = batch.problems[i];
      iterations += warm ? qp.solve(p.Q, p.beta * 1.01, p.g, p.w, dw, &batch.active_sets[i]).iterations
                         : qp.solve(p.Q, p.beta, p.g, p.w, dw).iterations;
      benchmark::DoNotOptimize(dw.data());
    }
    solves += static_cast<long>(batch.problems.size());
  }
  state.counters["solves"] = benchmark::Counter(static_cast<double>(solves), benchmark::Counter::kIsRate);
  state.counters["iterations_per_solve"] = static_cast<double>(iterations) / static_cast<double>(solves);
}

void BM_CappedSimplexQp4x26Cold(benchmark::State& state) { run(state, false); }
void BM_CappedSimplexQp4x26Warm(benchmark::State& state) { run(state, true); }
BENCHMARK(BM_CappedSimplexQp4x26Cold);
BENCHMARK(BM_CappedSimplexQp4x26Warm);

}  // namespace

BENCHMARK_MAIN();
