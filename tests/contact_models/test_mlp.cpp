// The MLP contact model (DESIGN.md §7.3): autograd derivatives against central differences, batch
// and run-to-run bit-identity, the HDF5 file round trip, the full PlanarWrenchModel chain rule, the
// JSON factory, and bad model files.
#include <map>
#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <random>
#include <thread>

#include "contact_derivative_check.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/mlp/mlp_model.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "io/hdf5_file.hpp"
#include "common/input_error.hpp"
#include "terrain/plane.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp {
namespace {

using test::relativeError;
using test::TempFile;

constexpr int kVertices = 26;

// A random 2×64 network with a non-trivial normalization (fixed seeds).
MlpParameters testParameters(MlpActivation activation = MlpActivation::Tanh, std::uint32_t seed = 7) {
  MlpParameters p = randomMlpParameters(2, 64, kVertices, activation, seed);
  p.input_mean = Eigen::Vector2d(-0.02, 0.1);
  p.input_std = Eigen::Vector2d(0.03, 0.4);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 3 * kVertices; ++i) {
    p.output_scale[i] = 50.0 + 100.0 * u(rng);
    p.output_offset[i] = -20.0 + 40.0 * u(rng);
  }
  return p;
}

// The published RBF model's geometry (torque centre, cut-off and its band, in m).
PlanarGeometry testGeometry() { return PlanarGeometry{0.1572, 0.1, 0.02}; }

Eigen::MatrixX2d testFeatures() {
  Eigen::MatrixX2d f(4, 2);
  f << -0.05, 0.3, -0.01, -0.4, 0.02, 0.05, -0.08, 1.0;
  return f;
}

bool identical(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

// dW/dφ (d = 0) or dW/dβ (d = 1) of every row by central differences (contact_derivative_check.hpp)
// with a step of 1e-4 of that feature's normalization.
Eigen::MatrixXd centralDifference(const MlpFunction& mlp, const Eigen::MatrixX2d& f, int d, int order = 2) {
  return test::centralFeatureDerivative(mlp, f, d, 1e-4 * mlp.parameters().input_std[d], order);
}

// Each row's dW/dφ and dW/dβ against central differences, on that row's own scale (rows near a zero
// of W must match too, not only the batch as a whole).
void expectRowsMatchCentralDifferences(const MlpFunction& mlp, const Eigen::MatrixX2d& f, const Eigen::MatrixXd& dphi,
                                       const Eigen::MatrixXd& dbeta, double tolerance) {
  for (int d = 0; d < 2; ++d) {
    const Eigen::MatrixXd fd = centralDifference(mlp, f, d);
    const Eigen::MatrixXd& ad = d == 0 ? dphi : dbeta;
    for (Eigen::Index r = 0; r < f.rows(); ++r)
      EXPECT_LT(relativeError(ad.row(r), fd.row(r)), tolerance) << (d == 0 ? "dW/dphi" : "dW/dbeta") << " row " << r;
  }
}

// Asking for one direction only gives the same numbers as asking for both, bit for bit: the function
// computes both directions either way (one path, whatever the BLAS kernels of this CPU).
void expectOneDirectionAsBoth(const MlpFunction& mlp, const Eigen::MatrixX2d& f, const Eigen::MatrixXd& W,
                              const Eigen::MatrixXd& dphi, const Eigen::MatrixXd& dbeta) {
  Eigen::MatrixXd W1, dphi1, dbeta1;
  mlp.evaluate(f, W1, &dphi1, nullptr);
  EXPECT_TRUE(identical(dphi1, dphi));
  EXPECT_TRUE(identical(W1, W));
  mlp.evaluate(f, W1, nullptr, &dbeta1);
  EXPECT_TRUE(identical(dbeta1, dbeta));
  EXPECT_TRUE(identical(W1, W));
}

// ----- the feature function ------------------------------------------------------------------------

struct FunctionCase {
  MlpActivation activation;
  MlpJacobian jacobian;
};
void PrintTo(const FunctionCase& c, std::ostream* os) {
  *os << mlpActivationName(c.activation) << "_" << mlpJacobianName(c.jacobian);
}

class MlpDerivatives : public ::testing::TestWithParam<FunctionCase> {};

TEST_P(MlpDerivatives, MatchCentralDifferences) {
  const MlpFunction mlp(testParameters(GetParam().activation), GetParam().jacobian);
  ASSERT_EQ(mlp.vertexCount(), kVertices);
  EXPECT_EQ(mlp.derivative(), GetParam().jacobian == MlpJacobian::Tangents ? DerivativeSupport::Analytic
                                                                            : DerivativeSupport::Autograd);
  const Eigen::MatrixX2d f = testFeatures();
  Eigen::MatrixXd W, dphi, dbeta;
  mlp.evaluate(f, W, &dphi, &dbeta);
  ASSERT_EQ(W.rows(), 4);
  ASSERT_EQ(W.cols(), 3 * kVertices);

  for (int d = 0; d < 2; ++d) {
    const Eigen::MatrixXd fd = centralDifference(mlp, f, d);
    const Eigen::MatrixXd& ad = d == 0 ? dphi : dbeta;
    EXPECT_LT(relativeError(ad, fd), 1e-7) << (d == 0 ? "dW/dphi" : "dW/dbeta");
    EXPECT_GT(ad.cwiseAbs().maxCoeff(), 1.0);  // not trivially zero
  }

  expectOneDirectionAsBoth(mlp, f, W, dphi, dbeta);
}

// "tanh_forward_mode": the activation and the Jacobian scheme, as a test name.
std::string functionCaseName(const ::testing::TestParamInfo<FunctionCase>& info) {
  std::string s = std::string(mlpActivationName(info.param.activation)) + "_" + mlpJacobianName(info.param.jacobian);
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(ActivationsAndSchemes, MlpDerivatives,
                         ::testing::Values(FunctionCase{MlpActivation::Tanh, MlpJacobian::ForwardMode},
                                           FunctionCase{MlpActivation::Softplus, MlpJacobian::ForwardMode},
                                           FunctionCase{MlpActivation::Silu, MlpJacobian::ForwardMode},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::DoubleBackward},
                                           FunctionCase{MlpActivation::Softplus, MlpJacobian::DoubleBackward},
                                           FunctionCase{MlpActivation::Silu, MlpJacobian::DoubleBackward},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::Tangents},
                                           FunctionCase{MlpActivation::Softplus, MlpJacobian::Tangents},
                                           FunctionCase{MlpActivation::Silu, MlpJacobian::Tangents}),
                         functionCaseName);

// How far the values of two Jacobian schemes may be apart, in ulps of the largest value.
constexpr double kSchemesUlps = 4;

