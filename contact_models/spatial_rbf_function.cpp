#include "contact_models/spatial_rbf_function.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "common/limits.hpp"
#include "common/text.hpp"
#include "contact_models/file_attributes.hpp"
#include "contact_models/rbf_basis.hpp"
#include "io/hdf5_file.hpp"

namespace nmdp {

namespace {

constexpr int kFormatVersion = 1;
constexpr const char* kUnits = "phi: m, beta: rad, gamma: rad; tau: N m about the foot point; F: N";
constexpr int kWidth = kSpatialWrenchWidth;
constexpr int kTail = 4;  // polynomial rows: 1, φ, β, γ

}  // namespace

SpatialRbfFunction::SpatialRbfFunction(SpatialRbfParameters parameters) : params_(std::move(parameters)) {
  const SpatialRbfParameters& p = params_;
  const Eigen::Index N = p.centres.rows();
  if (N < 1) throw std::invalid_argument("SpatialRbfFunction: no centres");
  if (p.weights.rows() != N || p.weights.cols() < kWidth || p.weights.cols() % kWidth != 0)
    throw std::invalid_argument("SpatialRbfFunction: weights must be N x 6K with N = " + std::to_string(N) +
                                " centres, got " + shapeText(p.weights));
  if (p.polynomial.size() != 0 && (p.polynomial.rows() != kTail || p.polynomial.cols() != p.weights.cols()))
    throw std::invalid_argument("SpatialRbfFunction: the polynomial tail must be 4 x " + std::to_string(p.weights.cols()) +
                                ", got " + shapeText(p.polynomial));
  if (!p.centres.allFinite() || !p.weights.allFinite() || !p.polynomial.allFinite())
    throw std::invalid_argument("SpatialRbfFunction: non-finite centre, weight or polynomial coefficient");
  if (!(p.scaling.minCoeff() > 0.0) || !p.scaling.allFinite())
    throw std::invalid_argument("SpatialRbfFunction: the feature scaling must be positive");
  if (!(p.epsilon > 0.0) || !std::isfinite(p.epsilon))
    throw std::invalid_argument("SpatialRbfFunction: epsilon must be positive");

  scaled_centres_ = p.centres * p.scaling.asDiagonal();
  const Eigen::Index tail = p.polynomial.size() != 0 ? kTail : 0;
  const Eigen::Index C = p.weights.cols();
  coefficients_.setZero(N + tail, rbfPackedColumns(C));
  coefficients_.topLeftCorner(N, C) = p.weights;
  if (tail) coefficients_.bottomLeftCorner(kTail, C) = p.polynomial;
}

int SpatialRbfFunction::vertexCount() const { return static_cast<int>(params_.weights.cols() / kWidth); }

std::string SpatialRbfFunction::describe() const {
  std::ostringstream s;
  s << "3-D RBF " << rbfKernelName(params_.kernel) << " kernel";
  if (params_.kernel == RbfKernel::Gaussian || params_.kernel == RbfKernel::Multiquadric ||
      params_.kernel == RbfKernel::InverseMultiquadric)
    s << " (epsilon " << params_.epsilon << ")";
  s << ", " << centreCount() << " centres, " << vertexCount() << " vertices, scaling (" << params_.scaling[0] << ", "
    << params_.scaling[1] << ", " << params_.scaling[2] << ")" << (params_.polynomial.size() ? ", linear tail" : "");
  return s.str();
}

void SpatialRbfFunction::computeBasis(const Eigen::MatrixX3d& features, Eigen::Index count, bool derivatives) const {
  const Eigen::Index B = features.rows();
  const Eigen::Index N = scaled_centres_.rows();
  const Eigen::Index M = coefficients_.rows();
  const Eigen::Vector3d& s = params_.scaling;
  // Sized by the batch only (not by the count or whether derivatives are asked for), so
  // alternating calls do not reallocate.
  if (r2_.size() != N) {
    kappa_.resize(N);
    d0_.resize(N);
    d1_.resize(N);
    d2_.resize(N);
    r2_.resize(N);
    g_.resize(N);
  }
  const Eigen::Index columns = rbfRoundUp(4 * B, kRbfRowBlock);
  if (basis_.rows() != M || basis_.cols() != columns) basis_.resize(M, columns);
  const auto c0 = scaled_centres_.col(0).array(), c1 = scaled_centres_.col(1).array(),
             c2 = scaled_centres_.col(2).array();
  // Per point, vectorized over the centres, written straight into the basis (column r = output row
  // r: Φ, then ∂Φ/∂φ, ∂Φ/∂β, ∂Φ/∂γ of point b; the polynomial 1, φ, β, γ in the last rows).
  const Eigen::Index per_point = derivatives ? 4 : 1;
  for (Eigen::Index b = 0; b < count; ++b) {
    const Eigen::Index r = per_point * b;
    d0_ = s[0] * features(b, 0) - c0;  // S(f_b − c_i)
    d1_ = s[1] * features(b, 1) - c1;
    d2_ = s[2] * features(b, 2) - c2;
    r2_ = d0_.square() + d1_.square() + d2_.square();
    // Into an aligned scratch first: Eigen's vectorized exp/log peel unaligned heads with the scalar
    // functions, so writing into the basis column (aligned or not depending on r) would make a
    // point's values depend on its place in the batch.
    rbfKernelColumn(params_.kernel, params_.epsilon, r2_, kappa_.data(), g_);
    basis_.col(r).head(N) = kappa_.matrix();
    if (M > N) basis_.col(r).tail<kTail>() << 1.0, features(b, 0), features(b, 1), features(b, 2);
    if (!derivatives) continue;
    // ∂κ/∂f = g(ρ) S (S(f − c))
    Eigen::Map<Eigen::ArrayXd>(basis_.col(r + 1).data(), N) = g_ * s[0] * d0_;
    Eigen::Map<Eigen::ArrayXd>(basis_.col(r + 2).data(), N) = g_ * s[1] * d1_;
    Eigen::Map<Eigen::ArrayXd>(basis_.col(r + 3).data(), N) = g_ * s[2] * d2_;
    if (M > N)
      for (int v = 1; v <= 3; ++v) {
        basis_.col(r + v).tail<kTail>().setZero();
        basis_(N + v, r + v) = 1.0;
      }
  }
  // The padding up to a whole row block: zero (it may hold an earlier call's columns).
  const Eigen::Index R = per_point * count;
  basis_.middleCols(R, rbfRoundUp(R, kRbfRowBlock) - R).setZero();
}

bool SpatialRbfFunction::evaluateRows(const Eigen::MatrixX3d& features, Eigen::Index count, bool derivatives,
                                      SpatialRows& rows) const {
  computeBasis(features, count, derivatives);
  const Eigen::Index capacity = rbfRoundUp(4 * features.rows(), kRbfRowBlock);
  if (rows.rows() != capacity || rows.cols() != coefficients_.cols()) rows.resize(capacity, coefficients_.cols());
  rbfProduct(coefficients_, basis_, rbfRoundUp((derivatives ? 4 : 1) * count, kRbfRowBlock), rows);
  return true;
}

void SpatialRbfFunction::evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W,
                                  std::array<Eigen::MatrixXd, 3>* dW) const {
  const Eigen::Index B = features.rows();
  const Eigen::Index C = params_.weights.cols();
  const bool derivatives = dW != nullptr;
  evaluateRows(features, B, derivatives, product_);
  const Eigen::Index per_point = derivatives ? 4 : 1;
  W.resize(B, C);
  if (dW)
    for (Eigen::MatrixXd& d : *dW) d.resize(B, C);
  for (Eigen::Index b = 0; b < B; ++b) {
    W.row(b) = product_.row(per_point * b).head(C);
    if (dW)
      for (int v = 0; v < 3; ++v) (*dW)[v].row(b) = product_.row(4 * b + 1 + v).head(C);
  }
}

