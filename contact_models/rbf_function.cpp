#include "contact_models/rbf_function.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "io/hdf5_file.hpp"
#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"
#include "common/named_enum.hpp"
#include "common/text.hpp"
#include "contact_models/file_attributes.hpp"
#include "contact_models/rbf_basis.hpp"

namespace nmdp {

namespace {

constexpr int kFormatVersion = 1;
constexpr const char* kUnits = "phi: m, beta: rad; F_x, F_z: N; tau_y: N m";

constexpr int kRowBlock = kRbfRowBlock;

Eigen::Index roundUp(Eigen::Index n, Eigen::Index m) { return rbfRoundUp(n, m); }

}  // namespace

const char* rbfKernelName(RbfKernel kernel) { return nameOf(kRbfKernels, kernel); }

bool parseRbfKernel(const std::string& name, RbfKernel* kernel) { return assignIfNamed(kRbfKernels, name, kernel); }

std::string rbfKernelNames() { return join(namesOf(kRbfKernels)); }

void rbfKernel(RbfKernel kernel, double epsilon, double r2, double* kappa, double* g) {
  switch (kernel) {
    case RbfKernel::ThinPlate:
      // κ = ρ² log ρ = ½ r2 log r2;  κ'/ρ = 2 log ρ + 1 = log r2 + 1; at the centre κ = 0 and the
      // gradient g·S²(f − c) → 0, so g is set to 0 there rather than −∞.
      if (r2 > 0.0) {
        const double l = std::log(r2);
        *kappa = 0.5 * r2 * l;
        *g = l + 1.0;
      } else {
        *kappa = 0.0;
        *g = 0.0;
      }
      return;
    case RbfKernel::Gaussian: {
      const double e2 = epsilon * epsilon;
      *kappa = std::exp(-e2 * r2);
      *g = -2.0 * e2 * *kappa;
      return;
    }
    case RbfKernel::Multiquadric: {
      const double e2 = epsilon * epsilon;
      *kappa = std::sqrt(1.0 + e2 * r2);
      *g = e2 / *kappa;
      return;
    }
    case RbfKernel::InverseMultiquadric: {
      const double e2 = epsilon * epsilon;
      const double k = 1.0 / std::sqrt(1.0 + e2 * r2);
      *kappa = k;
      *g = -e2 * k * k * k;
      return;
    }
    case RbfKernel::Cubic: {
      const double rho = std::sqrt(r2);
      *kappa = r2 * rho;
      *g = 3.0 * rho;
      return;
    }
    case RbfKernel::Linear: {
      // Not differentiable at ρ = 0: the zero subgradient is returned there.
      const double rho = std::sqrt(r2);
      *kappa = rho;
      *g = rho > 0.0 ? 1.0 / rho : 0.0;
      return;
    }
  }
  *kappa = 0.0;
  *g = 0.0;
}

PlanarGeometry publishedRbfGeometry() {
  PlanarGeometry g;
  g.torque_centre = 0.1572;
  g.cutoff = 0.1;
  g.cutoff_width = 0.02;
  return g;
}

std::string rbfMagnitudeProblem(const RbfParameters& p) {
  return rbfMagnitudeProblem(p.centres, {"phi", "beta"}, p.weights, p.polynomial, p.spec.scaling, p.spec.epsilon);
}

RbfFunction::RbfFunction(RbfParameters parameters) : params_(std::move(parameters)) {
  const RbfParameters& p = params_;
  const Eigen::Index N = p.centres.rows();
  if (N < 1) throw std::invalid_argument("RbfFunction: no centres");
  if (p.weights.rows() != N || p.weights.cols() < 3 || p.weights.cols() % 3 != 0)
    throw std::invalid_argument("RbfFunction: weights must be N x 3K with N = " + std::to_string(N) + " centres, got " +
                                shapeText(p.weights));
  if (p.polynomial.size() != 0 && (p.polynomial.rows() != 3 || p.polynomial.cols() != p.weights.cols()))
    throw std::invalid_argument("RbfFunction: the polynomial tail must be 3 x " + std::to_string(p.weights.cols()) +
                                ", got " + shapeText(p.polynomial));
  if (!p.centres.allFinite() || !p.weights.allFinite() || !p.polynomial.allFinite())
    throw std::invalid_argument("RbfFunction: non-finite centre, weight or polynomial coefficient");
  if (!(p.spec.scaling.minCoeff() > 0.0) || !p.spec.scaling.allFinite())
    throw std::invalid_argument("RbfFunction: the feature scaling must be positive");
  if (!(p.spec.epsilon > 0.0) || !std::isfinite(p.spec.epsilon))
    throw std::invalid_argument("RbfFunction: epsilon must be positive");

  scaled_centres_ = p.centres * p.spec.scaling.asDiagonal();
  const Eigen::Index tail = p.polynomial.size() != 0 ? 3 : 0;
  const Eigen::Index C = p.weights.cols();
  coefficients_.setZero(N + tail, rbfPackedColumns(C));
  coefficients_.topLeftCorner(N, C) = p.weights;
  if (tail) coefficients_.bottomLeftCorner(3, C) = p.polynomial;
}

std::string RbfFunction::describe() const {
  std::ostringstream s;
  s << "RBF " << rbfKernelName(params_.spec.kernel) << " kernel";
  if (params_.spec.kernel == RbfKernel::Gaussian || params_.spec.kernel == RbfKernel::Multiquadric ||
      params_.spec.kernel == RbfKernel::InverseMultiquadric)
    s << " (epsilon " << params_.spec.epsilon << ")";
  s << ", " << centreCount() << " centres, " << vertexCount() << " vertices, scaling (" << params_.spec.scaling[0]
    << ", " << params_.spec.scaling[1] << ")" << (params_.polynomial.size() ? ", linear tail" : "");
  return s.str();
}

void RbfFunction::computeBasis(const Eigen::MatrixX2d& features, Eigen::Index count, bool derivatives) const {
  const Eigen::Index B = features.rows();
  const Eigen::Index N = scaled_centres_.rows();
  const Eigen::Index M = coefficients_.rows();
  const double sphi = params_.spec.scaling[0], sbeta = params_.spec.scaling[1];

  // The basis is sized by the batch only (not by the count or whether derivatives are asked for),
  // so alternating calls do not reallocate.
  if (dphi_.size() != N) {
    dphi_.resize(N);
    dbeta_.resize(N);
    r2_.resize(N);
    g_.resize(N);
  }
  if (basis_.rows() != M || basis_.cols() != roundUp(3 * B, kRowBlock)) basis_.resize(M, roundUp(3 * B, kRowBlock));
  const auto cphi = scaled_centres_.col(0).array(), cbeta = scaled_centres_.col(1).array();

  // Per point, vectorized over the centres, written straight into the basis (column r = output row
  // r: Φ, then ∂Φ/∂φ and ∂Φ/∂β of point b; the polynomial 1, φ, β in the last rows).
  const Eigen::Index per_point = derivatives ? 3 : 1;
  for (Eigen::Index b = 0; b < count; ++b) {
    const Eigen::Index r = per_point * b;
    Eigen::Map<Eigen::ArrayXd> kappa(basis_.col(r).data(), N);
    dphi_ = sphi * features(b, 0) - cphi;  // S(f_b − c_i)
    dbeta_ = sbeta * features(b, 1) - cbeta;
    r2_ = dphi_.square() + dbeta_.square();
    rbfKernelColumn(params_.spec.kernel, params_.spec.epsilon, r2_, kappa.data(), g_);
    if (M > N) basis_.col(r).tail<3>() << 1.0, features(b, 0), features(b, 1);
    if (!derivatives) continue;
    Eigen::Map<Eigen::ArrayXd>(basis_.col(r + 1).data(), N) = g_ * sphi * dphi_;  // ∂κ/∂f = g(ρ) S (S(f − c))
    Eigen::Map<Eigen::ArrayXd>(basis_.col(r + 2).data(), N) = g_ * sbeta * dbeta_;
    if (M > N) {
      basis_.col(r + 1).tail<3>() << 0.0, 1.0, 0.0;
      basis_.col(r + 2).tail<3>() << 0.0, 0.0, 1.0;
    }
  }
  // The padding up to a whole row block: zero (it may hold an earlier call's columns).
  const Eigen::Index R = per_point * count;
  basis_.middleCols(R, roundUp(R, kRowBlock) - R).setZero();
}

bool RbfFunction::evaluateRows(const Eigen::MatrixX2d& features, Eigen::Index count, bool derivatives,
                               PlanarRows& rows) const {
  computeBasis(features, count, derivatives);
  const Eigen::Index capacity = roundUp(3 * features.rows(), kRowBlock);
  if (rows.rows() != capacity || rows.cols() != coefficients_.cols()) rows.resize(capacity, coefficients_.cols());
  rbfProduct(coefficients_, basis_, roundUp((derivatives ? 3 : 1) * count, kRowBlock), rows);
  return true;
}

void RbfFunction::evaluate(const Eigen::MatrixX2d& features, Eigen::MatrixXd& W, Eigen::MatrixXd* dW_dphi,
                           Eigen::MatrixXd* dW_dbeta) const {
  const Eigen::Index B = features.rows();
  const Eigen::Index C = params_.weights.cols();
  const bool derivatives = dW_dphi != nullptr || dW_dbeta != nullptr;
  evaluateRows(features, B, derivatives, product_);
  const Eigen::Index per_point = derivatives ? 3 : 1;
  W.resize(B, C);
  if (dW_dphi) dW_dphi->resize(B, C);
  if (dW_dbeta) dW_dbeta->resize(B, C);
  for (Eigen::Index b = 0; b < B; ++b) {
    W.row(b) = product_.row(per_point * b).head(C);
    if (dW_dphi) dW_dphi->row(b) = product_.row(per_point * b + 1).head(C);
    if (dW_dbeta) dW_dbeta->row(b) = product_.row(per_point * b + 2).head(C);
  }
}

// ----- the published text format -------------------------------------------------------------

namespace {

// The published format's files hold centres × vertices weight lines; at the limits of both.
constexpr std::int64_t kMaxTableValues = 3 * limits::kMaxRbfCentres * limits::kMaxVertices;

// Reads every non-blank, non-comment line of a text file of `columns` numbers per line.
// Returns the values row by row; `line_numbers` receives the 1-based physical line of each row.
std::vector<double> readNumberTable(const std::string& path, int columns, const char* layout,
                                    std::vector<int>* line_numbers) {
  std::istringstream in(readInputFile(path, std::string("text file of '") + layout + "' lines"));
  std::vector<double> values;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream tokens(line);
    std::string token;
    int count = 0;
    while (tokens >> token) {
      ++count;
      if (count > columns) break;
      const char* begin = token.data();
      const char* end = token.data() + token.size();
      if (begin != end && *begin == '+') ++begin;
      double x = 0.0;
      const auto result = std::from_chars(begin, end, x);
      if (result.ec != std::errc() || result.ptr != end)
        throw InputError(path + ":" + std::to_string(number) + ": '" + token.substr(0, 40) + (token.size() > 40 ? "..." : "") +
                         "' is not a number (expected '" + layout + "')");
      if (!std::isfinite(x))
        throw InputError(path + ":" + std::to_string(number) + ": non-finite value '" + token.substr(0, 40) + "'");
      values.push_back(x);
    }
    if (static_cast<std::int64_t>(values.size()) > kMaxTableValues)
      throw InputError(path + ":" + std::to_string(number) + ": more than " + std::to_string(kMaxTableValues) +
                       " numbers, beyond any model this format can hold");
    if (count != columns)
      throw InputError(path + ":" + std::to_string(number) + ": expected " + std::to_string(columns) + " numbers '" +
                       layout + "', got " + (count > columns ? "more" : std::to_string(count)));
    if (line_numbers) line_numbers->push_back(number);
  }
  return values;
}

}  // namespace