TEST(MlpFunction, JacobianSchemesAgree) {
  for (MlpActivation activation : {MlpActivation::Tanh, MlpActivation::Softplus, MlpActivation::Silu}) {
    const MlpFunction forward(testParameters(activation), MlpJacobian::ForwardMode);
    Eigen::MatrixXd W1, p1, b1;
    forward.evaluate(testFeatures(), W1, &p1, &b1);
    for (MlpJacobian other : {MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
      const MlpFunction mlp(testParameters(activation), other);
      Eigen::MatrixXd W2, p2, b2;
      mlp.evaluate(testFeatures(), W2, &p2, &b2);
      // Not bit for bit: ForwardMode and DoubleBackward carry the values through 2B stacked rows,
      // Tangents through B rows, and the BLAS may round another shape differently.
      EXPECT_LE(test::ulpsOfLargest(W1, W2), kSchemesUlps) << mlpActivationName(activation) << " " << mlpJacobianName(other);
      EXPECT_LT(relativeError(p2, p1), 1e-13) << mlpActivationName(activation) << " " << mlpJacobianName(other);
      EXPECT_LT(relativeError(b2, b1), 1e-13) << mlpActivationName(activation) << " " << mlpJacobianName(other);
    }
  }
}

// Batching must not change results beyond round-off. Not bit-for-bit: the BLAS (OpenBLAS) picks
// its kernels by matrix size, so a 1-row and a 4-row product may round differently; the same call
// repeated is bit-identical (SameEvaluationTwiceIsBitIdentical).
TEST(MlpFunction, BatchEqualsSingleEvaluationsToRoundOff) {
  for (MlpJacobian jacobian : {MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
    const MlpFunction mlp(testParameters(), jacobian);
    const Eigen::MatrixX2d f = testFeatures();
    Eigen::MatrixXd W, dphi, dbeta, W0;
    mlp.evaluate(f, W, &dphi, &dbeta);
    mlp.evaluate(f, W0, nullptr, nullptr);
    EXPECT_LT(relativeError(W, W0), 1e-13) << "values with and without derivatives";
    for (int b = 0; b < f.rows(); ++b) {
      const Eigen::MatrixX2d row = f.row(b);
      Eigen::MatrixXd w, p, q, w0;
      mlp.evaluate(row, w, &p, &q);
      mlp.evaluate(row, w0, nullptr, nullptr);
      EXPECT_LT(relativeError(w, W.row(b)), 1e-13) << mlpJacobianName(jacobian) << " row " << b;
      EXPECT_LT(relativeError(w0, W.row(b)), 1e-13) << mlpJacobianName(jacobian) << " row " << b;
      EXPECT_LT(relativeError(p, dphi.row(b)), 1e-13) << mlpJacobianName(jacobian) << " row " << b;
      EXPECT_LT(relativeError(q, dbeta.row(b)), 1e-13) << mlpJacobianName(jacobian) << " row " << b;
    }
  }
}

TEST(MlpFunction, SameEvaluationTwiceIsBitIdentical) {
  const MlpFunction mlp(testParameters());
  Eigen::MatrixXd W1, p1, b1, W2, p2, b2;
  mlp.evaluate(testFeatures(), W1, &p1, &b1);
  mlp.evaluate(testFeatures(), W2, &p2, &b2);
  EXPECT_TRUE(identical(W1, W2));
  EXPECT_TRUE(identical(p1, p2));
  EXPECT_TRUE(identical(b1, b2));
  // A second instance built from the same parameters too.
  const MlpFunction other(testParameters());
  Eigen::MatrixXd W3, p3, b3;
  other.evaluate(testFeatures(), W3, &p3, &b3);
  EXPECT_TRUE(identical(W1, W3));
  EXPECT_TRUE(identical(p1, p3));
  EXPECT_TRUE(identical(b1, b3));
}

TEST(MlpFunction, ConcurrentEvaluationsAgree) {
  // One function shared by threads (libtorch's single forward-AD level is taken in turns).
  for (MlpJacobian jacobian : {MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
    const MlpFunction mlp(testParameters(), jacobian);
    Eigen::MatrixXd W, p, b;
    mlp.evaluate(testFeatures(), W, &p, &b);
    std::atomic<int> mismatches{0}, errors{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 3; ++t) {
      threads.emplace_back([&] {
        try {
          for (int i = 0; i < 30; ++i) {
            Eigen::MatrixXd Wt, pt, bt;
            mlp.evaluate(testFeatures(), Wt, &pt, &bt);
            if (!identical(Wt, W) || !identical(pt, p) || !identical(bt, b)) ++mismatches;
          }
        } catch (...) {
          ++errors;
        }
      });
    }
    for (std::thread& t : threads) t.join();
    EXPECT_EQ(errors.load(), 0) << mlpJacobianName(jacobian);
    EXPECT_EQ(mismatches.load(), 0) << mlpJacobianName(jacobian);
  }
}

TEST(MlpFunction, ZeroRowsAndDescribe) {
  const MlpFunction mlp(testParameters());
  Eigen::MatrixXd W, p, b;
  mlp.evaluate(Eigen::MatrixX2d(0, 2), W, &p, &b);
  EXPECT_EQ(W.rows(), 0);
  EXPECT_EQ(W.cols(), 3 * kVertices);
  EXPECT_EQ(mlp.describe(), "MLP 2-64-64-78 tanh, 26 vertices, forward-mode autograd");
}

TEST(MlpFunction, NormalizationIsApplied) {
  // One affine layer and identity weights: W = scale ⊙ (A (f − mean)/std + b) + offset, by hand.
  MlpParameters p;
  MlpLayer l;
  l.weight = Eigen::MatrixXd::Zero(3, 2);
  l.weight << 1, 2, 3, 4, 5, 6;
  l.bias = Eigen::Vector3d(0.5, -0.5, 1.0);
  p.layers.push_back(l);
  p.input_mean = Eigen::Vector2d(0.1, -0.2);
  p.input_std = Eigen::Vector2d(2.0, 4.0);
  p.output_scale = Eigen::Vector3d(10, 20, 30);
  p.output_offset = Eigen::Vector3d(1, 2, 3);
  const MlpFunction mlp(p);
  Eigen::MatrixX2d f(1, 2);
  f << 0.3, 0.6;
  Eigen::MatrixXd W, dphi, dbeta;
  mlp.evaluate(f, W, &dphi, &dbeta);
  const Eigen::Vector2d x((0.3 - 0.1) / 2.0, (0.6 + 0.2) / 4.0);
  const Eigen::Vector3d expected = p.output_scale.cwiseProduct(l.weight * x + l.bias) + p.output_offset;
  EXPECT_LT((W.row(0).transpose() - expected).norm(), 1e-12);
  EXPECT_LT((dphi.row(0).transpose() - p.output_scale.cwiseProduct(l.weight.col(0)) / 2.0).norm(), 1e-12);
  EXPECT_LT((dbeta.row(0).transpose() - p.output_scale.cwiseProduct(l.weight.col(1)) / 4.0).norm(), 1e-12);
}

TEST(MlpFunction, InconsistentParametersAreRejected) {
  MlpParameters p = testParameters();
  p.layers[1].weight.resize(64, 32);
  p.layers[1].weight.setZero();
  EXPECT_THROW(MlpFunction{p}, std::invalid_argument);
  p = testParameters();
  p.layers[0].weight(3, 1) = std::nan("");
  EXPECT_THROW(MlpFunction{p}, std::invalid_argument);
  p = testParameters();
  p.input_std[1] = 0.0;
  EXPECT_THROW(MlpFunction{p}, std::invalid_argument);
  EXPECT_THROW(randomMlpParameters(2, 0, 26, MlpActivation::Tanh, 1), std::invalid_argument);
  MlpActivation a;
  EXPECT_FALSE(parseMlpActivation("relu", &a));
  EXPECT_NE(mlpActivationProblem("relu").find("ReLU"), std::string::npos);
  EXPECT_NE(mlpActivationProblem("gelu").find("valid activations"), std::string::npos);
  EXPECT_EQ(mlpActivationProblem("silu"), "");
}

// ----- the depth envelope W = (−φ) ⊙ N --------------------------------------------------------------

MlpParameters envelopeParameters(MlpActivation activation = MlpActivation::Tanh) {
  MlpParameters p = testParameters(activation);
  p.output_envelope = MlpOutputEnvelope::Depth;
  return p;
}

// Rows below, at and above the surface (φ = 0 exactly in rows 1 and 4).
Eigen::MatrixX2d envelopeFeatures() {
  Eigen::MatrixX2d f(6, 2);
  f << -0.05, 0.3, 0.0, -0.4, 0.02, 0.05, -0.08, 1.0, 0.0, 0.7, -0.0004, -0.2;
  return f;
}

class MlpEnvelopeDerivatives : public ::testing::TestWithParam<FunctionCase> {};

TEST_P(MlpEnvelopeDerivatives, MatchCentralDifferences) {
  const MlpFunction mlp(envelopeParameters(GetParam().activation), GetParam().jacobian);
  const Eigen::MatrixX2d f = envelopeFeatures();
  Eigen::MatrixXd W, dphi, dbeta;
  mlp.evaluate(f, W, &dphi, &dbeta);
  ASSERT_EQ(W.rows(), f.rows());
  ASSERT_EQ(dphi.cols(), 3 * kVertices);
  EXPECT_LT(relativeError(dphi, centralDifference(mlp, f, 0)), 1e-7) << "dW/dphi";
  EXPECT_LT(relativeError(dbeta, centralDifference(mlp, f, 1)), 1e-7) << "dW/dbeta";
  // Row by row too: the rows at the surface (small W, the derivative −N) must match on their own scale.
  expectRowsMatchCentralDifferences(mlp, f, dphi, dbeta, 1e-6);
  EXPECT_GT(dphi.cwiseAbs().maxCoeff(), 1.0);  // not trivially zero
  EXPECT_GT(dbeta.cwiseAbs().maxCoeff(), 1.0);

  expectOneDirectionAsBoth(mlp, f, W, dphi, dbeta);
}

INSTANTIATE_TEST_SUITE_P(ActivationsAndSchemes, MlpEnvelopeDerivatives,
                         ::testing::Values(FunctionCase{MlpActivation::Tanh, MlpJacobian::ForwardMode},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::DoubleBackward},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::Tangents},
                                           FunctionCase{MlpActivation::Softplus, MlpJacobian::ForwardMode},
                                           FunctionCase{MlpActivation::Silu, MlpJacobian::Tangents}),
                         functionCaseName);

TEST(MlpEnvelope, IsTheDepthTimesTheNetworkAndZeroAtTheSurface) {
  const Eigen::MatrixX2d f = envelopeFeatures();
  for (MlpJacobian jacobian : {MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
    const MlpFunction plain(testParameters(), jacobian), enveloped(envelopeParameters(), jacobian);
    Eigen::MatrixXd N, dN_phi, dN_beta, W, dW_phi, dW_beta, W0;
    plain.evaluate(f, N, &dN_phi, &dN_beta);
    enveloped.evaluate(f, W, &dW_phi, &dW_beta);
    enveloped.evaluate(f, W0, nullptr, nullptr);
    for (Eigen::Index r = 0; r < f.rows(); ++r) {
      const double depth = 0.0 - f(r, 0);  // +0 at the surface, as mlp_function.cpp computes it
      // W = (−φ) N and its derivatives, as the header defines them (the same roundings: bit for bit).
      EXPECT_TRUE(identical(W.row(r), depth * N.row(r))) << mlpJacobianName(jacobian) << " row " << r;
      EXPECT_TRUE(identical(dW_beta.row(r), depth * dN_beta.row(r))) << mlpJacobianName(jacobian) << " row " << r;
      EXPECT_TRUE(identical(dW_phi.row(r), depth * dN_phi.row(r) - N.row(r))) << mlpJacobianName(jacobian) << " row " << r;
      if (f(r, 0) == 0.0) {
        // At the surface: exactly zero wrench (with and without derivatives) and zero dW/dβ; dW/dφ = −N.
        EXPECT_EQ(W.row(r).cwiseAbs().maxCoeff(), 0.0) << mlpJacobianName(jacobian) << " row " << r;
        EXPECT_EQ(W0.row(r).cwiseAbs().maxCoeff(), 0.0) << mlpJacobianName(jacobian) << " row " << r;
        EXPECT_EQ(dW_beta.row(r).cwiseAbs().maxCoeff(), 0.0) << mlpJacobianName(jacobian) << " row " << r;
        EXPECT_TRUE(identical(dW_phi.row(r), -N.row(r))) << mlpJacobianName(jacobian) << " row " << r;
        EXPECT_GT(N.row(r).cwiseAbs().maxCoeff(), 1.0);  // N itself is not zero there
      }
    }
    EXPECT_LT(relativeError(W0, W), 1e-13) << "values with and without derivatives, " << mlpJacobianName(jacobian);
  }
  EXPECT_EQ(MlpFunction(envelopeParameters()).describe(),
            "MLP 2-64-64-78 tanh, W = (-phi) N depth envelope, 26 vertices, forward-mode autograd");
  EXPECT_STREQ(mlpOutputEnvelopeName(MlpOutputEnvelope::None), "none");
  EXPECT_STREQ(mlpOutputEnvelopeName(MlpOutputEnvelope::Depth), "depth");
  MlpOutputEnvelope e = MlpOutputEnvelope::None;
  EXPECT_TRUE(parseMlpOutputEnvelope("depth", &e));
  EXPECT_EQ(e, MlpOutputEnvelope::Depth);
  EXPECT_FALSE(parseMlpOutputEnvelope("Depth", &e));
  EXPECT_EQ(e, MlpOutputEnvelope::Depth);
}

// ----- zero anchors W = N − Σ_a b_a N(ξ_a) ------------------------------------------------------------

// Four anchors, 0.333 apart at least in normalized units (input_std 0.03, 0.4), bumps of radius 0.3.
MlpParameters anchorParameters(MlpActivation activation = MlpActivation::Tanh) {
  MlpParameters p = testParameters(activation);
  p.anchors.resize(4, 2);
  p.anchors << 0.0, 0.0, 0.0, 0.3, 0.01, 0.0, 0.01, 0.3;
  p.anchor_radius = 0.3;
  return p;
}

// Rows inside the bumps (near the anchors), at two anchors and one far from all of them.
Eigen::MatrixX2d anchorFeatures() {
  Eigen::MatrixX2d f(6, 2);
  f << -0.004, 0.05, 0.003, 0.28, 0.0, 0.3, 0.01, 0.0, -0.002, 0.0, -0.05, -0.6;
  return f;
}

class MlpAnchorDerivatives : public ::testing::TestWithParam<FunctionCase> {};

TEST_P(MlpAnchorDerivatives, MatchCentralDifferences) {
  const MlpFunction mlp(anchorParameters(GetParam().activation), GetParam().jacobian);
  const Eigen::MatrixX2d f = anchorFeatures();
  Eigen::MatrixXd W, dphi, dbeta;
  mlp.evaluate(f, W, &dphi, &dbeta);
  expectRowsMatchCentralDifferences(mlp, f, dphi, dbeta, 1e-6);
  expectOneDirectionAsBoth(mlp, f, W, dphi, dbeta);
}

INSTANTIATE_TEST_SUITE_P(ActivationsAndSchemes, MlpAnchorDerivatives,
                         ::testing::Values(FunctionCase{MlpActivation::Tanh, MlpJacobian::ForwardMode},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::DoubleBackward},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::Tangents},
                                           FunctionCase{MlpActivation::Silu, MlpJacobian::Tangents}),
                         functionCaseName);

