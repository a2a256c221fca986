// The project's 3-D sand model, data/granular/rft3d_quadruped_rbf.h5 (data/granular/README.md,
// "rft3d_quadruped_rbf.h5"), made by two written commands:
//   nmdp gen-rft --config data/granular/rft3d_quadruped_samples.json --out data/granular/rft3d_quadruped_samples.h5
//   nmdp fit --data data/granular/rft3d_quadruped_samples.h5 --config data/granular/rft3d_quadruped_fit.json
//            --model rbf --out data/granular/rft3d_quadruped_rbf.h5
// and its planar counterpart from the same medium and foot, data/granular/rft3d_quadruped_planar_rbf.h5:
//   nmdp gen-rft --config data/granular/rft3d_quadruped_planar.json --out SAMPLES
//   nmdp fit --data SAMPLES --config data/granular/rft_quadruped_fit.json --model rbf --out data/granular/rft3d_quadruped_planar_rbf.h5
//  * the commands, run again, give the shipped samples (to 1e-12) and models that predict the
//    shipped ones' wrenches at random features to the round-off of their fit (cond(A)·ε of the
//    largest entry): the shipped files are what the commands make;
//  * the model loads through the "rbf" registry entry (17 vertices: the directions that do not lift the foot), and its function reproduces
//    the fitted values at its centres;
//  * its leave-one-point-out error stays within the bound data/granular/README.md states (largest
//    44.3 %, RMS per vertex at most 16.7 %, relative to the largest wrench at the point);
//  * between the samples it reproduces 3-D RFT (gen-rft on a finer grid of depths and tilts)
//    within 5.5 % RMS and 16.5 % at worst of the largest wrench at each point (measured 5.12 %, 16.24 %).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "config/json_params.hpp"
#include "contact_models/rbf_function.hpp"
#include "contact_models/rbf_model.hpp"
#include "contact_models/spatial_rbf_function.hpp"
#include "io/hdf5_file.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"
#include "training/force_dataset.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;

const std::string kSampleConfig = "data/granular/rft3d_quadruped_samples.json";
const std::string kSamples = "data/granular/rft3d_quadruped_samples.h5";
const std::string kFitConfig = "data/granular/rft3d_quadruped_fit.json";
const std::string kModel = "data/granular/rft3d_quadruped_rbf.h5";
const std::string kPlanarConfig = "data/granular/rft3d_quadruped_planar.json";
const std::string kPlanarFitConfig = "data/granular/rft_quadruped_fit.json";
const std::string kPlanarModel = "data/granular/rft3d_quadruped_planar_rbf.h5";
// The stated bound (data/granular/README.md): the leave-one-point-out error relative to the largest
// wrench at the point, largest over points and vertices, and the largest per-vertex RMS.
constexpr double kLooLargest = 0.443, kLooVertexRms = 0.167;
// The cube directions that do not lift the foot (k ≤ 0): a buried foot that RFT holds on the way up
// makes the trot fall at dt = 50 ms (data/granular/README.md).
constexpr Eigen::Index kDirections = 17;

std::string commandLine(const std::vector<std::string>& args) {
  std::string s = "nmdp";
  for (const std::string& a : args) s += " " + shellQuote(a);
  return s;
}

void runOk(const std::vector<std::string>& args, const TempDir& dir) {
  const CliResult r = runNmdp(args, dir);
  ASSERT_TRUE(r.exited) << "nmdp was killed by a signal";
  ASSERT_EQ(r.exit_code, 0) << commandLine(args) << "\nstderr: " << r.err;
}

double reciprocalCondition(const std::string& model) {
  const std::string report = h5::File::openRead(model).readStringAttribute("/fit", "report");
  const std::string key = "reciprocal condition number ";
  const size_t at = report.find(key);
  if (at == std::string::npos) return 0.0;
  std::istringstream in(report.substr(at + key.size()));
  double rcond = 0.0;
  in >> rcond;
  return in ? rcond : 0.0;
}

Eigen::MatrixXd evaluateSpatial(const SpatialRbfFunction& f, const Eigen::MatrixX3d& features) {
  Eigen::MatrixXd W;
  f.evaluate(features, W, nullptr);
  return W;
}

TEST(Rft3dQuadrupedModel, TheCommandsRegenerateTheShippedSamplesAndModel) {
  TempDir dir;
  const std::string samples = dir.file("samples.h5"), model = dir.file("model.h5");
  runOk({"gen-rft", "--config", sourcePath(kSampleConfig), "--out", samples}, dir);
  const ForceDataset shipped_data = readForceDataset(sourcePath(kSamples)), data = readForceDataset(samples);
  ASSERT_EQ(shipped_data.features.rows(), data.features.rows());
  EXPECT_EQ(shipped_data.vertex, data.vertex);
  EXPECT_LE((shipped_data.features - data.features).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((shipped_data.wrench - data.wrench).cwiseAbs().maxCoeff(), 1e-12 * shipped_data.wrench.cwiseAbs().maxCoeff());

  runOk({"fit", "--data", samples, "--config", sourcePath(kFitConfig), "--model", "rbf", "--out", model, "--quiet"}, dir);
  const SpatialRbfFunction shipped(readSpatialRbfHdf5(sourcePath(kModel)).parameters);
  const SpatialRbfFunction regenerated(readSpatialRbfHdf5(model).parameters);
  ASSERT_EQ(shipped.vertexCount(), kDirections);
  ASSERT_EQ(regenerated.vertexCount(), kDirections);
  std::mt19937 rng(20261127);
  std::uniform_real_distribution<double> depth(-0.12, 0.0), tilt(-0.8, 0.8);
  Eigen::MatrixX3d f(500, 3);
  for (Eigen::Index i = 0; i < f.rows(); ++i) f.row(i) << depth(rng), tilt(rng), tilt(rng);
  const Eigen::MatrixXd a = evaluateSpatial(shipped, f), b = evaluateSpatial(regenerated, f);
  const double rcond = reciprocalCondition(model);
  ASSERT_GT(rcond, 0.0);
  // Another CPU or compiler rounds the solve differently, by up to about cond(A)·ε of the largest entry.
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), std::numeric_limits<double>::epsilon() / rcond * a.cwiseAbs().maxCoeff());

  // The leave-one-point-out error within the stated bound.
  const Eigen::MatrixXd loo = h5::File::openRead(model).readMatrix("/fit/loo_relative");
  ASSERT_EQ(loo.cols(), kDirections);
  EXPECT_LE(loo.maxCoeff(), kLooLargest);
  for (Eigen::Index j = 0; j < loo.cols(); ++j)
    EXPECT_LE(std::sqrt(loo.col(j).squaredNorm() / loo.rows()), kLooVertexRms) << "vertex " << j;
}

