// The MLP fit on 3-D data (training/mlp/mlp_fit.hpp, mlp_points.hpp): a small synthetic dataset of
// six-dimensional wrenches of (φ, β, γ) for the 26 default directions, fitted by a small network in
// about a second; the validation error it reaches, the model file, determinism, and the settings and
// data that 3-D fits refuse.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "io/hdf5_file.hpp"
#include "mlp_fit_fixtures.hpp"
#include "test_temp_dir.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace nmdp::test {
namespace {

// The default direction set: (i, j, k) ∈ {−1, 0, 1}³ \ {0}, normalized, i slowest.
std::vector<Eigen::Vector3d> defaultDirections() {
  std::vector<Eigen::Vector3d> out;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        if (i || j || k) out.push_back(Eigen::Vector3d(i, j, k).normalized());
  return out;
}

// A smooth stand-in for 3-D resistive force: the force resisting direction u grows linearly with the
// depth d = −φ and depends on the leg axis a(β, γ) through an anisotropic resistance; the torque
// about the foot point is that of the force at a point 2 cm up the leg plus a small drag torque.
Eigen::Matrix<double, 1, 6> syntheticWrench(double phi, double beta, double gamma, const Eigen::Vector3d& u) {
  const double d = -phi;
  const Eigen::Vector3d a(std::cos(gamma) * std::sin(beta), std::sin(gamma), std::cos(gamma) * std::cos(beta));
  const Eigen::Vector3d resistance(1.0 + 0.5 * a.x() * a.x() + 0.2 * a.y(), 1.0 + 0.5 * a.y() * a.y() - 0.2 * a.x(),
                                   2.0 + a.z());
  const Eigen::Vector3d F = -2e4 * d * resistance.cwiseProduct(u);
  const Eigen::Vector3d tau = (0.02 * a).cross(F) - 50.0 * d * u;
  Eigen::Matrix<double, 1, 6> w;
  w << tau.transpose(), F.transpose();
  return w;
}

ForceDataset spatialDataset() {
  const std::vector<Eigen::Vector3d> dirs = defaultDirections();
  std::vector<std::array<double, 3>> points;
  for (double phi : {-0.04, -0.03, -0.02, -0.01})
    for (double beta : {-0.6, -0.3, 0.0, 0.3, 0.6})
      for (double gamma : {-0.4, 0.0, 0.4}) points.push_back({phi, beta, gamma});
  const Eigen::Index N = static_cast<Eigen::Index>(points.size() * dirs.size());
  ForceDataset data;
  data.features.resize(N, 3);
  data.vertex.resize(N);
  data.wrench.resize(N, 6);
  Eigen::Index row = 0;
  for (const auto& p : points)
    for (size_t j = 0; j < dirs.size(); ++j, ++row) {
      data.features.row(row) << p[0], p[1], p[2];
      data.vertex[row] = static_cast<int>(j);
      data.wrench.row(row) = syntheticWrench(p[0], p[1], p[2], dirs[j]);
    }
  data.feature_names = {"phi", "beta", "gamma"};
  data.feature_units = {"m", "rad", "rad"};
  data.wrench_names = {"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"};
  data.wrench_units = {"N m", "N m", "N m", "N", "N", "N"};
  data.source = "synthetic 3-D wrenches (test_mlp_spatial_fit.cpp)";
  return data;
}

FitConfig spatialConfig() {
  FitConfig c;
  c.mlp.hidden_layers = 2;
  c.mlp.width = 24;
  c.mlp.max_epochs = 1500;
  c.mlp.learning_rate = 1e-2;
  c.mlp.final_learning_rate = 1e-4;
  c.mlp.validation_fraction = 0.2;
  c.mlp.patience = 0;
  // W = (−φ) N: the synthetic wrench is linear in the depth, so N depends on the tilts only (without
  // the envelope the same fit reaches 6.9 % largest, 3.6 % RMS).
  c.mlp.output_envelope = MlpOutputEnvelope::Depth;
  return c;
}

// Largest and RMS over the validation points of the per-point error (largest over the vertices).
std::pair<double, double> validationError(const MlpFit& fit) {
  double largest = 0.0, sum2 = 0.0;
  int n = 0;
  for (Eigen::Index i = 0; i < fit.relative.rows(); ++i)
    if (fit.validation[i]) {
      const double e = fit.relative.row(i).maxCoeff();
      largest = std::max(largest, e);
      sum2 += e * e;
      ++n;
    }
  return {largest, n ? std::sqrt(sum2 / n) : 0.0};
}

TEST(MlpSpatialFit, ReachesTheStatedValidationError) {
  const MlpFitOutcome out = fitMlpToDataset(spatialDataset(), spatialConfig(), "synthetic 3-D");
  ASSERT_TRUE(out.spatial());
  const MlpFit& fit = out.record.fit;
  EXPECT_EQ(fit.parameters.sizes(), (std::vector<int>{3, 24, 24, 156}));
  EXPECT_EQ(out.record.points.pointCount(), 60);
  EXPECT_EQ(out.record.points.vertexCount(), 26);
  ASSERT_EQ(fit.relative.cols(), 26);
  int held = 0;
  for (bool v : fit.validation) held += v;
  EXPECT_EQ(held, 12);
  const auto [largest, rms] = validationError(fit);
  // Measured: largest 0.22 %, RMS 0.12 % of the largest wrench at the point (1500 epochs, ~1 s).
  EXPECT_LT(largest, 0.005);
  EXPECT_LT(rms, 0.003);
  // The report states the kind and the per-vertex validation errors.
  const std::string report = formatMlpFitReport(out.record);
  EXPECT_NE(report.find("3-D data"), std::string::npos) << report;
  EXPECT_NE(report.find("network: 3-24-24-156"), std::string::npos) << report;
  EXPECT_NE(report.find("max(valid.)"), std::string::npos) << report;
  EXPECT_EQ(out.record.settings.count("torque_centre"), 0u) << out.record.settings.dump();
}

// The fitted model in the file is the one in memory: same evaluation bit for bit; the /fit group
// holds the 3-D points.
TEST(MlpSpatialFit, ModelFileHoldsTheFit) {
  FitConfig c = spatialConfig();
  c.mlp.max_epochs = 50;
  c.cutoff_width = 0.004;
  const MlpFitOutcome out = fitMlpToDataset(spatialDataset(), c, "synthetic 3-D");
  TempFile file("spatial_fit.h5");
  saveMlpFit(file.path(), out.record, out.geometry);
  const MlpModelFile m = loadMlpModel(file.path());
  ASSERT_EQ(m.parameters.wrench, MlpWrench::Spatial);
  EXPECT_EQ(m.spatialGeometry().cutoff, 0.0);
  EXPECT_EQ(m.spatialGeometry().cutoff_width, 0.004);
  const Eigen::MatrixX3d f = out.record.points.features;
  Eigen::MatrixXd W_file, W_fit;
  MlpFunction(m.parameters).evaluate(f, W_file, nullptr);
  MlpFunction(out.record.fit.parameters).evaluate(f, W_fit, nullptr);
  EXPECT_TRUE(W_file == W_fit);
  EXPECT_TRUE((W_fit - out.record.points.values) == out.record.fit.error);
  const h5::File raw = h5::File::openRead(file.path());
  EXPECT_EQ(raw.readMatrix("/fit/points").cols(), 3);
  EXPECT_EQ(raw.readMatrix("/fit/values").cols(), 156);
}

TEST(MlpSpatialFit, IsDeterministic) {
  FitConfig c = spatialConfig();
  c.mlp.max_epochs = 40;
  TempFile a("a.h5"), b("b.h5");
  const MlpFitOutcome fa = fitMlpToDataset(spatialDataset(), c, "synthetic 3-D");
  saveMlpFit(a.path(), fa.record, fa.geometry);
  const MlpFitOutcome fb = fitMlpToDataset(spatialDataset(), c, "synthetic 3-D");
  saveMlpFit(b.path(), fb.record, fb.geometry);
  expectSameModelFiles(a.path(), b.path(), true);
}

// Zero anchors and the soft depth envelope work on 3-D points: the anchored zero-wrench points are
// exact zeros of the fitted model.
TEST(MlpSpatialFit, AnchorsAtTheSurfacePoints) {
  ForceDataset data = spatialDataset();
  const Eigen::Index N = data.features.rows();
  data.features.conservativeResize(N + 26, Eigen::NoChange);
  data.vertex.conservativeResize(N + 26);
  data.wrench.conservativeResize(N + 26, Eigen::NoChange);
  for (int j = 0; j < 26; ++j) {  // one surface point (φ = 0) with zero wrenches
    data.features.row(N + j) << 0.0, 0.3, -0.4;
    data.vertex[N + j] = j;
    data.wrench.row(N + j).setZero();
  }
  FitConfig c = spatialConfig();
  c.mlp.max_epochs = 50;
  c.mlp.validation_fraction = 0.0;
  c.mlp.zero_anchors = true;
  c.mlp.output_envelope = MlpOutputEnvelope::SoftDepth;
  const MlpFitOutcome out = fitMlpToDataset(data, c, "synthetic 3-D");
  const MlpParameters& p = out.record.fit.parameters;
  ASSERT_EQ(p.anchors.rows(), 1);
  EXPECT_EQ(p.anchors.row(0), Eigen::RowVector3d(0.0, 0.3, -0.4));
  Eigen::MatrixXd W;
  MlpFunction(p).evaluate(Eigen::MatrixX3d(p.anchors), W, nullptr);
  EXPECT_LT(W.cwiseAbs().maxCoeff(), 1e-12 * out.record.points.values.cwiseAbs().maxCoeff());
}

TEST(MlpSpatialFit, RefusesPlanarOnlySettings) {
  FitConfig c = spatialConfig();
  c.torque_centre = 0.1;
  try {
    fitMlpToDataset(spatialDataset(), c, "data3d.h5");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("data3d.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("torque_centre"), std::string::npos) << e.what();
  }
  c = spatialConfig();
  c.mlp.teacher_grid = {5, 5};
  try {
    fitMlpToDataset(spatialDataset(), c, "data3d.h5");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mlp.teacher_grid"), std::string::npos) << e.what();
  }
}

TEST(MlpSpatialFit, RefusesDataOfAnotherLayout) {
  ForceDataset data = spatialDataset();
  data.wrench_names = {"F_x", "F_y", "F_z", "tau_x", "tau_y", "tau_z"};  // forces first
  try {
    fitMlpToDataset(data, spatialConfig(), "data3d.h5");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("data3d.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'/wrench'"), std::string::npos) << e.what();
  }
  data = spatialDataset();
  data.feature_names = {"phi", "gamma", "beta"};
  EXPECT_THROW(fitMlpToDataset(data, spatialConfig(), "data3d.h5"), InputError);
  // A missing vertex at one point.
  data = spatialDataset();
  data.features.conservativeResize(data.features.rows() - 1, Eigen::NoChange);
  data.vertex.conservativeResize(data.vertex.size() - 1);
  data.wrench.conservativeResize(data.wrench.rows() - 1, Eigen::NoChange);
  try {
    fitMlpToDataset(data, spatialConfig(), "data3d.h5");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no sample of vertex 25"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nmdp::test