TEST(MlpAnchors, ZeroAtTheAnchorsTheNetworkAwayAndItsGradientAtThem) {
  const MlpParameters p = anchorParameters();
  for (MlpJacobian jacobian : {MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents}) {
    const MlpFunction plain(testParameters(), jacobian), anchored(p, jacobian);
    Eigen::MatrixXd N, dN_phi, dN_beta, W, dW_phi, dW_beta, W0;
    plain.evaluate(p.anchors, N, &dN_phi, &dN_beta);
    anchored.evaluate(p.anchors, W, &dW_phi, &dW_beta);
    anchored.evaluate(p.anchors, W0, nullptr, nullptr);
    EXPECT_GT(N.cwiseAbs().maxCoeff(), 1.0);  // the network is not zero there ...
    EXPECT_LT(W.cwiseAbs().maxCoeff(), 1e-10 * N.cwiseAbs().maxCoeff()) << mlpJacobianName(jacobian);  // ... W is
    EXPECT_LT(W0.cwiseAbs().maxCoeff(), 1e-10 * N.cwiseAbs().maxCoeff()) << mlpJacobianName(jacobian);
    // ψ'(0) = 0 and the other bumps vanish there: the gradient at an anchor is the network's.
    EXPECT_TRUE(identical(dW_phi, dN_phi)) << mlpJacobianName(jacobian);
    EXPECT_TRUE(identical(dW_beta, dN_beta)) << mlpJacobianName(jacobian);
    // Outside every bump the model is the network, bit for bit.
    const Eigen::MatrixX2d far = (Eigen::MatrixX2d(2, 2) << -0.05, -0.6, 0.02, 0.9).finished();
    plain.evaluate(far, N, &dN_phi, &dN_beta);
    anchored.evaluate(far, W, &dW_phi, &dW_beta);
    EXPECT_TRUE(identical(W, N));
    EXPECT_TRUE(identical(dW_phi, dN_phi));
    EXPECT_TRUE(identical(dW_beta, dN_beta));
  }
  // Inside a bump, W = N − b_a N(ξ_a) with the documented bump.
  const MlpFunction plain(testParameters()), anchored(p);
  Eigen::MatrixX2d f(1, 2);
  f << -0.004, 0.05;
  Eigen::MatrixXd N, Na, W, b;
  plain.evaluate(f, N, nullptr, nullptr);
  plain.evaluate(p.anchors.topRows(1), Na, nullptr, nullptr);
  anchored.evaluate(f, W, nullptr, nullptr);
  const double r = std::hypot(0.004 / 0.03, 0.05 / 0.4) / 0.3;
  const double psi = std::pow(1 - r, 6) * (35 * r * r + 18 * r + 3) / 3;
  mlpAnchorBumps(p, f, b);
  EXPECT_NEAR(b(0, 0), psi, 1e-15);
  EXPECT_EQ(b.row(0).tail(3).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT(relativeError(W, N - psi * Na), 1e-12);
  EXPECT_GT((W - N).cwiseAbs().maxCoeff(), 1e-3);  // the correction is not negligible here
  EXPECT_EQ(anchored.describe(), "MLP 2-64-64-78 tanh, 4 zero anchors, 26 vertices, forward-mode autograd");
}

TEST(MlpAnchors, BadAnchorsAreRejected) {
  MlpParameters p = anchorParameters();
  p.anchor_radius = 0.34;  // more than the 0.333 between (0, 0) and (0.01, 0)
  try {
    MlpFunction{p};
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("anchor_radius"), std::string::npos) << e.what();
  }
  p.anchor_radius = 0.0;
  EXPECT_THROW(MlpFunction{p}, std::invalid_argument);
  p = anchorParameters();
  p.anchors(2, 1) = std::nan("");
  EXPECT_THROW(MlpFunction{p}, std::invalid_argument);
  p = anchorParameters();
  p.output_envelope = MlpOutputEnvelope::Depth;
  EXPECT_THROW(MlpFunction{p}, std::invalid_argument);
}

