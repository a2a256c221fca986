// RBF fitting (issue 6 target: a fit on the sand data under 1 s on this 2-core machine).
//   FitSandRbf         group, augment (to the published model's 103 points) and fit 3 × the sand
//                      samples with the LOO report's inverse: what `nmdp fit` computes;
//   FitSandRbfEndToEnd the same from the CSV folder to the model file on disk (import, fit, report,
//                      write), i.e. `nmdp fit --data granular/sand_samples ...` without process start.
// Both need ../shared (skipped with a message when it is absent).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"

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
}  // namespace

int main(int argc, char** argv) {
  if (std::filesystem::exists(kSamples)) {
    benchmark::RegisterBenchmark("FitSandRbf", FitSandRbf)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("FitSandRbfEndToEnd", FitSandRbfEndToEnd)->Unit(benchmark::kMillisecond);
  } else {
    std::cerr << "../shared is absent (" << kSamples << "): skipping the RBF fit benchmarks\n";
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
