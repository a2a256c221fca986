// The RBF granular feature function (DESIGN.md §7.2, Zhu, Abdulmajeid & Hauser 2019): K planar
// wrenches (F_x, F_z, τ_y) as radial-basis-function interpolants of the features f = (φ, β),
//
//     W_j(f) = Σ_i W_{j,i} κ(ρ_i) + a_j + b_j φ + c_j β,     ρ_i = ‖S (f − c_i)‖,  S = diag(s_φ, s_β),
//
// the polynomial tail (a, b, c) being optional. PlanarWrenchModel (planar_wrench_model.hpp) places
// the wrenches in the world; rbf_model.hpp builds one from JSON.
//
// Kernels κ(ρ) (ε the shape parameter, used by the Gaussian and the multiquadrics only):
//   thin_plate            ρ² log ρ, κ(0) = 0                 C¹ (log-singular 2nd derivative at ρ = 0)
//   gaussian              exp(−(ερ)²)                        C^∞
//   multiquadric          √(1 + (ερ)²)                       C^∞
//   inverse_multiquadric  1 / √(1 + (ερ)²)                   C^∞
//   cubic                 ρ³                                 C²
//   linear                ρ                                  C⁰ only: not differentiable at a centre
// Derivatives use the gradient form ∂κ/∂f = g(ρ) S² (f − c) with g = κ'(ρ)/ρ, which stays finite:
// thin-plate g = 2 log ρ + 1, and g·S(f − c) → 0 at the centre, where the gradient is exactly 0
// (no NaN). For the linear kernel the gradient at ρ = 0 does not exist; the zero subgradient is
// returned there (elsewhere it is the unit vector S²(f − c)/ρ). Prefer a C¹ kernel for the solver.
//
// Evaluation is batched: the kernel values are computed elementwise (vectorized) for all B points
// and N centres into the basis [Φᵀ ∂Φᵀ/∂φ ∂Φᵀ/∂β] (N [+3] × 3B, the polynomial rows last), which
// multiplies the coefficients (N [+3] × 3K, stored row-major and padded to whole SIMD packets) in a
// register-blocked kernel (rbf_function.cpp). Every output entry is one fixed-order sum over the
// centres, so values are bit-identical whatever the batch size and with or without derivatives.
// The scratch is sized on first use for a batch size and reused: no allocation once warmed up,
// with or without derivatives. An instance is therefore not safe to evaluate from two threads at
// once (like the models).
//
// ----- File formats ------------------------------------------------------------------------------
// (a) The published text format (granular/robosimian_sand_rbf): a folder with
//       inputs.txt   N lines "depth theta": the centres c_i (φ in m, β in rad);
//       weights.txt  K·N lines "fx fz wy": the weight of vertex v and centre i on line v·N + i
//                    (0-based, counting non-blank lines).
//     Blank lines and lines starting with '#' are skipped. The kernel, the scaling and the geometry
//     are not stored: they come from the configuration (defaults: the published model's, thin-plate,
//     S = diag(5, 1), torque centre 0.1572 m, cut-off 0.1 m).
// (b) The project's HDF5 model file, format_version 1 (readable by h5py):
//       /                     attribute nmdp_model = "rbf" (string, informational)
//       /rbf                  group; attributes:
//           format_version    1 (float64)
//           epsilon           float64 > 0, kernel shape parameter (stored for every kernel)
//           torque_centre     float64, m up the leg from the foot point (PlanarGeometry)
//           cutoff            float64, m: zero wrench for φ ≥ cutoff
//           cutoff_width      float64 > 0, m: blending band below the cut-off
//           units             string, informational ("phi: m, beta: rad; F_x, F_z: N; tau_y: N m")
//       /rbf/kernel           (1) string: one of the kernel names above
//       /rbf/centres          N×2 float64, rows (φ, β), unscaled
//       /rbf/weights          N×3K float64, row i = centre i, columns 3j..3j+2 = vertex j's (F_x, F_z, τ_y)
//       /rbf/scaling          (2) float64 > 0: s_φ, s_β
//       /rbf/polynomial       optional, 3×3K float64: rows = coefficients of 1, φ, β
//       /rbf/feature_names    (2) strings "phi", "beta" (checked when present)
//     Every value must be finite; a wrong shape, a NaN, an unknown kernel or a newer format_version
//     is an InputError naming the file and the dataset or attribute.
#pragma once
#include <Eigen/Dense>
#include <string>

#include "common/named_enum.hpp"
#include "contact_models/planar_wrench_model.hpp"