// ----- the soft depth envelope W = w softplus(−φ/w) ⊙ N, with zero anchors ----------------------------

// The anchors' network, under the soft depth envelope of width 5 mm.
MlpParameters softDepthParameters(MlpActivation activation = MlpActivation::Tanh) {
  MlpParameters p = anchorParameters(activation);
  p.output_envelope = MlpOutputEnvelope::SoftDepth;
  p.envelope_width = 0.005;
  return p;
}

// The anchors' rows, one deep and one far above the surface (where the factor underflows to tiny).
Eigen::MatrixX2d softDepthFeatures() {
  Eigen::MatrixX2d f(8, 2);
  f.topRows(6) = anchorFeatures();
  f.bottomRows(2) << -0.08, 0.4, 0.3, -0.1;
  return f;
}

TEST(MlpSoftDepth, FactorIsTheSoftplusOfDepthAndItsDerivative) {
  const double w = 0.005;
  for (double phi : {-0.2, -0.07, -0.01, -1e-4, 0.0, 1e-4, 0.004, 0.05, 1.0}) {
    double m, dm;
    mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, w, phi, &m, &dm);
    // The textbook form, which is exact enough in this range (no overflow: −φ/w ≤ 40).
    EXPECT_NEAR(m, w * std::log(1.0 + std::exp(-phi / w)), 1e-15 + 1e-13 * m) << phi;
    double mp, mm, unused;
    const double h = 1e-7;
    mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, w, phi + h, &mp, &unused);
    mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, w, phi - h, &mm, &unused);
    EXPECT_NEAR(dm, (mp - mm) / (2 * h), 1e-7) << phi;
    EXPECT_GT(m, 0.0) << phi;
  }
  double m, dm;
  mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, w, -0.1, &m, &dm);  // deep: the depth itself
  EXPECT_NEAR(m, 0.1, 1e-10);
  EXPECT_NEAR(dm, -1.0, 1e-8);
  mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, w, 0.0, &m, &dm);  // at the surface: w log 2, slope −½
  EXPECT_DOUBLE_EQ(m, w * std::log(2.0));
  EXPECT_DOUBLE_EQ(dm, -0.5);
  mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, w, 10.0, &m, &dm);  // far above: underflows, no NaN
  EXPECT_EQ(m, 0.0);
  EXPECT_EQ(dm, 0.0);
  mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, w, -10.0, &m, &dm);  // far below: no overflow
  EXPECT_DOUBLE_EQ(m, 10.0);
  mlpEnvelopeFactor(MlpOutputEnvelope::Depth, w, -0.03, &m, &dm);
  EXPECT_EQ(m, 0.03);
  EXPECT_EQ(dm, -1.0);
}

// The fourth-order central difference: at an anchor W = m (N − b N_a) is zero while the bump's
// curvature times m' is large, so the second-order one is off by ~1e-5 there at the usual step.
Eigen::MatrixXd fivePointDifference(const MlpFunction& mlp, const Eigen::MatrixX2d& f, int d) {
  return centralDifference(mlp, f, d, 4);
}

class MlpSoftDepthDerivatives : public ::testing::TestWithParam<FunctionCase> {};

TEST_P(MlpSoftDepthDerivatives, MatchCentralDifferences) {
  const MlpFunction mlp(softDepthParameters(GetParam().activation), GetParam().jacobian);
  const Eigen::MatrixX2d f = softDepthFeatures();
  Eigen::MatrixXd W, dphi, dbeta;
  mlp.evaluate(f, W, &dphi, &dbeta);
  for (int d = 0; d < 2; ++d) {
    const Eigen::MatrixXd fd = fivePointDifference(mlp, f, d);
    for (Eigen::Index r = 0; r < f.rows(); ++r)
      EXPECT_LT(relativeError((d == 0 ? dphi : dbeta).row(r), fd.row(r)), 1e-7) << "d " << d << ", row " << r;
  }
  expectOneDirectionAsBoth(mlp, f, W, dphi, dbeta);
  EXPECT_GT(dphi.cwiseAbs().maxCoeff(), 1e-2);  // not trivially zero
}

INSTANTIATE_TEST_SUITE_P(ActivationsAndSchemes, MlpSoftDepthDerivatives,
                         ::testing::Values(FunctionCase{MlpActivation::Tanh, MlpJacobian::ForwardMode},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::DoubleBackward},
                                           FunctionCase{MlpActivation::Tanh, MlpJacobian::Tangents},
                                           FunctionCase{MlpActivation::Softplus, MlpJacobian::ForwardMode}),
                         functionCaseName);

