// The 3-D RBF granular feature function: K six-dimensional wrenches (τ_x, τ_y, τ_z, F_x, F_y, F_z)
// as radial-basis-function interpolants of the features f = (φ, β, γ) (spatial_wrench_model.hpp),
//
//     W_j(f) = Σ_i W_{j,i} κ(ρ_i) + a_j + b_j φ + c_j β + d_j γ,   ρ_i = ‖S (f − c_i)‖,  S = diag(s_φ, s_β, s_γ),
//
// with the kernels of the planar RBF function (rbf_function.hpp: rbfKernel), the tail optional.
//
// ----- HDF5 model file (the planar file's layout, format_version 1, with three features) ----------
//   /                     attribute nmdp_model = "rbf" (string, informational)
//   /rbf                  group; attributes format_version 1, epsilon, cutoff, cutoff_width, units
//                         ("phi: m, beta: rad, gamma: rad; tau: N m about the foot point; F: N")
//   /rbf/kernel           (1) string
//   /rbf/centres          N×3 float64, rows (φ, β, γ): a file whose centres have 3 columns is spatial
//   /rbf/weights          N×6K float64, columns 6j .. 6j + 5 = vertex j's (τ_x, τ_y, τ_z, F_x, F_y, F_z)
//   /rbf/scaling          (3) float64 > 0
//   /rbf/polynomial       optional, 4×6K float64: rows = coefficients of 1, φ, β, γ
//   /rbf/feature_names    (3) strings "phi", "beta", "gamma"
// The "rbf" contact model (rbf_model.hpp) loads either kind: two columns of centres give the planar
// model, three the spatial one. Every error is an InputError naming the file and the dataset.
#pragma once
#include <Eigen/Dense>
#include <string>

#include "contact_models/rbf_function.hpp"
#include "contact_models/spatial_wrench_model.hpp"

namespace nmdp {

namespace h5 {
class File;
}

struct SpatialRbfParameters {
  RbfKernel kernel = RbfKernel::ThinPlate;
  Eigen::Vector3d scaling = Eigen::Vector3d(20.0, 1.0, 1.0);  // s_φ, s_β, s_γ
  double epsilon = 1.0;
  Eigen::MatrixX3d centres;    // N×3, rows (φ, β, γ)
  Eigen::MatrixXd weights;     // N×6K
  Eigen::MatrixXd polynomial;  // empty (no tail) or 4×6K
};

class SpatialRbfFunction : public SpatialFeatureFunction {
 public:
  // Throws std::invalid_argument on inconsistent shapes, non-finite values, a non-positive scaling
  // or epsilon.
  explicit SpatialRbfFunction(SpatialRbfParameters parameters);

  int vertexCount() const override;
  int centreCount() const { return static_cast<int>(params_.centres.rows()); }
  DerivativeSupport derivative() const override { return DerivativeSupport::Analytic; }
  std::string describe() const override;
  void evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W,
                std::array<Eigen::MatrixXd, 3>* dW) const override;
  bool evaluateRows(const Eigen::MatrixX3d& features, Eigen::Index count, bool derivatives,
                    SpatialRows& rows) const override;

  const SpatialRbfParameters& parameters() const { return params_; }

 private:
  // Fills basis_ for the first `count` rows of `features`, sized for all of them (see evaluateRows).
  void computeBasis(const Eigen::MatrixX3d& features, Eigen::Index count, bool derivatives) const;

  SpatialRbfParameters params_;
  Eigen::MatrixX3d scaled_centres_;  // N×3: S c_i
  SpatialRows coefficients_;         // (N [+4])×C padded, row-major: weights stacked over the polynomial
  // Scratch: scaled differences, ρ², κ, g for one point (N); the basis, (N [+4])×R padded, column r =
  // output row r of evaluateRows; the product for evaluate(). Sized on first use, then reused.
  mutable Eigen::ArrayXd d0_, d1_, d2_, r2_, kappa_, g_;
  mutable Eigen::MatrixXd basis_;
  mutable SpatialRows product_;
};

// "" when every number of `p` lies within the limits of common/limits.hpp (as rbfMagnitudeProblem).
std::string spatialRbfMagnitudeProblem(const SpatialRbfParameters& p);

struct SpatialRbfModelFile {
  SpatialRbfParameters parameters;
  SpatialGeometry geometry;
};

// Whether the HDF5 model file at `path` holds a spatial RBF (centres with 3 columns). Throws
// InputError naming the file when it is not a readable RBF model file.
bool isSpatialRbfFile(const std::string& path);
// Reads and validates a spatial model file (format above). Throws InputError naming file and dataset.
SpatialRbfModelFile readSpatialRbfHdf5(const std::string& path);
// Writes the model (format above) into an open file, for writers that add groups of their own
// (the fit adds /fit); the caller commits.
void writeSpatialRbfModel(h5::File& file, const SpatialRbfFunction& function, const SpatialGeometry& geometry);
// Writes the model file atomically (path + ".partial", renamed on success).
void saveSpatialRbfModel(const std::string& path, const SpatialRbfFunction& function, const SpatialGeometry& geometry);

}  // namespace nmdp