RbfParameters readPublishedRbf(const std::string& inputs_path, const std::string& weights_path,
                               const RbfKernelSpec& spec) {
  RbfParameters p;
  p.spec = spec;
  const std::vector<double> centres = readNumberTable(inputs_path, 2, "depth theta", nullptr);
  const Eigen::Index N = static_cast<Eigen::Index>(centres.size() / 2);
  if (N == 0) throw InputError(inputs_path + ": no centres (expected N lines 'depth theta')");
  if (N > limits::kMaxRbfCentres)
    throw InputError(inputs_path + ": " + std::to_string(N) + " centres, more than the " + std::to_string(limits::kMaxRbfCentres) +
                     " a model may have");
  const std::vector<double> weights = readNumberTable(weights_path, 3, "fx fz wy", nullptr);
  const Eigen::Index lines = static_cast<Eigen::Index>(weights.size() / 3);
  if (lines == 0 || lines % N != 0)
    throw InputError(weights_path + ": " + std::to_string(lines) + " weight lines is not a positive multiple of the " +
                     std::to_string(N) + " centres of " + inputs_path +
                     " (expected K*N lines 'fx fz wy', vertex v and centre i on line v*N + i)");
  const Eigen::Index K = lines / N;
  if (K > limits::kMaxVertices)
    throw InputError(weights_path + ": " + std::to_string(K) + " vertices, more than the " + std::to_string(limits::kMaxVertices) +
                     " a model may have");
  p.centres.resize(N, 2);
  for (Eigen::Index i = 0; i < N; ++i) {
    p.centres(i, 0) = centres[2 * i];
    p.centres(i, 1) = centres[2 * i + 1];
  }
  p.weights.resize(N, 3 * K);
  for (Eigen::Index v = 0; v < K; ++v)
    for (Eigen::Index i = 0; i < N; ++i)
      for (int c = 0; c < 3; ++c) p.weights(i, 3 * v + c) = weights[3 * (v * N + i) + c];
  if (const std::string problem = rbfMagnitudeProblem(p); !problem.empty())
    throw InputError(inputs_path + " and " + weights_path + ": " + problem + ", beyond any contact model");
  return p;
}