TEST(MlpSoftDepth, IsTheFactorTimesTheAnchoredNetworkAndZeroAtTheAnchors) {
  const MlpParameters p = softDepthParameters();
  const Eigen::MatrixX2d f = softDepthFeatures();
  for (MlpJacobian jacobian : {MlpJacobian::ForwardMode, MlpJacobian::Tangents}) {
    const MlpFunction anchored(anchorParameters(), jacobian), soft(p, jacobian);
    Eigen::MatrixXd N, dN_phi, dN_beta, W, dW_phi, dW_beta;
    anchored.evaluate(f, N, &dN_phi, &dN_beta);
    soft.evaluate(f, W, &dW_phi, &dW_beta);
    for (Eigen::Index r = 0; r < f.rows(); ++r) {
      const double m = p.envelope_width * std::log1p(std::exp(-f(r, 0) / p.envelope_width));
      const double dm = -1.0 / (1.0 + std::exp(f(r, 0) / p.envelope_width));
      EXPECT_LT(relativeError(W.row(r), m * N.row(r)), 1e-13) << mlpJacobianName(jacobian) << " row " << r;
      EXPECT_LT(relativeError(dW_beta.row(r), m * dN_beta.row(r)), 1e-13) << " row " << r;
      EXPECT_LT(relativeError(dW_phi.row(r), m * dN_phi.row(r) + dm * N.row(r)), 1e-13) << " row " << r;
    }
    // Exactly zero at the anchors, above the surface or at it, whatever the factor.
    soft.evaluate(p.anchors, W, nullptr, nullptr);
    anchored.evaluate(p.anchors, N, nullptr, nullptr);
    EXPECT_LT(W.cwiseAbs().maxCoeff(), 1e-12) << mlpJacobianName(jacobian);
  }
  // Far above the surface the factor has underflowed: zero wrench, finite derivatives.
  Eigen::MatrixXd W, dphi, dbeta;
  MlpFunction(p).evaluate((Eigen::MatrixX2d(1, 2) << 5.0, 0.1).finished(), W, &dphi, &dbeta);
  EXPECT_EQ(W.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(dphi.allFinite() && dbeta.allFinite());
  EXPECT_EQ(MlpFunction(p).describe(),
            "MLP 2-64-64-78 tanh, W = w softplus(-phi/w) N soft depth envelope (w = 0.005 m), 4 zero anchors, "
            "26 vertices, forward-mode autograd");
  MlpOutputEnvelope e = MlpOutputEnvelope::None;
  EXPECT_TRUE(parseMlpOutputEnvelope("soft_depth", &e));
  EXPECT_EQ(e, MlpOutputEnvelope::SoftDepth);
  EXPECT_STREQ(mlpOutputEnvelopeName(MlpOutputEnvelope::SoftDepth), "soft_depth");
}

TEST(MlpSoftDepth, NeedsAPositiveWidth) {
  for (double width : {0.0, -0.005, std::nan(""), std::numeric_limits<double>::infinity()}) {
    MlpParameters p = softDepthParameters();
    p.envelope_width = width;
    try {
      MlpFunction{p};
      ADD_FAILURE() << "no exception for width " << width;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("envelope_width"), std::string::npos) << e.what();
    }
  }
}

// ----- the HDF5 file -------------------------------------------------------------------------------

TEST(MlpFile, SaveLoadRoundTripIsBitIdentical) {
  TempFile file("roundtrip.h5");
  const MlpFunction mlp(testParameters(MlpActivation::Softplus));
  saveMlpModel(file.path(), mlp, testGeometry());
  EXPECT_FALSE(std::filesystem::exists(file.path() + ".partial"));

  const MlpModelFile loaded = loadMlpModel(file.path());
  const MlpParameters& a = mlp.parameters();
  const MlpParameters& b = loaded.parameters;
  EXPECT_EQ(b.activation, MlpActivation::Softplus);
  EXPECT_EQ(loaded.geometry.torque_centre, testGeometry().torque_centre);
  EXPECT_EQ(loaded.geometry.cutoff, testGeometry().cutoff);
  EXPECT_EQ(loaded.geometry.cutoff_width, testGeometry().cutoff_width);
  ASSERT_EQ(b.layers.size(), a.layers.size());
  for (size_t i = 0; i < a.layers.size(); ++i) {
    EXPECT_TRUE(identical(a.layers[i].weight, b.layers[i].weight)) << "layer " << i;
    EXPECT_TRUE(identical(a.layers[i].bias, b.layers[i].bias)) << "layer " << i;
  }
  EXPECT_TRUE(identical(a.input_mean, b.input_mean));
  EXPECT_TRUE(identical(a.input_std, b.input_std));
  EXPECT_TRUE(identical(a.output_scale, b.output_scale));
  EXPECT_TRUE(identical(a.output_offset, b.output_offset));

  const MlpFunction again(loaded.parameters);
  Eigen::MatrixXd W1, p1, b1, W2, p2, b2;
  mlp.evaluate(testFeatures(), W1, &p1, &b1);
  again.evaluate(testFeatures(), W2, &p2, &b2);
  EXPECT_TRUE(identical(W1, W2));
  EXPECT_TRUE(identical(p1, p2));
  EXPECT_TRUE(identical(b1, b2));

  // The documented layout, as another reader (h5py) sees it.
  const h5::File raw = h5::File::openRead(file.path());
  EXPECT_EQ(raw.readStringAttribute("/", "nmdp_model"), "mlp");
  EXPECT_EQ(raw.readStringAttribute("/mlp", "activation"), "softplus");
  EXPECT_EQ(raw.readDoubleAttribute("/mlp", "layers"), 3.0);
  EXPECT_EQ(raw.readDoubleAttribute("/mlp", "vertices"), 26.0);
  EXPECT_EQ(raw.readDoubleAttribute("/mlp", "format_version"), 1.0);
  EXPECT_EQ(raw.readStrings("/mlp/feature_names"), (std::vector<std::string>{"phi", "beta"}));
  const Eigen::MatrixXd w1 = raw.readMatrix("/mlp/layer_1/weight");
  EXPECT_EQ(w1.rows(), 64);
  EXPECT_EQ(w1.cols(), 64);
  EXPECT_EQ(w1(3, 5), a.layers[1].weight(3, 5));  // out × in, row-major on disk
  EXPECT_EQ(raw.readMatrix("/mlp/layer_2/bias").size(), 78);
}

TEST(MlpFile, SaveLoadRoundTripWithTheDepthEnvelope) {
  TempFile file("envelope.h5");
  const MlpFunction mlp(envelopeParameters(), MlpJacobian::Tangents);
  saveMlpModel(file.path(), mlp, testGeometry());
  {
    const h5::File raw = h5::File::openRead(file.path());
    EXPECT_EQ(raw.readDoubleAttribute("/mlp", "format_version"), 2.0);
    EXPECT_EQ(raw.readStringAttribute("/mlp", "output_envelope"), "depth");
  }
  const MlpModelFile loaded = loadMlpModel(file.path());
  EXPECT_EQ(loaded.parameters.output_envelope, MlpOutputEnvelope::Depth);
  const MlpFunction again(loaded.parameters, MlpJacobian::Tangents);
  Eigen::MatrixXd W1, p1, b1, W2, p2, b2;
  mlp.evaluate(envelopeFeatures(), W1, &p1, &b1);
  again.evaluate(envelopeFeatures(), W2, &p2, &b2);
  EXPECT_TRUE(identical(W1, W2));
  EXPECT_TRUE(identical(p1, p2));
  EXPECT_TRUE(identical(b1, b2));

  // Without the envelope the file stays version 1 and has no output_envelope attribute.
  TempFile plain("plain.h5");
  saveMlpModel(plain.path(), testParameters(), testGeometry());
  const h5::File raw = h5::File::openRead(plain.path());
  EXPECT_EQ(raw.readDoubleAttribute("/mlp", "format_version"), 1.0);
  EXPECT_FALSE(raw.hasAttribute("/mlp", "output_envelope"));
  EXPECT_EQ(loadMlpModel(plain.path()).parameters.output_envelope, MlpOutputEnvelope::None);
}

