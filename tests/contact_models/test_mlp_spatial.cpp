// The spatial (3-D) MLP feature function: derivatives of every Jacobian scheme against central
// differences of the function of (φ, β, γ), the schemes against each other, the HDF5 round trip, and
// spatial model files with wrong shapes, NaN or planar-only attributes.
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "io/hdf5_file.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp {
namespace {

using test::relativeError;
using test::TempFile;

constexpr int kVertices = 26;  // the default direction set of the spatial models

// A random 3-input network with a non-trivial normalization (fixed seeds), of the given envelope;
// SoftDepth comes with four zero anchors.
MlpParameters spatialParameters(MlpActivation activation = MlpActivation::Tanh,
                                MlpOutputEnvelope envelope = MlpOutputEnvelope::None, std::uint32_t seed = 7) {
  MlpParameters p = randomMlpParameters(2, 32, kVertices, activation, seed, MlpWrench::Spatial);
  p.input_mean = Eigen::Vector3d(-0.02, 0.1, -0.05);
  p.input_std = Eigen::Vector3d(0.03, 0.4, 0.3);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 6 * kVertices; ++i) {
    p.output_scale[i] = 50.0 + 100.0 * u(rng);
    p.output_offset[i] = -20.0 + 40.0 * u(rng);
  }
  p.output_envelope = envelope;
  if (envelope == MlpOutputEnvelope::SoftDepth) {
    p.envelope_width = 0.005;
    p.anchors.resize(4, 3);  // at least 0.333 apart (normalized), bumps of radius 0.3
    p.anchors << 0.0, 0.0, 0.0, 0.0, 0.3, 0.0, 0.01, 0.0, 0.1, 0.01, 0.3, -0.2;
    p.anchor_radius = 0.3;
  }
  return p;
}

// Rows inside and near the anchors' bumps, off the sagittal plane, and one above the surface.
Eigen::MatrixX3d spatialFeatures() {
  Eigen::MatrixX3d f(6, 3);
  f << -0.05, 0.3, 0.2, -0.01, -0.4, -0.3, 0.02, 0.05, 0.1, -0.004, 0.05, 0.02, 0.003, 0.28, -0.01, -0.08, 1.0, 0.6;
  return f;
}

// ∂W/∂f_d of every row by 4th-order central differences, step h = 1e-4 of that feature's spread.
Eigen::MatrixXd centralDifference(const MlpFunction& mlp, const Eigen::MatrixX3d& f, int d) {
  const double h = 1e-4 * mlp.parameters().input_std[d];
  Eigen::MatrixXd out, W;
  const std::array<double, 4> steps{-2 * h, -h, h, 2 * h}, weights{1.0 / 12, -8.0 / 12, 8.0 / 12, -1.0 / 12};
  for (int k = 0; k < 4; ++k) {
    Eigen::MatrixX3d g = f;
    g.col(d).array() += steps[k];
    mlp.evaluate(g, W, nullptr);
    if (k == 0) out = Eigen::MatrixXd::Zero(W.rows(), W.cols());
    out += weights[k] / h * W;
  }
  return out;
}

