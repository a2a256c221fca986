// The spatial (3-D) MLP, one core, 4 contacts: its feature function alone (W and dW/df for 4 rows
// (φ, β, γ), each Jacobian scheme) beside the planar one of bench_contact_models.cpp
// (MlpFeatures2x64_4), for a 2×64 tanh network with 26 vertices (3-64-64-156 against 2-64-64-78).
#include <benchmark/benchmark.h>

#include <array>
#include <memory>
#include <string>

#include "contact_models/mlp/mlp_function.hpp"

namespace {
using namespace nmdp;

// W, ∂W/∂φ, ∂W/∂β, ∂W/∂γ for 4 rows of the data's range.
void runSpatialFeatures(benchmark::State& state, const MlpFunction& function) {
  Eigen::MatrixX3d features(4, 3);
  features << -0.05, 0.3, 0.1, -0.01, -0.4, -0.2, -0.02, 0.05, 0.0, -0.08, 1.0, 0.4;
  Eigen::MatrixXd W;
  std::array<Eigen::MatrixXd, 3> dW;
  const SpatialFeatureFunction& f = function;
  for (auto _ : state) {
    f.evaluate(features, W, &dW);
    benchmark::DoNotOptimize(W.data());
    benchmark::ClobberMemory();
  }
}

// The planar feature function with the same network size, for the ratio.
void runPlanarFeatures(benchmark::State& state, const MlpFunction& function) {
  Eigen::MatrixX2d features(4, 2);
  features << -0.05, 0.3, -0.01, -0.4, -0.02, 0.05, -0.08, 1.0;
  Eigen::MatrixXd W, dphi, dbeta;
  for (auto _ : state) {
    function.evaluate(features, W, &dphi, &dbeta);
    benchmark::DoNotOptimize(W.data());
    benchmark::ClobberMemory();
  }
}

}  // namespace

int main(int argc, char** argv) {
  for (MlpJacobian jacobian : {MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
    const std::string scheme = std::string("_") + mlpJacobianName(jacobian);
    auto spatial = std::make_shared<MlpFunction>(
        randomMlpParameters(2, 64, 26, MlpActivation::Tanh, 7, MlpWrench::Spatial), jacobian);
    auto planar = std::make_shared<MlpFunction>(randomMlpParameters(2, 64, 26, MlpActivation::Tanh, 7), jacobian);
    benchmark::RegisterBenchmark(("SpatialMlpFeatures3x64_4" + scheme + "/W+dW").c_str(),
                                 [spatial](benchmark::State& s) { runSpatialFeatures(s, *spatial); });
    benchmark::RegisterBenchmark(("PlanarMlpFeatures2x64_4" + scheme + "/W+dW").c_str(),
                                 [planar](benchmark::State& s) { runPlanarFeatures(s, *planar); });
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
