// Contact models, one core: V and dV/dξ for 4 contacts. Targets: Coulomb < 1 µs, the published RBF
// model (103 centres × 26 vertices) < 20 µs, a 2×64 MLP with autograd < 100 µs (each Jacobian
// scheme, and its feature function alone with dW/df for 4 rows, to see what the placement costs).
// The shipped 3-D sand model (RbfQuadruped3d4: 45 centres, 17 vertices of 6-D wrenches) should stay
// within 2× the shipped planar quadruped model (RbfQuadruped4: 99 centres, 13 vertices); the synthetic
// 3-D RBFs (SpatialRbf4_N<centres>_K<vertices>, thin-plate with a linear tail) show how it scales.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <iostream>
#include <random>

#include "contact_models/coulomb_model.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/rbf_model.hpp"
#include "contact_models/spatial_rbf_function.hpp"
#include "terrain/plane.hpp"

namespace {
using namespace nmdp;

// Four feet of a quadruped standing a few mm deep, legs slightly tilted.
std::vector<ContactFrame> fourFeet(double radius) {
  std::vector<ContactFrame> frames(4);
  const double depth[4] = {-0.003, -0.004, -0.0035, -0.002};
  const double tilt[4] = {0.1, -0.05, 0.2, -0.15};
  for (int i = 0; i < 4; ++i) {
    frames[i].radius = radius;
    frames[i].position = Vec3(0.2 * (i < 2 ? 1 : -1), 0.15 * (i % 2 ? 1 : -1), radius + depth[i]);
    frames[i].leg_axis = Vec3(std::sin(tilt[i]), 0.0, std::cos(tilt[i]));
    frames[i].lateral = Vec3::UnitY();
  }
  return frames;
}

void run(benchmark::State& state, const ContactModel& model, double radius, bool derivatives) {
  const PlaneTerrain ground;
  const std::vector<ContactFrame> frames = fourFeet(radius);
  std::vector<ContactWrenches> out(frames.size());
  for (ContactWrenches& o : out) o.resize(model.vertexCount());
  for (auto _ : state) {
    model.evaluate(frames, ground, out, derivatives);
    benchmark::DoNotOptimize(out[3].V.data());
    benchmark::ClobberMemory();
  }
}

// The MLP's feature function alone: W, dW/dφ and dW/dβ for 4 rows (φ, β) of the data's range.
void runFeatures(benchmark::State& state, const MlpFunction& function) {
  Eigen::MatrixX2d features(4, 2);
  features << -0.05, 0.3, -0.01, -0.4, 0.02, 0.05, -0.08, 1.0;
  Eigen::MatrixXd W, dphi, dbeta;
  for (auto _ : state) {
    function.evaluate(features, W, &dphi, &dbeta);
    benchmark::DoNotOptimize(W.data());
    benchmark::ClobberMemory();
  }
}

// A 3-D thin-plate RBF with a linear tail of the planned shape: N centres on a grid of depths ×
// tilt nodes, K vertices, random weights (the cost does not depend on their values).
std::shared_ptr<ContactModel> syntheticSpatialRbf(int N, int K) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SpatialRbfParameters p;
  p.centres.resize(N, 3);
  for (int i = 0; i < N; ++i) p.centres.row(i) << -0.08 + 0.09 * (i / 5) / std::max(1, N / 5 - 1), 0.4 * u(rng), 0.4 * u(rng);
  p.weights = Eigen::MatrixXd::NullaryExpr(N, 6 * K, [&]() { return 100.0 * u(rng); });
  p.polynomial = Eigen::MatrixXd::NullaryExpr(4, 6 * K, [&]() { return 100.0 * u(rng); });
  return std::make_shared<SpatialWrenchModel>(std::make_shared<const SpatialRbfFunction>(p), SpatialGeometry{0.0, 0.005},
                                              "rbf");
}

void registerModel(const std::string& name, std::shared_ptr<ContactModel> model, double radius) {
  benchmark::RegisterBenchmark((name + "/V").c_str(), [model, radius](benchmark::State& s) { run(s, *model, radius, false); });
  benchmark::RegisterBenchmark((name + "/V+dV").c_str(), [model, radius](benchmark::State& s) { run(s, *model, radius, true); });
}
}  // namespace

int main(int argc, char** argv) {
  const ConfigContext ctx{"bench", ""};
  registerModel("Coulomb4", makeCoulombModel(nlohmann::json::object(), ctx), 0.02);
  const std::string published = std::string(NMDP_SHARED_DIR) + "/granular/robosimian_sand_rbf";
  if (std::filesystem::exists(published))
    registerModel("RbfPublished4", makeRbfModel({{"file", published}}, ctx), 0.0);
  else
    std::cerr << "../shared is absent (" << published << "): skipping the published RBF model\n";
  registerModel("RbfQuadruped4", makeRbfModel({{"file", std::string(NMDP_SOURCE_DIR) + "/data/granular/rft_quadruped_rbf.h5"}}, ctx),
                0.02);
  registerModel("RbfQuadruped3d4",
                makeRbfModel({{"file", std::string(NMDP_SOURCE_DIR) + "/data/granular/rft3d_quadruped_rbf.h5"}}, ctx), 0.02);
  for (const auto& [N, K] : {std::pair{45, 26}, std::pair{81, 26}, std::pair{45, 18}})
    registerModel("SpatialRbf4_N" + std::to_string(N) + "_K" + std::to_string(K), syntheticSpatialRbf(N, K), 0.02);
  // "Mlp2x64_4" is forward-mode autograd (the default); the other schemes carry their name.
  for (MlpJacobian jacobian : {MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
    auto function = std::make_shared<MlpFunction>(randomMlpParameters(2, 64, 26, MlpActivation::Tanh, 7), jacobian);
    const std::string scheme = jacobian == MlpJacobian::ForwardMode ? "" : std::string("_") + mlpJacobianName(jacobian);
    registerModel("Mlp2x64_4" + scheme,
                  std::make_shared<PlanarWrenchModel>(function, PlanarGeometry{0.1572, 0.1, 0.02}, "mlp"), 0.0);
    benchmark::RegisterBenchmark(("MlpFeatures2x64_4" + scheme + "/W+dW").c_str(),
                                 [function](benchmark::State& s) { runFeatures(s, *function); });
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