std::string spatialRbfMagnitudeProblem(const SpatialRbfParameters& p) {
  return rbfMagnitudeProblem(p.centres, {"phi", "beta", "gamma"}, p.weights, p.polynomial, p.scaling, p.epsilon);
}

// ----- the HDF5 model file -------------------------------------------------------------------

namespace {

// The centres of an RBF model file, after the checks every RBF file shares.
Eigen::MatrixXd readCentres(const h5::File& file, const FileAttributes& rbf) {
  if (!file.exists("/rbf"))
    rbf.fail("not an nmdp RBF model file: group '/rbf' is missing (write one with saveRbfModel or 'nmdp fit')");
  rbf.checkFormatVersion(kFormatVersion);
  return file.readMatrix("/rbf/centres", 3 * limits::kMaxRbfCentres);
}

}  // namespace

bool isSpatialRbfFile(const std::string& path) {
  const h5::File file = h5::File::openRead(path);
  const FileAttributes rbf(file, path, "/rbf");
  const Eigen::MatrixXd centres = readCentres(file, rbf);
  if (centres.cols() != 2 && centres.cols() != kSpatialFeatureCount)
    rbf.fail("dataset '/rbf/centres' must be N x 2 (phi, beta: a planar model) or N x 3 (phi, beta, gamma: a 3-D "
             "model), got " + shapeText(centres));
  return centres.cols() == kSpatialFeatureCount;
}

