// RBF fitting (target: a fit on the sand data under 1 s on this 2-core machine).
//   FitSandRbf         group, augment (to the published model's 103 points) and fit 3 × the sand
//                      samples with the LOO report's inverse: what `nmdp fit` computes;
//   FitSandRbfEndToEnd the same from the CSV folder to the model file on disk (import, fit, report,
//                      write), i.e. `nmdp fit --data granular/sand_samples ...` without process start.
// Both need ../shared (skipped with a message when it is absent).
//
// MLP training (target: 10⁴ samples under 60 s on this 2-core machine), without ../shared:
//   FitMlp/P           P random feature points (depth −0.05..0 m, angle ±0.9 rad) sampled from the
//                      project's hand-made sand model data/granular/handmade_sand_rbf.h5 (26 vertices,
//                      so P·26 dataset rows: P = 385 gives 10 010 samples, P = 10 000 gives 260 000),
//                      trained with the default settings of fit_config.hpp (2-64-64-78 tanh,
//                      full-batch Adam, 10 000 epochs at most, validation 30 %, patience 1000; zero
//                      rows at 10 heights × 25 angles) except where the benchmark's name says otherwise. One iteration each; the counters
//                      give the epochs run and the validation error. FitMlp/10000points runs 200 epochs
//                      only (one epoch on 10 000 points costs ~0.1-0.3 s): its time per epoch is the point.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include <random>

#include "contact_models/rbf_function.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace {
using namespace nmdp;

const std::string kSamples = std::string(NMDP_SHARED_DIR) + "/granular/sand_samples";

FitConfig publishedConfig() {
  const std::string path = std::string(NMDP_SOURCE_DIR) + "/data/granular/sand_rbf_fit.json";
  std::ifstream in(path);
  return parseFitConfig(nlohmann::json::parse(in), {path, ""});
}

void FitSandRbf(benchmark::State& state) {
  const ForceDataset data = importSandSamplesCsv(kSamples);
  const FitConfig config = publishedConfig();
  for (auto _ : state) {
    RbfFitOutcome fit = fitRbfToDataset(data, config, "sand_samples");
    benchmark::DoNotOptimize(fit.record.fit.parameters.weights.data());
  }
}

void FitSandRbfEndToEnd(benchmark::State& state) {
  const FitConfig config = publishedConfig();
  const std::string out =
      (std::filesystem::temp_directory_path() / ("nmdp_bench_fit_" + std::to_string(::getpid()) + ".h5")).string();
  for (auto _ : state) {
    const ForceDataset data = importSandSamplesCsv(kSamples);
    const RbfFitOutcome fit = fitRbfToDataset(data, config, kSamples);
    const std::string report = formatRbfFitReport(fit.record);
    saveRbfFit(out, fit.record, fit.geometry);
    benchmark::DoNotOptimize(report.data());
  }
  std::filesystem::remove(out);
}
// P random points of the hand-made model, all 26 vertices each.
ForceDataset handmadeSamples(int P) {
  const RbfModelFile model = readRbfHdf5(std::string(NMDP_SOURCE_DIR) + "/data/granular/handmade_sand_rbf.h5");
  const RbfFunction f(model.parameters);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> depth(-0.05, 0.0), angle(-0.9, 0.9);
  Eigen::MatrixX2d points(P, 2);
  for (int i = 0; i < P; ++i) points.row(i) << depth(rng), angle(rng);
  Eigen::MatrixXd W;
  f.evaluate(points, W, nullptr, nullptr);
  const int K = static_cast<int>(W.cols() / 3);
  ForceDataset d;
  d.features.resize(P * K, 2);
  d.vertex.resize(P * K);
  d.wrench.resize(P * K, 3);
  for (int i = 0; i < P; ++i)
    for (int j = 0; j < K; ++j) {
      d.features.row(i * K + j) = points.row(i);
      d.vertex[i * K + j] = j;
      d.wrench.row(i * K + j) = W.block(i, 3 * j, 1, 3);
    }
  d.feature_names = {"phi", "beta"};
  d.feature_units = {"m", "rad"};
  d.wrench_names = {"F_x", "F_z", "tau_y"};
  d.wrench_units = {"N", "N", "N m"};
  d.torque_centre = model.geometry.torque_centre;
  return d;
}

void FitMlp(benchmark::State& state, int points, int max_epochs, int batch_size) {
  const ForceDataset data = handmadeSamples(points);
  FitConfig config;
  if (max_epochs > 0) config.mlp.max_epochs = max_epochs;
  config.mlp.batch_size = batch_size;
  for (auto _ : state) {
    const MlpFitOutcome fit = fitMlpToDataset(data, config, "handmade samples");
    const MlpFit& r = fit.record.fit;
    double worst = 0.0;
    for (int i = 0; i < fit.record.points.pointCount(); ++i)
      if (r.validation[i]) worst = std::max(worst, r.relative.row(i).maxCoeff());
    state.counters["samples"] = static_cast<double>(data.features.rows());
    state.counters["epochs"] = r.epochs;
    state.counters["best_epoch"] = r.best_epoch;
    state.counters["val_loss"] = r.validation_loss;
    state.counters["val_max_rel_err_pct"] = 100 * worst;
    state.counters["seconds"] = fit.record.seconds;
  }
}
}  // namespace

int main(int argc, char** argv) {
  if (std::filesystem::exists(kSamples)) {
    benchmark::RegisterBenchmark("FitSandRbf", FitSandRbf)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("FitSandRbfEndToEnd", FitSandRbfEndToEnd)->Unit(benchmark::kMillisecond);
  } else {
    std::cerr << "../shared is absent (" << kSamples << "): skipping the RBF fit benchmarks\n";
  }
  benchmark::RegisterBenchmark("FitMlp/385points_10k_samples", FitMlp, 385, 0, 0)
      ->Unit(benchmark::kSecond)
      ->Iterations(1);
  benchmark::RegisterBenchmark("FitMlp/10000points_260k_samples/200epochs", FitMlp, 10000, 200, 0)
      ->Unit(benchmark::kSecond)
      ->Iterations(1);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