TEST(MlpFile, SaveLoadRoundTripWithZeroAnchors) {
  TempFile file("anchors.h5");
  const MlpFunction mlp(anchorParameters(), MlpJacobian::Tangents);
  saveMlpModel(file.path(), mlp, testGeometry());
  {
    const h5::File raw = h5::File::openRead(file.path());
    EXPECT_EQ(raw.readDoubleAttribute("/mlp", "format_version"), 3.0);
    EXPECT_EQ(raw.readDoubleAttribute("/mlp", "anchor_radius"), 0.3);
    EXPECT_TRUE(identical(raw.readMatrix("/mlp/anchors"), anchorParameters().anchors));
  }
  const MlpModelFile loaded = loadMlpModel(file.path());
  EXPECT_TRUE(identical(loaded.parameters.anchors, anchorParameters().anchors));
  const MlpFunction again(loaded.parameters, MlpJacobian::Tangents);
  Eigen::MatrixXd W1, p1, b1, W2, p2, b2;
  mlp.evaluate(anchorFeatures(), W1, &p1, &b1);
  again.evaluate(anchorFeatures(), W2, &p2, &b2);
  EXPECT_TRUE(identical(W1, W2));
  EXPECT_TRUE(identical(p1, p2));
  EXPECT_TRUE(identical(b1, b2));

  // Broken by hand: anchors without their radius, of the wrong shape, a radius too large.
  const auto expectError = [&](const std::function<void(h5::File&)>& edit, const std::string& part) {
    TempFile bad("bad_anchors.h5");
    {
      h5::File f = h5::File::createAtomic(bad.path());
      writeMlpModel(f, testParameters(), testGeometry());
      edit(f);
      f.commit();
    }
    try {
      loadMlpModel(bad.path());
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError([](h5::File& f) { f.writeMatrix("/mlp/anchors", anchorParameters().anchors); }, "anchor_radius");
  expectError(
      [](h5::File& f) {
        f.writeMatrix("/mlp/anchors", Eigen::MatrixXd::Zero(2, 3));
        f.writeDoubleAttribute("/mlp", "anchor_radius", 0.3);
      },
      "'/mlp/anchors' is 2 x 3");
  expectError(
      [](h5::File& f) {
        f.writeMatrix("/mlp/anchors", anchorParameters().anchors);
        f.writeDoubleAttribute("/mlp", "anchor_radius", 0.5);
      },
      "anchor_radius");
}

TEST(MlpFile, SaveLoadRoundTripWithTheSoftDepthEnvelope) {
  TempFile file("soft.h5");
  const MlpFunction mlp(softDepthParameters(), MlpJacobian::Tangents);
  saveMlpModel(file.path(), mlp, testGeometry());
  {
    const h5::File raw = h5::File::openRead(file.path());
    EXPECT_EQ(raw.readDoubleAttribute("/mlp", "format_version"), 4.0);  // older programs refuse it
    EXPECT_EQ(raw.readStringAttribute("/mlp", "output_envelope"), "soft_depth");
    EXPECT_EQ(raw.readDoubleAttribute("/mlp", "envelope_width"), 0.005);
  }
  const MlpModelFile loaded = loadMlpModel(file.path());
  EXPECT_EQ(loaded.parameters.output_envelope, MlpOutputEnvelope::SoftDepth);
  EXPECT_EQ(loaded.parameters.envelope_width, 0.005);
  const MlpFunction again(loaded.parameters, MlpJacobian::Tangents);
  Eigen::MatrixXd W1, p1, b1, W2, p2, b2;
  mlp.evaluate(softDepthFeatures(), W1, &p1, &b1);
  again.evaluate(softDepthFeatures(), W2, &p2, &b2);
  EXPECT_TRUE(identical(W1, W2));
  EXPECT_TRUE(identical(p1, p2));
  EXPECT_TRUE(identical(b1, b2));

  // Broken by hand: the width missing, or not positive.
  for (const double width : {std::nan(""), 0.0, -1.0}) {
    TempFile bad("bad_soft.h5");
    {
      h5::File f = h5::File::createAtomic(bad.path());
      MlpParameters p = testParameters();
      writeMlpModel(f, p, testGeometry());
      f.writeStringAttribute("/mlp", "output_envelope", "soft_depth");
      if (!std::isnan(width)) f.writeDoubleAttribute("/mlp", "envelope_width", width);
      f.commit();
    }
    try {
      loadMlpModel(bad.path());
      ADD_FAILURE() << "no InputError for width " << width;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("envelope_width"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(bad.path()), std::string::npos) << e.what();
    }
  }
}

// Writes the file format by hand, with what a test wants broken (saveMlpModel refuses bad input).
struct RawFile {
  MlpParameters p = testParameters();
  std::string activation = "tanh";
  double layers = 3;
  double vertices = kVertices;
  double version = 1.0;
  std::string envelope;  // the output_envelope attribute; empty: not written (a version-1 file)
  std::string skip;  // a dataset not to write
  std::map<std::string, Eigen::VectorXd> replace;  // datasets written with these values instead

  void write(const std::string& path) const {
    h5::File f = h5::File::createAtomic(path);
    f.writeStringAttribute("/", "nmdp_model", "mlp");
    f.createGroup("/mlp");
    f.writeDoubleAttribute("/mlp", "format_version", version);
    if (!envelope.empty()) f.writeStringAttribute("/mlp", "output_envelope", envelope);
    f.writeStringAttribute("/mlp", "activation", activation);
    f.writeDoubleAttribute("/mlp", "layers", layers);
    f.writeDoubleAttribute("/mlp", "vertices", vertices);
    f.writeDoubleAttribute("/mlp", "torque_centre", 0.1);
    f.writeDoubleAttribute("/mlp", "cutoff", 0.1);
    f.writeDoubleAttribute("/mlp", "cutoff_width", 0.02);
    const auto vec = [&](const std::string& name, const Eigen::VectorXd& v) {
      if (name != skip) f.writeVector(name, replace.count(name) ? replace.at(name) : v);
    };
    vec("/mlp/input_mean", p.input_mean);
    vec("/mlp/input_std", p.input_std);
    vec("/mlp/output_scale", p.output_scale);
    vec("/mlp/output_offset", p.output_offset);
    for (size_t i = 0; i < p.layers.size(); ++i) {
      const std::string g = "/mlp/layer_" + std::to_string(i);
      f.createGroup(g);
      if (g + "/weight" != skip) f.writeMatrix(g + "/weight", p.layers[i].weight);
      vec(g + "/bias", p.layers[i].bias);
    }
    f.commit();
  }
};

// Loads `raw` and expects an InputError whose message names the file and holds every `parts`.
void expectLoadError(const RawFile& raw, const std::vector<std::string>& parts) {
  TempFile file("bad.h5");
  raw.write(file.path());
  try {
    loadMlpModel(file.path());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.path()), std::string::npos) << message;
    for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

TEST(MlpFile, CleanRawFileLoads) {
  TempFile file("clean.h5");
  RawFile().write(file.path());  // version 1, no output_envelope attribute
  MlpModelFile m;
  EXPECT_NO_THROW(m = loadMlpModel(file.path()));
  EXPECT_EQ(m.parameters.output_envelope, MlpOutputEnvelope::None);
  RawFile raw;
  raw.version = 2;
  raw.envelope = "depth";
  raw.write(file.path());
  EXPECT_EQ(loadMlpModel(file.path()).parameters.output_envelope, MlpOutputEnvelope::Depth);
  raw.envelope = "none";
  raw.write(file.path());
  EXPECT_EQ(loadMlpModel(file.path()).parameters.output_envelope, MlpOutputEnvelope::None);
}

TEST(MlpFile, BadOutputEnvelope) {
  RawFile raw;
  raw.version = 2;
  raw.envelope = "sqrt_depth";
  expectLoadError(raw, {"attribute 'output_envelope'", "'sqrt_depth'", "\"none\"", "\"depth\""});
  raw.envelope = "Depth";
  expectLoadError(raw, {"attribute 'output_envelope'", "'Depth'"});
}

TEST(MlpFile, NewerFormatVersion) {
  RawFile raw;
  raw.version = 6;
  expectLoadError(raw, {"attribute 'format_version'", "versions 1 to 5"});
}

TEST(MlpFile, MissingFile) {
  try {
    loadMlpModel("/nonexistent/folder/model.h5");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/folder/model.h5"), std::string::npos) << e.what();
  }
}

TEST(MlpFile, LayerSizeMismatch) {
  RawFile raw;
  raw.p.layers[1].weight = Eigen::MatrixXd::Ones(64, 32);
  expectLoadError(raw, {"'/mlp/layer_1/weight'", "64 x 32", "64 outputs"});
}

TEST(MlpFile, FirstLayerMustTakeTwoInputs) {
  RawFile raw;
  raw.p.layers[0].weight = Eigen::MatrixXd::Ones(64, 3);
  expectLoadError(raw, {"'/mlp/layer_0/weight'", "(phi, beta)"});
}

TEST(MlpFile, OutputMustMatchVertices) {
  RawFile raw;
  raw.vertices = 20;
  expectLoadError(raw, {"'/mlp/output_scale'", "attribute 'vertices' = 20"});
  raw.p.output_scale.resize(60);
  raw.p.output_scale.setOnes();
  raw.p.output_offset = Eigen::VectorXd::Zero(60);
  expectLoadError(raw, {"'/mlp/layer_2/weight'", "3K = 60"});
}

TEST(MlpFile, BiasSizeMismatch) {
  RawFile raw;
  raw.p.layers[0].bias = Eigen::VectorXd::Zero(63);
  expectLoadError(raw, {"'/mlp/layer_0/bias'", "64 values"});
}

TEST(MlpFile, NanWeight) {
  RawFile raw;
  raw.p.layers[1].weight(10, 20) = std::nan("");
  expectLoadError(raw, {"'/mlp/layer_1/weight'", "NaN", "row 10, column 20"});
  raw = RawFile();
  raw.p.output_offset[5] = std::numeric_limits<double>::infinity();
  expectLoadError(raw, {"'/mlp/output_offset'", "non-finite"});
}

// Finite weights whose product through the layers overflows a double: refused at loading, where a
// loaded model would have returned infinite wrenches. A trained network is far inside the bound.
TEST(MlpFile, WeightsThatCouldOverflowAreRefused) {
  RawFile raw;
  raw.activation = "silu";  // unbounded: the bound grows with every layer
  for (MlpLayer& l : raw.p.layers) l.weight *= 1e80;
  expectLoadError(raw, {"'/mlp'", "could overflow"});
  raw = RawFile();
  raw.p.input_std[0] = 1e-300;  // features normalized to 1e303
  expectLoadError(raw, {"'/mlp'", "could overflow"});
  raw = RawFile();
  EXPECT_EQ(mlpParameterProblem(raw.p), "");
}

// A dataset's size is checked from its header against what the model needs before it is read:
// fuzz_model_h5 found a 62 782 127-value '/mlp/output_scale' (an unwritten chunked dataset of 11 kB)
// that took 1.4 GB and 7 s to read before its size was found wrong.
TEST(MlpFile, OversizedDatasetsAreRefusedBeforeReading) {
  RawFile raw;
  raw.replace["/mlp/input_mean"] = Eigen::VectorXd::Zero(10000);
  expectLoadError(raw, {"'/mlp/input_mean'", "10000 values, more than the 64 it may hold"});
}

TEST(MlpFile, MissingDataset) {
  RawFile raw;
  raw.skip = "/mlp/layer_2/bias";
  expectLoadError(raw, {"'/mlp/layer_2/bias'", "missing"});
  raw.skip = "/mlp/input_std";
  expectLoadError(raw, {"'/mlp/input_std'", "missing"});
  raw = RawFile();
  raw.layers = 4;  // says 4 layers, holds 3
  expectLoadError(raw, {"'/mlp/layer_3/weight'", "missing"});
  raw.layers = 2;  // says 2 layers, holds 3: layer_1 is read as the output layer
  expectLoadError(raw, {"'/mlp/layer_1/weight'", "3K = 78"});
}

TEST(MlpFile, ReluIsRejected) {
  RawFile raw;
  raw.activation = "relu";
  expectLoadError(raw, {"attribute 'activation'", "ReLU", "C1"});
  raw.activation = "sigmoidish";
  expectLoadError(raw, {"attribute 'activation'", "unknown activation 'sigmoidish'"});
}

TEST(MlpFile, NonPositiveStd) {
  RawFile raw;
  raw.p.input_std[0] = -1.0;
  expectLoadError(raw, {"'/mlp/input_std'", "positive"});
}

TEST(MlpFile, NotAnMlpFile) {
  TempFile file("other.h5");
  {
    h5::File f = h5::File::createAtomic(file.path());
    f.createGroup("/rbf");
    f.commit();
  }
  try {
    loadMlpModel(file.path());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'/mlp' is missing"), std::string::npos) << e.what();
  }
}

// ----- the contact model ---------------------------------------------------------------------------

// Four contacts at given depths φ on `terrain` (a plane): tilted legs, one in the cut-off band, one
// with a 3-D leg, one with a world-fixed sagittal plane (planar base).
std::vector<ContactFrame> testFrames(const Terrain& terrain = PlaneTerrain()) {
  const double r = 0.03;
  std::vector<ContactFrame> frames(4);
  const auto place = [&](ContactFrame& c, double x, double phi, const Vec3& leg, const Vec3& lateral, bool rotates) {
    const Vec3 p0(x, 0.05 * x, 0.0);
    TerrainQuery q;
    terrain.query(p0, q, false);
    c.position = p0 + (phi + r - q.distance) * q.normal;  // exact on a plane: φ(c) − r = phi
    c.radius = r;
    c.leg_axis = leg.normalized();
    c.lateral = lateral.normalized();
    c.lateral_rotates = rotates;
  };
  place(frames[0], 0.0, -0.03, Vec3(std::sin(0.3), 0.0, std::cos(0.3)), Vec3::UnitY(), true);   // tilted leg
  place(frames[1], 0.4, 0.09, Vec3(-std::sin(0.5), 0.1, std::cos(0.5)), Vec3::UnitY(), true);  // in the cut-off band
  place(frames[2], -0.3, -0.06, Vec3(0.2, 0.3, 0.93), Vec3(0.1, 1.0, 0.05), true);              // 3-D leg
  place(frames[3], 0.7, -0.01, Vec3(std::sin(-0.2), 0.0, std::cos(-0.2)), Vec3::UnitY(), false);  // planar base
  return frames;
}

class MlpModelTerrain : public ::testing::TestWithParam<int> {};

TEST_P(MlpModelTerrain, DerivativeMatchesFiniteDifferences) {
  const PlaneTerrain terrain = GetParam() == 0 ? PlaneTerrain() : PlaneTerrain(Vec3(0.1, -0.05, 1.0), -0.01);
  const std::vector<ContactFrame> frames = testFrames(terrain);
  for (int n = 0; n < 6; ++n) {
    const MlpJacobian jacobian =
        std::array<MlpJacobian, 3>{MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents}[n % 3];
    const bool envelope = n >= 3;  // and the same with the depth envelope, N × 100 so that W at a
    MlpParameters p = testParameters();  // depth of centimetres is as large as without it
    if (envelope) {
      p = envelopeParameters();
      p.output_scale *= 100.0;
      p.output_offset *= 100.0;
    }
    const PlanarWrenchModel model(std::make_shared<const MlpFunction>(p, jacobian), testGeometry(), "mlp");
    // Each dV/dξ_i on its own scale (at least 1 N/m), steps of 1e-6 m and rad.
    test::VertexDerivativeCheck check;
    check.scale = test::VertexDerivativeCheck::Scale::PerMotion;
    check.scale_floor = 1.0;
    const test::VertexDerivativeResult r = test::checkVertexDerivative(
        model, frames, terrain, check, std::string(mlpJacobianName(jacobian)) + (envelope ? " (depth envelope)" : ""));
    for (size_t c = 0; c < frames.size(); ++c) EXPECT_GT(r.analytic[c].V.cwiseAbs().maxCoeff(), 1.0) << "contact " << c;
  }
}

INSTANTIATE_TEST_SUITE_P(FlatAndTilted, MlpModelTerrain, ::testing::Values(0, 1),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::string(info.param == 0 ? "flat" : "tilted");
                         });

TEST(MlpModel, ModelEvaluationTwiceIsBitIdentical) {
  const PlaneTerrain terrain;
  const PlanarWrenchModel model(std::make_shared<const MlpFunction>(testParameters()), testGeometry(), "mlp");
  const std::vector<ContactFrame> frames = testFrames();
  std::vector<ContactWrenches> a(4), b(4);
  for (int c = 0; c < 4; ++c) {
    a[c].resize(26);
    b[c].resize(26);
  }
  model.evaluate(frames, terrain, a, true);
  model.evaluate(frames, terrain, b, true);
  for (int c = 0; c < 4; ++c) {
    EXPECT_TRUE(identical(a[c].V, b[c].V));
    for (int i = 0; i < 6; ++i) EXPECT_TRUE(identical(a[c].dV[i], b[c].dV[i]));
  }
}

TEST(MlpModel, FeaturesAreTheNetworksInput) {
  // The model as the factory builds it from a file, on flat ground: the legs of frames 0 and 3
  // lean by 0.3 and −0.2 rad in the world's sagittal plane (lateral axis y), 3 and 1 cm deep.
  TempFile file("features.h5");
  saveMlpModel(file.path(), testParameters(), testGeometry());
  const auto model = makeMlpModel({{"file", file.path()}}, ConfigContext{"test", ""});
  const auto& planar = dynamic_cast<const PlanarWrenchModel&>(*model);
  ASSERT_EQ(model->featureInfo().size(), 2u);
  EXPECT_EQ(model->featureInfo()[0].name, "depth");
  EXPECT_EQ(model->featureInfo()[1].name, "beta");
  const PlaneTerrain terrain;
  const std::vector<ContactFrame> all = testFrames(terrain);
  const std::vector<ContactFrame> frames = {all[0], all[3]};
  Eigen::MatrixXd f(2, 2);
  model->features(frames, terrain, f);
  EXPECT_NEAR(f(0, 0), -0.03, 1e-15);
  EXPECT_NEAR(f(0, 1), 0.3, 1e-15);
  EXPECT_NEAR(f(1, 0), -0.01, 1e-15);
  EXPECT_NEAR(f(1, 1), -0.2, 1e-15);
  // The network at the reported features gives the model's forces: F = (σ F_x, 0, σ F_z) there.
  std::vector<ContactWrenches> out(2);
  for (ContactWrenches& w : out) w.resize(kVertices);
  model->evaluate(frames, terrain, out, false);
  Eigen::MatrixXd W;
  planar.function().evaluate(Eigen::MatrixX2d(f), W, nullptr, nullptr);
  for (int c = 0; c < 2; ++c) {
    const double sigma = cutoffStep(planar.geometry(), f(c, 0), nullptr);
    Eigen::MatrixXd expected(3, kVertices);
    for (int k = 0; k < kVertices; ++k) expected.col(k) = Vec3(sigma * W(c, 3 * k), 0.0, sigma * W(c, 3 * k + 1));
    const Eigen::MatrixXd forces = out[c].V.bottomRows<3>();
    EXPECT_GT(forces.cwiseAbs().maxCoeff(), 1.0) << c;
    // A batch of 2 through the model's rows and of 2 through evaluate(): one network, another kernel.
    EXPECT_LE(test::ulpsOfLargest(forces, expected), 64.0) << c << "\n" << forces << "\n" << expected;
  }
}

TEST(MlpModel, FactoryBuildsFromJson) {
  TempFile file("factory.h5");
  saveMlpModel(file.path(), testParameters(), testGeometry());
  const std::filesystem::path p(file.path());
  const ConfigContext ctx{"scene.json: contacts.model", p.parent_path().string()};

  const auto model = makeMlpModel({{"type", "mlp"}, {"file", p.filename().string()}}, ctx);  // relative path
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->vertexCount(), kVertices);
  EXPECT_EQ(model->derivative(), DerivativeSupport::Autograd);
  EXPECT_EQ(model->describe().rfind("mlp: MLP 2-64-64-78 tanh", 0), 0u) << model->describe();
  const auto* planar = dynamic_cast<const PlanarWrenchModel*>(model.get());
  ASSERT_NE(planar, nullptr);
  EXPECT_EQ(planar->geometry().torque_centre, 0.1572);
  EXPECT_EQ(planar->geometry().cutoff_width, 0.02);

  const auto overridden =
      makeMlpModel({{"file", file.path()}, {"torque_centre", 0.2}, {"cutoff", 0.05}, {"cutoff_width", 0.01}}, ctx);
  const auto* g = dynamic_cast<const PlanarWrenchModel*>(overridden.get());
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->geometry().torque_centre, 0.2);
  EXPECT_EQ(g->geometry().cutoff, 0.05);
  EXPECT_EQ(g->geometry().cutoff_width, 0.01);
  EXPECT_EQ(kMlpParameters,
            (std::vector<std::string>{"file", "torque_centre", "cutoff", "cutoff_width", "jacobian"}));
  for (const char* jacobian : {"forward-mode", "double-backward", "tangents"}) {
    const auto m = makeMlpModel({{"file", file.path()}, {"jacobian", jacobian}}, ctx);
    EXPECT_EQ(dynamic_cast<const MlpFunction&>(dynamic_cast<const PlanarWrenchModel&>(*m).function()).jacobian(),
              [&] {
                MlpJacobian j{};
                parseMlpJacobian(jacobian, &j);
                return j;
              }());
  }
}