bool identical(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

struct SpatialCase {
  MlpActivation activation;
  MlpOutputEnvelope envelope;
  MlpJacobian jacobian;
};

std::string spatialCaseName(const ::testing::TestParamInfo<SpatialCase>& info) {
  std::string s = std::string(mlpActivationName(info.param.activation)) + "_" +
                  mlpOutputEnvelopeName(info.param.envelope) + "_" + mlpJacobianName(info.param.jacobian);
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

class MlpSpatialDerivatives : public ::testing::TestWithParam<SpatialCase> {};

// Every row's ∂W/∂φ, ∂W/∂β, ∂W/∂γ against central differences on that row's own scale; asking for
// no derivative gives the same values to a few ulps (another batch shape through the BLAS).
TEST_P(MlpSpatialDerivatives, MatchCentralDifferences) {
  const SpatialCase c = GetParam();
  const MlpFunction mlp(spatialParameters(c.activation, c.envelope), c.jacobian);
  const SpatialFeatureFunction& function = mlp;
  ASSERT_EQ(function.vertexCount(), kVertices);
  EXPECT_EQ(function.derivative(),
            c.jacobian == MlpJacobian::Tangents ? DerivativeSupport::Analytic : DerivativeSupport::Autograd);
  const Eigen::MatrixX3d f = spatialFeatures();
  Eigen::MatrixXd W;
  std::array<Eigen::MatrixXd, 3> dW;
  function.evaluate(f, W, &dW);
  ASSERT_EQ(W.rows(), f.rows());
  ASSERT_EQ(W.cols(), 6 * kVertices);
  for (int d = 0; d < 3; ++d) {
    ASSERT_EQ(dW[d].rows(), f.rows());
    ASSERT_EQ(dW[d].cols(), 6 * kVertices);
    const Eigen::MatrixXd fd = centralDifference(mlp, f, d);
    for (Eigen::Index r = 0; r < f.rows(); ++r)
      EXPECT_LT(relativeError(dW[d].row(r), fd.row(r)), 1e-6) << "feature " << d << " row " << r;
    EXPECT_GT(dW[d].cwiseAbs().maxCoeff(), 1.0) << "feature " << d;  // not trivially zero
  }
  Eigen::MatrixXd W0;
  function.evaluate(f, W0, nullptr);
  EXPECT_LT(test::ulpsOfLargest(W0, W), 64.0);
}

std::vector<SpatialCase> spatialCases() {
  std::vector<SpatialCase> out;
  for (MlpActivation a : {MlpActivation::Tanh, MlpActivation::Softplus, MlpActivation::Silu})
    for (MlpOutputEnvelope e : {MlpOutputEnvelope::None, MlpOutputEnvelope::Depth, MlpOutputEnvelope::SoftDepth})
      for (MlpJacobian j : {MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents})
        out.push_back({a, e, j});
  return out;
}

INSTANTIATE_TEST_SUITE_P(AllSchemes, MlpSpatialDerivatives, ::testing::ValuesIn(spatialCases()), spatialCaseName);

// The three schemes compute the same Jacobian: within a few ulps of its largest entry.
TEST(MlpSpatial, SchemesAgree) {
  const MlpParameters p = spatialParameters(MlpActivation::Silu, MlpOutputEnvelope::SoftDepth);
  const Eigen::MatrixX3d f = spatialFeatures();
  std::array<Eigen::MatrixXd, 3> reference;
  Eigen::MatrixXd W;
  MlpFunction(p, MlpJacobian::ForwardMode).evaluate(f, W, &reference);
  for (MlpJacobian j : {MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
    std::array<Eigen::MatrixXd, 3> dW;
    MlpFunction(p, j).evaluate(f, W, &dW);
    for (int d = 0; d < 3; ++d) EXPECT_LT(test::ulpsOfLargest(dW[d], reference[d]), 64.0) << mlpJacobianName(j) << " " << d;
  }
}

// The anchors are exact zeros of the spatial model too, whatever the network.
TEST(MlpSpatial, AnchorsAreZeros) {
  const MlpParameters p = spatialParameters(MlpActivation::Tanh, MlpOutputEnvelope::SoftDepth);
  Eigen::MatrixXd W;
  MlpFunction(p).evaluate(Eigen::MatrixX3d(p.anchors), W, nullptr);
  const Eigen::MatrixX3d f = spatialFeatures();
  Eigen::MatrixXd W_far;
  MlpFunction(p).evaluate(f, W_far, nullptr);
  EXPECT_LT(W.cwiseAbs().maxCoeff(), 1e-12 * W_far.cwiseAbs().maxCoeff());
}

// γ matters: the network's derivative in γ is not zero and a spatial MLP refuses to act as a planar one.
TEST(MlpSpatial, KindsAreKept) {
  const MlpFunction spatial(spatialParameters());
  EXPECT_EQ(spatial.wrench(), MlpWrench::Spatial);
  EXPECT_NE(spatial.describe().find("3-32-32-156"), std::string::npos) << spatial.describe();
  EXPECT_NE(spatial.describe().find("spatial"), std::string::npos) << spatial.describe();
  Eigen::MatrixXd W, a, b;
  EXPECT_THROW(spatial.evaluate(Eigen::MatrixX2d::Zero(1, 2), W, &a, &b), std::logic_error);
  const MlpFunction planar(randomMlpParameters(1, 8, 2, MlpActivation::Tanh, 3));
  EXPECT_THROW(planar.evaluate(Eigen::MatrixX3d::Zero(1, 3), W, nullptr), std::logic_error);
  // A planar network in a spatial MLP's parameters is inconsistent (input width 2, 3 expected).
  MlpParameters mixed = randomMlpParameters(1, 8, 2, MlpActivation::Tanh, 3);
  mixed.wrench = MlpWrench::Spatial;
  EXPECT_NE(mlpParameterProblem(mixed).find("'/mlp/input_mean'"), std::string::npos) << mlpParameterProblem(mixed);
}

// ----- the file --------------------------------------------------------------------------------------

TEST(MlpSpatialFile, RoundTripIsBitIdentical) {
  const MlpParameters p = spatialParameters(MlpActivation::Softplus, MlpOutputEnvelope::SoftDepth);
  TempFile file("spatial.h5");
  saveMlpModel(file.path(), p, SpatialGeometry{0.0, 0.004});
  const MlpModelFile m = loadMlpModel(file.path());
  EXPECT_EQ(m.parameters.wrench, MlpWrench::Spatial);
  EXPECT_EQ(m.spatialGeometry().cutoff, 0.0);
  EXPECT_EQ(m.spatialGeometry().cutoff_width, 0.004);
  EXPECT_EQ(m.parameters.anchors, p.anchors);
  const h5::File raw = h5::File::openRead(file.path());
  EXPECT_EQ(raw.readStringAttribute("/mlp", "wrench"), "spatial");
  EXPECT_EQ(raw.readDoubleAttribute("/mlp", "inputs"), 3.0);
  EXPECT_EQ(raw.readDoubleAttribute("/mlp", "format_version"), 5.0);  // older programs refuse it
  EXPECT_FALSE(raw.hasAttribute("/mlp", "torque_centre"));
  const Eigen::MatrixX3d f = spatialFeatures();
  Eigen::MatrixXd W1, W2;
  std::array<Eigen::MatrixXd, 3> d1, d2;
  MlpFunction(p).evaluate(f, W1, &d1);
  MlpFunction(m.parameters).evaluate(f, W2, &d2);
  EXPECT_TRUE(identical(W1, W2));
  for (int d = 0; d < 3; ++d) EXPECT_TRUE(identical(d1[d], d2[d]));
  // The planar writer refuses a spatial MLP (and the spatial writer a planar one).
  TempFile other("other.h5");
  EXPECT_THROW(saveMlpModel(other.path(), p, PlanarGeometry{}), std::invalid_argument);
  EXPECT_THROW(saveMlpModel(other.path(), randomMlpParameters(1, 4, 2, MlpActivation::Tanh, 1), SpatialGeometry{}),
               std::invalid_argument);
}

// Writes a spatial file by hand: `tweak` changes the parameters first, `extra` writes more attributes
// or datasets before the commit.
void writeSpatialFile(const std::string& path, const MlpParameters& p, const std::function<void(MlpParameters&)>& tweak,
                      const std::function<void(h5::File&)>& extra, const std::string& wrench = "spatial") {
  MlpParameters q = p;
  if (tweak) tweak(q);
  h5::File f = h5::File::createAtomic(path);
  f.writeStringAttribute("/", "nmdp_model", "mlp");
  f.createGroup("/mlp");
  f.writeDoubleAttribute("/mlp", "format_version", 5.0);
  f.writeStringAttribute("/mlp", "activation", "tanh");
  f.writeDoubleAttribute("/mlp", "layers", static_cast<double>(q.layers.size()));
  f.writeDoubleAttribute("/mlp", "vertices", kVertices);
  f.writeStringAttribute("/mlp", "wrench", wrench);
  f.writeDoubleAttribute("/mlp", "cutoff", 0.0);
  f.writeDoubleAttribute("/mlp", "cutoff_width", 0.005);
  f.writeVector("/mlp/input_mean", q.input_mean);
  f.writeVector("/mlp/input_std", q.input_std);
  f.writeVector("/mlp/output_scale", q.output_scale);
  f.writeVector("/mlp/output_offset", q.output_offset);
  for (size_t i = 0; i < q.layers.size(); ++i) {
    const std::string g = "/mlp/layer_" + std::to_string(i);
    f.createGroup(g);
    f.writeMatrix(g + "/weight", q.layers[i].weight);
    f.writeVector(g + "/bias", q.layers[i].bias);
  }
  if (extra) extra(f);
  f.commit();
}

void expectSpatialLoadError(const std::function<void(MlpParameters&)>& tweak, const std::function<void(h5::File&)>& extra,
                            const std::vector<std::string>& parts) {
  TempFile file("bad_spatial.h5");
  writeSpatialFile(file.path(), spatialParameters(), tweak, extra);
  try {
    loadMlpModel(file.path());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.path()), std::string::npos) << message;
    for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

TEST(MlpSpatialFile, CleanFileLoads) {
  TempFile file("clean_spatial.h5");
  writeSpatialFile(file.path(), spatialParameters(), nullptr, nullptr);
  EXPECT_EQ(loadMlpModel(file.path()).parameters.wrench, MlpWrench::Spatial);
}

TEST(MlpSpatialFile, PlanarInputWidth) {
  // layer 0 takes (phi, beta) only: the first layer of a planar network in a spatial file.
  expectSpatialLoadError([](MlpParameters& p) { p.layers[0].weight.conservativeResize(Eigen::NoChange, 2); }, nullptr,
                         {"'/mlp/layer_0/weight'", "32 x 2", "(phi, beta, gamma)"});
}

TEST(MlpSpatialFile, PlanarOutputWidth) {
  // 3 outputs per vertex, as a planar model has: the last layer and the scaling have 3K entries.
  expectSpatialLoadError(
      [](MlpParameters& p) {
        p.layers.back().weight.conservativeResize(3 * kVertices, Eigen::NoChange);
        p.layers.back().bias.conservativeResize(3 * kVertices);
      },
      nullptr, {"'/mlp/layer_2/weight'", "6K = 156"});
}

TEST(MlpSpatialFile, TwoInputMeans) {
  expectSpatialLoadError([](MlpParameters& p) { p.input_mean = Eigen::Vector2d(0.0, 0.1); }, nullptr,
                         {"'/mlp/input_mean'", "3 values", "phi, beta, gamma"});
}

TEST(MlpSpatialFile, OutputScaleOfPlanarSize) {
  expectSpatialLoadError([](MlpParameters& p) { p.output_scale.conservativeResize(3 * kVertices); }, nullptr,
                         {"'/mlp/output_scale'", "156 values", "6 per vertex"});
}

TEST(MlpSpatialFile, NaNWeight) {
  expectSpatialLoadError([](MlpParameters& p) { p.layers[1].weight(3, 4) = std::nan(""); }, nullptr,
                         {"'/mlp/layer_1/weight'", "non-finite"});
}

TEST(MlpSpatialFile, NaNInputStd) {
  expectSpatialLoadError([](MlpParameters& p) { p.input_std[2] = std::nan(""); }, nullptr,
                         {"'/mlp/input_std'", "non-finite"});
}

TEST(MlpSpatialFile, AnchorsOfTwoFeatures) {
  expectSpatialLoadError(nullptr,
                         [](h5::File& f) {
                           f.writeMatrix("/mlp/anchors", Eigen::MatrixXd::Zero(2, 2));
                           f.writeDoubleAttribute("/mlp", "anchor_radius", 0.1);
                         },
                         {"'/mlp/anchors'", "2 x 2", "x 3"});
}

TEST(MlpSpatialFile, TorqueCentreIsPlanarOnly) {
  expectSpatialLoadError(nullptr, [](h5::File& f) { f.writeDoubleAttribute("/mlp", "torque_centre", 0.1); },
                         {"'torque_centre'", "planar"});
}

TEST(MlpSpatialFile, InputsDisagreeWithWrench) {
  expectSpatialLoadError(nullptr, [](h5::File& f) { f.writeDoubleAttribute("/mlp", "inputs", 2.0); },
                         {"'inputs'", "must be 3"});
}

TEST(MlpSpatialFile, PlanarFeatureNames) {
  expectSpatialLoadError(nullptr, [](h5::File& f) { f.writeStrings("/mlp/feature_names", {"phi", "beta"}); },
                         {"'/mlp/feature_names'", "gamma"});
}

TEST(MlpSpatialFile, UnknownWrench) {
  TempFile file("bad_wrench.h5");
  writeSpatialFile(file.path(), spatialParameters(), nullptr, nullptr, "volumetric");
  try {
    loadMlpModel(file.path());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.path()), std::string::npos) << message;
    EXPECT_NE(message.find("'wrench'"), std::string::npos) << message;
    EXPECT_NE(message.find("\"spatial\""), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace nmdp