TEST(Rft3dQuadrupedModel, LoadsThroughTheRbfEntryAndReproducesItsData) {
  const std::unique_ptr<ContactModel> model =
      makeRbfModel({{"type", "rbf"}, {"file", sourcePath(kModel)}}, ConfigContext{"test: contacts.model", ""});
  EXPECT_EQ(model->vertexCount(), kDirections);
  const SpatialRbfFunction function(readSpatialRbfHdf5(sourcePath(kModel)).parameters);
  const h5::File file = h5::File::openRead(sourcePath(kModel));
  const Eigen::MatrixX3d points = file.readMatrix("/fit/points");
  const Eigen::MatrixXd values = file.readMatrix("/fit/values");
  EXPECT_LE((evaluateSpatial(function, points) - values).cwiseAbs().maxCoeff(), 1e-8 * values.cwiseAbs().maxCoeff());
}

// Between the samples: gen-rft on depths and tilts halfway between (and beyond) the model's.
TEST(Rft3dQuadrupedModel, ReproducesRftBetweenTheSamples) {
  TempDir dir;
  const std::string truth = dir.file("truth.h5");
  nlohmann::json config = nlohmann::json::parse(readText(sourcePath(kSampleConfig)));
  config["grid"]["depths"] = {-0.0025, -0.0075, -0.0125, -0.0175, -0.0225, -0.06};
  config["grid"]["betas"] = config["grid"]["gammas"] = {-0.6, -0.3, 0.0, 0.3, 0.6};
  runOk({"gen-rft", "--config", config.dump(), "--out", truth}, dir);
  const ForceDataset data = readForceDataset(truth);
  const SpatialRbfFunction function(readSpatialRbfHdf5(sourcePath(kModel)).parameters);
  const Eigen::MatrixXd W = evaluateSpatial(function, data.features);
  // Per point (kDirections samples each, one per vertex): the largest error over its samples relative to its
  // largest wrench entry.
  double worst = 0.0, sum2 = 0.0;
  int points = 0;
  for (Eigen::Index s = 0; s < data.features.rows(); s += kDirections) {
    double error = 0.0, scale = 0.0;
    for (Eigen::Index k = s; k < s + kDirections; ++k) {
      const int v = data.vertex[k];
      error = std::max(error, (W.block(k, 6 * v, 1, 6) - data.wrench.row(k)).cwiseAbs().maxCoeff());
      scale = std::max(scale, data.wrench.row(k).cwiseAbs().maxCoeff());
    }
    ASSERT_GT(scale, 0.0);
    worst = std::max(worst, error / scale);
    sum2 += (error / scale) * (error / scale);
    ++points;
  }
  const double rms = std::sqrt(sum2 / points);
  std::cout << points << " points between the samples: RMS " << 100 * rms << " %, worst " << 100 * worst << " %\n";
  EXPECT_LE(rms, 0.055);
  EXPECT_LE(worst, 0.165);
}

TEST(Rft3dQuadrupedModel, ThePlanarCounterpartIsWhatItsCommandsMake) {
  TempDir dir;
  const std::string samples = dir.file("planar_samples"), model = dir.file("planar.h5");
  runOk({"gen-rft", "--config", sourcePath(kPlanarConfig), "--out", samples}, dir);
  runOk({"fit", "--data", samples, "--config", sourcePath(kPlanarFitConfig), "--model", "rbf", "--out", model, "--quiet"},
        dir);
  const RbfFunction shipped(readRbfHdf5(sourcePath(kPlanarModel)).parameters);
  const RbfFunction regenerated(readRbfHdf5(model).parameters);
  ASSERT_EQ(shipped.vertexCount(), 13);
  std::mt19937 rng(20261127);
  std::uniform_real_distribution<double> depth(-0.12, 0.0), angle(-1.4, 1.4);
  Eigen::MatrixX2d f(500, 2);
  for (Eigen::Index i = 0; i < f.rows(); ++i) f.row(i) << depth(rng), angle(rng);
  Eigen::MatrixXd a, b;
  shipped.evaluate(f, a, nullptr, nullptr);
  regenerated.evaluate(f, b, nullptr, nullptr);
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(),
            std::numeric_limits<double>::epsilon() / reciprocalCondition(model) * a.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace nmdp::test