namespace nmdp {

namespace h5 {
class File;
}

enum class RbfKernel { ThinPlate, Gaussian, Multiquadric, InverseMultiquadric, Cubic, Linear };
inline constexpr EnumName<RbfKernel> kRbfKernels[] = {
    {RbfKernel::ThinPlate, "thin_plate"}, {RbfKernel::Gaussian, "gaussian"},
    {RbfKernel::Multiquadric, "multiquadric"}, {RbfKernel::InverseMultiquadric, "inverse_multiquadric"},
    {RbfKernel::Cubic, "cubic"}, {RbfKernel::Linear, "linear"}};

const char* rbfKernelName(RbfKernel kernel);  // "thin_plate", "gaussian", ...
// Parses a kernel name; false when unknown.
bool parseRbfKernel(const std::string& name, RbfKernel* kernel);
std::string rbfKernelNames();  // "thin_plate, gaussian, ..." for messages

// κ(ρ) and g = κ'(ρ)/ρ as functions of r2 = ρ² (g = 0 at ρ = 0 for thin-plate and linear).
void rbfKernel(RbfKernel kernel, double epsilon, double r2, double* kappa, double* g);

// What the published text format does not store.
struct RbfKernelSpec {
  RbfKernel kernel = RbfKernel::ThinPlate;
  Eigen::Vector2d scaling = Eigen::Vector2d(5.0, 1.0);  // s_φ, s_β
  double epsilon = 1.0;                                 // Gaussian / multiquadric shape parameter
};

struct RbfParameters {
  RbfKernelSpec spec;
  Eigen::MatrixX2d centres;    // N×2, rows (φ, β)
  Eigen::MatrixXd weights;     // N×3K
  Eigen::MatrixXd polynomial;  // empty (no tail) or 3×3K: rows = coefficients of 1, φ, β
};

// "" when every number of `p` lies within the limits of common/limits.hpp (kMaxRbfCentreCoordinate,
// kMaxRbfWeight, kMaxRbfScale), else what does not, e.g. "centre 3 has |beta| = 3e+306 > 1000": a
// finite but huge number would make the model's wrenches overflow where it is evaluated.
std::string rbfMagnitudeProblem(const RbfParameters& p);

// The published sand model's geometry: torque centre 0.1572 m, cut-off 0.1 m (band 0.02 m).
PlanarGeometry publishedRbfGeometry();

class RbfFunction : public FeatureWrenchFunction {
 public:
  // Throws std::invalid_argument on inconsistent shapes, non-finite values, a non-positive scaling
  // or epsilon (the file loaders below report those as InputError first).
  explicit RbfFunction(RbfParameters parameters);

  int vertexCount() const override { return static_cast<int>(params_.weights.cols() / 3); }
  int centreCount() const { return static_cast<int>(params_.centres.rows()); }
  DerivativeSupport derivative() const override { return DerivativeSupport::Analytic; }
  std::string describe() const override;
  void evaluate(const Eigen::MatrixX2d& features, Eigen::MatrixXd& W, Eigen::MatrixXd* dW_dphi,
                Eigen::MatrixXd* dW_dbeta) const override;
  bool evaluateRows(const Eigen::MatrixX2d& features, Eigen::Index count, bool derivatives,
                    PlanarRows& rows) const override;

  const RbfParameters& parameters() const { return params_; }

 private:
  // Fills basis_ for the first `count` rows of `features`, sized for all of them (see evaluateRows).
  void computeBasis(const Eigen::MatrixX2d& features, Eigen::Index count, bool derivatives) const;

  RbfParameters params_;
  Eigen::MatrixX2d scaled_centres_;  // N×2: S c_i
  PlanarRows coefficients_;          // (N [+3])×C padded, row-major: weights stacked over the polynomial
  // Scratch: scaled differences, ρ², g for one point (N); the basis, (N [+3])×R padded, column r =
  // output row r of evaluateRows; the product for evaluate().
  mutable Eigen::ArrayXd dphi_, dbeta_, r2_, g_;
  mutable Eigen::MatrixXd basis_;
  mutable PlanarRows product_;
};

// Reads the published text format. Throws InputError naming the file (and line) on a missing file,
// a line without exactly 2 (inputs) or 3 (weights) numbers, a non-numeric or non-finite value, or a
// weight count that is not a positive multiple of the centre count.
RbfParameters readPublishedRbf(const std::string& inputs_path, const std::string& weights_path,
                               const RbfKernelSpec& spec = {});

struct RbfModelFile {
  RbfParameters parameters;
  PlanarGeometry geometry;
};

// Reads and validates an HDF5 model file (format above). Throws InputError naming file and dataset.
RbfModelFile readRbfHdf5(const std::string& path);

// Writes the HDF5 model file atomically (path + ".partial", renamed on success).
void saveRbfModel(const std::string& path, const RbfFunction& function, const PlanarGeometry& geometry);
// Writes the model (format above) into an open file, for writers that add groups of their own
// (training/rbf_fit.hpp adds the fit's report); the caller commits.
void writeRbfModel(h5::File& file, const RbfFunction& function, const PlanarGeometry& geometry);

}  // namespace nmdp