SpatialRbfModelFile readSpatialRbfHdf5(const std::string& path) {
  const h5::File file = h5::File::openRead(path);
  const FileAttributes rbf(file, path, "/rbf");
  const auto fail = [&](const std::string& what) { rbf.fail(what); };
  const Eigen::MatrixXd centres = readCentres(file, rbf);

  SpatialRbfModelFile out;
  SpatialRbfParameters& p = out.parameters;
  const std::vector<std::string> kernel = file.readStrings("/rbf/kernel");
  if (kernel.size() != 1 || !parseRbfKernel(kernel[0], &p.kernel))
    fail("dataset '/rbf/kernel' must hold one kernel name, one of " + rbfKernelNames() + "; got '" +
         (kernel.empty() ? std::string() : kernel[0]) + "'" + (kernel.size() > 1 ? " and more" : ""));
  p.epsilon = rbf.positive("epsilon", 1.0, false);
  out.geometry.cutoff = rbf.finite("cutoff");
  out.geometry.cutoff_width = rbf.positive("cutoff_width", 0.0, true);
  if (const std::string problem = planarGeometryProblem(planarGeometryOf(out.geometry)); !problem.empty())
    fail("attribute " + problem + " (of '/rbf')");

  if (centres.rows() < 1 || centres.cols() != kSpatialFeatureCount)
    fail("dataset '/rbf/centres' must be N x 3 (phi, beta, gamma), got " + shapeText(centres));
  if (centres.rows() > limits::kMaxRbfCentres)
    fail("dataset '/rbf/centres' has " + std::to_string(centres.rows()) + " centres, more than the " +
         std::to_string(limits::kMaxRbfCentres) + " a model may have");
  if (const std::string bad = firstNonFinite(centres); !bad.empty())
    fail("dataset '/rbf/centres' has a non-finite value at " + bad);
  const Eigen::MatrixXd weights = file.readMatrix("/rbf/weights", centres.rows() * kWidth * limits::kMaxVertices);
  if (weights.rows() != centres.rows() || weights.cols() < kWidth || weights.cols() % kWidth != 0)
    fail("dataset '/rbf/weights' must be N x 6K with N = " + std::to_string(centres.rows()) +
         " (the rows of '/rbf/centres'), got " + shapeText(weights));
  if (weights.cols() / kWidth > limits::kMaxVertices)
    fail("dataset '/rbf/weights' has " + std::to_string(weights.cols() / kWidth) + " vertices, more than the " +
         std::to_string(limits::kMaxVertices) + " a model may have");
  if (const std::string bad = firstNonFinite(weights); !bad.empty())
    fail("dataset '/rbf/weights' has a non-finite value at " + bad);
  const Eigen::MatrixXd scaling = file.readMatrix("/rbf/scaling", 64);
  if (scaling.size() != kSpatialFeatureCount)
    fail("dataset '/rbf/scaling' must hold 3 numbers (s_phi, s_beta, s_gamma), got " + shapeText(scaling));
  if (!(scaling.minCoeff() > 0.0) || !scaling.allFinite()) fail("dataset '/rbf/scaling' must hold positive finite numbers");
  if (file.exists("/rbf/polynomial")) {
    p.polynomial = file.readMatrix("/rbf/polynomial", 2 * kTail * weights.cols());
    if (p.polynomial.rows() != kTail || p.polynomial.cols() != weights.cols())
      fail("dataset '/rbf/polynomial' must be 4 x " + std::to_string(weights.cols()) + " (rows 1, phi, beta, gamma), got " +
           shapeText(p.polynomial));
    if (const std::string bad = firstNonFinite(p.polynomial); !bad.empty())
      fail("dataset '/rbf/polynomial' has a non-finite value at " + bad);
  }
  if (file.exists("/rbf/feature_names")) {
    const std::vector<std::string> names = file.readStrings("/rbf/feature_names");
    if (names != std::vector<std::string>{"phi", "beta", "gamma"})
      fail(
          "dataset '/rbf/feature_names' must be [\"phi\", \"beta\", \"gamma\"]: the 3-D RBF contact model takes the "
          "signed depth and the leg's sagittal and lateral lean");
  }
  p.centres = centres;
  p.weights = weights;
  p.scaling = Eigen::Vector3d(scaling.data()[0], scaling.data()[1], scaling.data()[2]);
  if (const std::string problem = spatialRbfMagnitudeProblem(p); !problem.empty())
    fail("'/rbf': " + problem + ", beyond any contact model");
  return out;
}

void writeSpatialRbfModel(h5::File& file, const SpatialRbfFunction& function, const SpatialGeometry& geometry) {
  const SpatialRbfParameters& p = function.parameters();
  file.writeStringAttribute("/", "nmdp_model", "rbf");
  file.createGroup("/rbf");
  file.writeDoubleAttribute("/rbf", "format_version", kFormatVersion);
  file.writeDoubleAttribute("/rbf", "epsilon", p.epsilon);
  file.writeDoubleAttribute("/rbf", "cutoff", geometry.cutoff);
  file.writeDoubleAttribute("/rbf", "cutoff_width", geometry.cutoff_width);
  file.writeStringAttribute("/rbf", "units", kUnits);
  file.writeMatrix("/rbf/centres", p.centres);
  file.writeMatrix("/rbf/weights", p.weights);
  file.writeStrings("/rbf/kernel", {rbfKernelName(p.kernel)});
  file.writeVector("/rbf/scaling", p.scaling);
  if (p.polynomial.size() != 0) file.writeMatrix("/rbf/polynomial", p.polynomial);
  file.writeStrings("/rbf/feature_names", {"phi", "beta", "gamma"});
}

void saveSpatialRbfModel(const std::string& path, const SpatialRbfFunction& function, const SpatialGeometry& geometry) {
  h5::File file = h5::File::createAtomic(path);
  writeSpatialRbfModel(file, function, geometry);
  file.commit();
}

}  // namespace nmdp