TEST(MlpModel, ConfigurationListsEveryKeyWithTheValueUsed) {
  TempFile file("configuration.h5");
  saveMlpModel(file.path(), testParameters(), testGeometry());
  const std::filesystem::path p(file.path());
  const ConfigContext ctx{"scene.json: contacts.model", p.parent_path().string()};
  const PlanarGeometry g = testGeometry();
  const nlohmann::json reported = makeMlpModel({{"file", p.filename().string()}, {"cutoff", 0.05}}, ctx)->configuration();
  EXPECT_EQ(reported, nlohmann::json({{"type", "mlp"},
                                      {"file", file.path()},
                                      {"jacobian", "forward-mode"},
                                      {"torque_centre", g.torque_centre},
                                      {"cutoff", 0.05},
                                      {"cutoff_width", g.cutoff_width}}));
  for (const std::string& key : kMlpParameters) EXPECT_TRUE(reported.contains(key)) << key;
  const auto again = makeMlpModel(nlohmann::json::parse(reported.dump()), ConfigContext{"again", "/nonexistent"});
  EXPECT_EQ(again->configuration(), reported);
  EXPECT_EQ(makeMlpModel({{"file", file.path()}, {"jacobian", "tangents"}}, ctx)->configuration().at("jacobian"), "tangents");
}