// ----- the HDF5 model file -------------------------------------------------------------------

RbfModelFile readRbfHdf5(const std::string& path) {
  const h5::File file = h5::File::openRead(path);
  const FileAttributes rbf(file, path, "/rbf");
  const auto fail = [&](const std::string& what) { rbf.fail(what); };
  if (!file.exists("/rbf"))
    fail("not an nmdp RBF model file: group '/rbf' is missing (write one with saveRbfModel or 'nmdp fit')");
  rbf.checkFormatVersion(kFormatVersion);

  RbfModelFile out;
  RbfParameters& p = out.parameters;
  const std::vector<std::string> kernel = file.readStrings("/rbf/kernel");
  if (kernel.size() != 1 || !parseRbfKernel(kernel[0], &p.spec.kernel))
    fail("dataset '/rbf/kernel' must hold one kernel name, one of " + rbfKernelNames() + "; got '" +
         (kernel.empty() ? std::string() : kernel[0]) + "'" + (kernel.size() > 1 ? " and more" : ""));
  p.spec.epsilon = rbf.positive("epsilon", 1.0, false);
  out.geometry.torque_centre = rbf.finite("torque_centre");
  out.geometry.cutoff = rbf.finite("cutoff");
  out.geometry.cutoff_width = rbf.positive("cutoff_width", 0.0, true);
  if (const std::string problem = planarGeometryProblem(out.geometry); !problem.empty()) fail("attribute " + problem + " (of '/rbf')");

  const Eigen::MatrixXd centres = file.readMatrix("/rbf/centres", 2 * limits::kMaxRbfCentres);
  if (centres.rows() < 1 || centres.cols() != 2)
    fail("dataset '/rbf/centres' must be N x 2 (phi, beta), got " + shapeText(centres));
  if (centres.rows() > limits::kMaxRbfCentres)
    fail("dataset '/rbf/centres' has " + std::to_string(centres.rows()) + " centres, more than the " +
         std::to_string(limits::kMaxRbfCentres) + " a model may have");
  if (const std::string bad = firstNonFinite(centres); !bad.empty())
    fail("dataset '/rbf/centres' has a non-finite value at " + bad);
  const Eigen::MatrixXd weights = file.readMatrix("/rbf/weights", centres.rows() * 3 * limits::kMaxVertices);
  if (weights.rows() != centres.rows() || weights.cols() < 3 || weights.cols() % 3 != 0)
    fail("dataset '/rbf/weights' must be N x 3K with N = " + std::to_string(centres.rows()) +
         " (the rows of '/rbf/centres'), got " + shapeText(weights));
  if (weights.cols() / 3 > limits::kMaxVertices)
    fail("dataset '/rbf/weights' has " + std::to_string(weights.cols() / 3) + " vertices, more than the " +
         std::to_string(limits::kMaxVertices) + " a model may have");
  if (const std::string bad = firstNonFinite(weights); !bad.empty())
    fail("dataset '/rbf/weights' has a non-finite value at " + bad);
  const Eigen::MatrixXd scaling = file.readMatrix("/rbf/scaling", 64);
  if (scaling.size() != 2) fail("dataset '/rbf/scaling' must hold 2 numbers (s_phi, s_beta), got " + shapeText(scaling));
  if (!(scaling.minCoeff() > 0.0) || !scaling.allFinite())
    fail("dataset '/rbf/scaling' must hold positive finite numbers");
  if (file.exists("/rbf/polynomial")) {
    p.polynomial = file.readMatrix("/rbf/polynomial", 4 * 3 * weights.cols());
    if (p.polynomial.rows() != 3 || p.polynomial.cols() != weights.cols())
      fail("dataset '/rbf/polynomial' must be 3 x " + std::to_string(weights.cols()) + " (rows 1, phi, beta), got " +
           shapeText(p.polynomial));
    if (const std::string bad = firstNonFinite(p.polynomial); !bad.empty())
      fail("dataset '/rbf/polynomial' has a non-finite value at " + bad);
  }
  if (file.exists("/rbf/feature_names")) {
    const std::vector<std::string> names = file.readStrings("/rbf/feature_names");
    if (names != std::vector<std::string>{"phi", "beta"})
      fail(
          "dataset '/rbf/feature_names' must be [\"phi\", \"beta\"]: the RBF contact model takes the signed distance "
          "and the sagittal leg angle");
  }
  p.centres = centres;
  p.weights = weights;
  p.spec.scaling = Eigen::Vector2d(scaling.data()[0], scaling.data()[1]);
  if (const std::string problem = rbfMagnitudeProblem(p); !problem.empty()) fail("'/rbf': " + problem + ", beyond any contact model");
  return out;
}