TEST(MlpModel, FactoryBadInput) {
  const ConfigContext ctx{"scene.json: contacts.model", "/nonexistent/base"};
  const auto expectError = [&](const nlohmann::json& params, const std::vector<std::string>& parts) {
    try {
      makeMlpModel(params, ctx);
      ADD_FAILURE() << "no InputError for " << params.dump();
    } catch (const InputError& e) {
      const std::string message = e.what();
      for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
    }
  };
  expectError({{"type", "mlp"}}, {"scene.json: contacts.model.file", "missing"});
  expectError({{"file", "model.h5"}}, {"scene.json: contacts.model.file", "/nonexistent/base/model.h5", "no such file"});
  expectError({{"file", "model.h5"}, {"activation", "tanh"}}, {"contacts.model.activation", "unknown key"});
  expectError({{"type", "rbf"}, {"file", "model.h5"}}, {"contacts.model.type", "expected \"mlp\""});

  TempFile file("factory_bad.h5");
  saveMlpModel(file.path(), testParameters(), testGeometry());
  expectError({{"file", file.path()}, {"cutoff_width", 0.0}}, {"contacts.model.cutoff_width", "positive"});
  expectError({{"file", file.path()}, {"cutoff", "high"}}, {"contacts.model.cutoff", "expected a number"});
  expectError({{"file", file.path()}, {"jacobian", "reverse"}}, {"contacts.model.jacobian", "\"tangents\""});

  RawFile raw;
  raw.p.layers[2].weight(0, 0) = std::nan("");
  raw.write(file.path());
  expectError({{"file", file.path()}}, {"contacts.model.file", file.path(), "'/mlp/layer_2/weight'"});
}

}  // namespace
}  // namespace nmdp