void saveRbfModel(const std::string& path, const RbfFunction& function, const PlanarGeometry& geometry) {
  h5::File file = h5::File::createAtomic(path);
  writeRbfModel(file, function, geometry);
  file.commit();
}

void writeRbfModel(h5::File& file, const RbfFunction& function, const PlanarGeometry& geometry) {
  const RbfParameters& p = function.parameters();
  file.writeStringAttribute("/", "nmdp_model", "rbf");
  file.createGroup("/rbf");
  file.writeDoubleAttribute("/rbf", "format_version", kFormatVersion);
  file.writeDoubleAttribute("/rbf", "epsilon", p.spec.epsilon);
  file.writeDoubleAttribute("/rbf", "torque_centre", geometry.torque_centre);
  file.writeDoubleAttribute("/rbf", "cutoff", geometry.cutoff);
  file.writeDoubleAttribute("/rbf", "cutoff_width", geometry.cutoff_width);
  file.writeStringAttribute("/rbf", "units", kUnits);
  file.writeMatrix("/rbf/centres", p.centres);
  file.writeMatrix("/rbf/weights", p.weights);
  file.writeStrings("/rbf/kernel", {rbfKernelName(p.spec.kernel)});
  file.writeVector("/rbf/scaling", p.spec.scaling);
  if (p.polynomial.size() != 0) file.writeMatrix("/rbf/polynomial", p.polynomial);
  file.writeStrings("/rbf/feature_names", {"phi", "beta"});
}

}  // namespace nmdp
