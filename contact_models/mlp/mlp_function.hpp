// A small multilayer perceptron as a feature function (DESIGN.md §7.3), evaluated with libtorch in
// double precision, of one of two kinds (MlpWrench, the file's attribute 'wrench'):
//   * planar:  K planar wrenches (F_x, F_z, τ_y) of the features f = (φ, β), a FeatureWrenchFunction
//              that PlanarWrenchModel (planar_wrench_model.hpp) places in the world;
//   * spatial: K six-dimensional wrenches (τ_x, τ_y, τ_z, F_x, F_y, F_z) of f = (φ, β, γ), a
//              SpatialFeatureFunction that SpatialWrenchModel (spatial_wrench_model.hpp) places.
// Everything below is written for the planar kind; the spatial one is the same code with F = 3
// inputs and w = 6 outputs per vertex instead of F = 2 and w = 3 (the network, the normalization,
// the envelopes, which depend on φ only, the anchors, which are points of F features, and the three
// Jacobian schemes, which stack the batch once per feature). mlp_model.hpp builds either from JSON.
// libtorch stays inside mlp_function.cpp: this header includes no torch header.
//
// The function, for L hidden layers (L ≥ 0) of widths H_1..H_L and the affine layers i = 0..L:
//
//     x̂ = (f − input_mean) ⊘ input_std                       (2)
//     h_0 = x̂,   h_{i+1} = σ(A_i h_i + b_i)   for i < L       (A_i: out_i × in_i, the torch layout)
//     y = A_L h_L + b_L                                        (3K)
//     N = output_scale ⊙ y + output_offset                    (3K; vertex j = entries 3j, 3j+1, 3j+2)
//     W = N                  with output_envelope "none" (the default)
//     W = (−φ) ⊙ N           with output_envelope "depth"
//     W = m(φ) ⊙ N           with output_envelope "soft_depth", m(φ) = w softplus(−φ/w) = w log(1 + e^(−φ/w))
//
// with a smooth activation σ (the solver needs C¹; ReLU is rejected):
//   tanh       tanh(x)
//   softplus   log(1 + eˣ), computed as torch softplus(x, beta = 1, threshold = 36): above 36 it
//              returns x, which equals log(1 + eˣ) and its slope 1 to double precision (the torch
//              default threshold 20, e.g. when training in float32, differs by < 2.1e-9)
//   silu       x / (1 + e⁻ˣ)
//
// The depth envelope (MlpOutputEnvelope::Depth) makes the wrench vanish exactly at the surface φ = 0:
// near the surface W ≈ N(0, β)·(−φ), so the network fits the slope W/(−φ), of order 1 down to the
// surface, instead of a wrench that fades to zero there. (The published sand model is zero at φ = 0
// only at its measured angles, not between them, so the envelope does not bring an MLP closer to it:
// training/README.md.) The factor is linear, so W stays C∞; above the surface it changes sign, and
// there the training's zero points drive N to ≈ 0 and the model's cut-off
// (planar_wrench_model.hpp) zeroes every wrench above `cutoff`. Derivatives:
//     dW/dφ = −N + (−φ) ⊙ dN/dφ,   dW/dβ = (−φ) ⊙ dN/dβ,
// applied in Eigen after the network pass (N and dN from any of the schemes below).
//
// The soft depth envelope (MlpOutputEnvelope::SoftDepth, width w = envelope_width in m) is −φ a few
// w below the surface, w log 2 at it and fades as e^(−φ/w) above it: smooth everywhere and never zero,
// so unlike "depth" it does not force W to vanish between the data's measured surface points. The
// network then fits W/m, of about one size at all depths. dW/dφ = m' N + m dN/dφ, m' = −sigmoid(−φ/w);
// dW/dβ = m dN/dβ. With zero anchors the factor multiplies the anchored network, W = m (N − Σ b_a N(ξ_a)),
// still exactly zero at the anchors.
//
// Zero anchors (optional; `anchors` A × 2 points ξ_a, `anchor_radius` R > 0): the model is
//     W(ξ) = N(ξ) − Σ_a b_a(ξ) N(ξ_a),   b_a(ξ) = ψ(‖x̂(ξ) − x̂(ξ_a)‖ / R),
// x̂ the normalized input (2), ψ(r) = (1 − r)⁶ (35 r² + 18 r + 3) / 3 for r < 1 and 0 beyond (Wendland's
// C⁴ function, ψ(0) = 1, ψ'(0) = 0). R must not exceed the smallest distance between two anchors
// (normalized), so b_a(ξ_c) = δ_ac and W is exactly zero (to round-off) at every anchor, whatever the
// network: the trainer anchors the training points whose wrench is exactly zero (the surface points of
// the sand data), where a plain network leaves a small non-zero wrench that is large relative to the
// vanishing wrench nearby. W stays C⁴ (bumps of compact support, constant coefficients N(ξ_a),
// computed once when the function is built), and since ψ'(0) = 0 the gradient at an anchor is the
// network's. Derivatives: dW/df = dN/df − Σ_a (db_a/df) N(ξ_a), applied in Eigen after the network pass.
// Anchors and the "depth" envelope are exclusive (its factor is zero at the surface already).
//
// Evaluation: all rows of a batch go through the network in one pass, one ATen call per affine
// layer with the transposed weight A_iᵀ stored contiguous (the reference BLAS multiplies it faster
// than the out×in layout of torch::nn::Linear): layer 0 is a torch::mm on the input augmented
// with a column of ones (its bias is a weight row), the middle layers torch::addmm, the last layer a
// torch::mm whose bias is added in Eigen with the output scaling. Without derivatives the pass runs
// under torch::NoGradGuard (no graph is recorded). dW/dφ and dW/dβ, by one of (MlpJacobian):
//   * ForwardMode (default): libtorch forward-mode autograd (dual tensors). The input has 2
//     columns and the output 3K = 78, so the Jacobian is cheapest column by column: the batch is
//     stacked once per direction (block d carries the seed e_d ⊘ input_std) and one forward pass
//     returns the values and both columns. The weights and biases enter as dual tensors
//     with zero tangents (libtorch 1.13's ZeroTensor path for absent tangents is slower).
//     libtorch 1.13 allows one forward-AD level per process, so these evaluations are serialized by
//     a mutex private to mlp_function.cpp (value-only passes and the other schemes still run
//     concurrently).
//   * DoubleBackward: libtorch reverse-mode autograd on the same stacked batch, twice (the
//     "double-backward" Jacobian-vector product): g(u) = Jᵀu for a dummy u with the graph kept,
//     then ∂(g·seed)/∂u = J·seed. Public API, no process-wide state, slower than ForwardMode.
//   * Tangents: the same forward-mode tangents coded by hand with torch ops (dz = dh A_iᵀ,
//     dh' = σ'(z) ⊙ dz), the values on B rows and the tangents on 2B rows: no primal rows are
//     duplicated and no AD bookkeeping runs, the fastest scheme. derivative() then says
//     Analytic. The tests check it against both autograd schemes and central differences.
//   Reverse mode with one-hot output seeds would need the batch stacked 3K times, so it is not
//   offered. (bench/bench_contact_models times each scheme.)
// Asking for one derivative computes both and drops the other (both directions are always stacked),
// so dW/dφ alone is bit for bit dW/dφ of the pair: a smaller batch would let the BLAS pick another
// kernel (it picks by shape and CPU) and round differently. The schemes and the value-only pass are
// different computations (batches of B or 2B rows through different ops): they agree to a few ulps of
// the largest entry (tested), not bit for bit.
//
// Threads and determinism: constructing an MlpFunction calls torch::set_num_threads(1), which is
// PROCESS-GLOBAL in libtorch (it also affects e.g. a trainer in the same process; a trainer that
// wants more threads must set them after building its MlpFunctions and reset them to 1 before
// evaluating). With one thread and the fixed summation order of the BLAS, the same evaluation twice
// is bit-identical (tested); a row of a batch agrees with that row evaluated alone to round-off, not
// bit for bit, since the BLAS picks its kernels by the number of rows.
// evaluate() is const and keeps no scratch, so one function may be shared by several models and
// threads. libtorch allocates its tensors on every call: the MLP is exempt from the
// no-allocation-while-stepping rule.
//
// ----- File format (HDF5, readable by h5py; never TorchScript: loading executes nothing) ---------
//   /                        attribute nmdp_model = "mlp"
//   /mlp                     group; attributes:
//       format_version       1 (float64), 2 when output_envelope is "depth", 3 with zero anchors, 4 with
//                            output_envelope "soft_depth" (files without any stay version 1, readable by
//                            older programs), 5 for a spatial MLP; 1 to 5 are read
//       activation           string: "tanh", "softplus" or "silu"
//       layers               float64, integer L + 1 ≥ 1: the number of affine layers
//       vertices             float64, integer K ≥ 1: the output has 3K entries
//       wrench               string "planar": the output holds (F_x, F_z, τ_y) per vertex; "spatial"
//                            (format_version 5): (τ_x, τ_y, τ_z, F_x, F_y, F_z) per vertex in the frame
//                            of spatial_wrench_model.hpp, the torque about the foot point, of the
//                            features (φ, β, γ). Spatial files differ from the planar layout below
//                            only in: inputs = 3 (attribute, float64), no torque_centre, units
//                            "phi: m, beta: rad, gamma: rad; tau: N m about the foot point; F: N",
//                            feature_names (phi, beta, gamma), input_mean/input_std/anchors with 3
//                            entries or columns, output_scale/output_offset and the last layer 6K.
//       torque_centre        float64, m up the leg from the foot point (PlanarGeometry)
//       cutoff               float64, m: zero wrench for φ ≥ cutoff
//       cutoff_width         float64 > 0, m: blending band below the cut-off
//       units                string, informational ("phi: m, beta: rad; F_x, F_z: N; tau_y: N m")
//       output_envelope      string, optional: "none" (W = N; the default when absent), "depth"
//                            (W = (−φ) ⊙ N) or "soft_depth" (see above); written unless "none"
//       envelope_width       float64 > 0, m: w of "soft_depth" (required with it)
//   /mlp/feature_names       (2) strings "phi", "beta" (checked when present)
//   /mlp/input_mean          (2) float64: mean of (φ, β)
//   /mlp/input_std           (2) float64 > 0
//   /mlp/output_scale        (3K) float64
//   /mlp/output_offset       (3K) float64
//   /mlp/layer_{i}/weight    out_i × in_i float64 (i = 0..L): in_0 = 2, in_i = out_{i−1}, out_L = 3K
//   /mlp/layer_{i}/bias      (out_i) float64
//   /mlp/anchors             (A × 2) float64, optional: the zero anchors (φ, β) (format_version 3),
//                            with the attribute anchor_radius of /mlp (R > 0, normalized input units)
// Every value must be finite. A missing dataset or attribute, a wrong shape, a NaN or inf, an
// unknown activation (ReLU included), an unknown output_envelope, a wrench kind other than "planar"
// or "spatial"
// or a newer format_version is an InputError naming the file and the dataset or attribute.
#pragma once
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "contact_models/mlp/mlp_names.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "contact_models/spatial_wrench_model.hpp"

namespace nmdp {

namespace h5 {
class File;
}

const char* mlpActivationName(MlpActivation activation);  // "tanh", "softplus", "silu"
// Parses an activation name; false when unknown (ReLU and its kin included: see mlpActivationProblem).
bool parseMlpActivation(const std::string& name, MlpActivation* activation);
// Why `name` is not an accepted activation, for messages ("" when it is accepted).
std::string mlpActivationProblem(const std::string& name);

// "none", "depth", "soft_depth" (kMlpOutputEnvelopes).
inline const char* mlpOutputEnvelopeName(MlpOutputEnvelope envelope) { return nameOf(kMlpOutputEnvelopes, envelope); }
// false when `name` is none of them.
inline bool parseMlpOutputEnvelope(const std::string& name, MlpOutputEnvelope* envelope) {
  const auto found = enumFromName(kMlpOutputEnvelopes, name);
  if (found) *envelope = *found;
  return found.has_value();
}
// The envelope's factor m(φ) and dm/dφ (width w, m, for SoftDepth only). Inline: the trainer uses it
// for its fixed per-row factors.
inline void mlpEnvelopeFactor(MlpOutputEnvelope envelope, double width, double phi, double* m, double* dm_dphi) {
  switch (envelope) {
    case MlpOutputEnvelope::Depth:
      *m = 0.0 - phi;  // +0 at the surface
      *dm_dphi = -1.0;
      return;
    case MlpOutputEnvelope::SoftDepth: {
      // w log(1 + e^z), z = −φ/w, in the form that neither overflows nor loses digits: for z > 0,
      // z + log(1 + e^−z).
      const double z = -phi / width, e = std::exp(-std::abs(z));
      *m = width * (std::max(z, 0.0) + std::log1p(e));
      *dm_dphi = -(z >= 0.0 ? 1.0 / (1.0 + e) : e / (1.0 + e));  // −sigmoid(z)
      return;
    }
    default:
      *m = 1.0;
      *dm_dphi = 0.0;
  }
}

// One affine layer in the torch layout: y = weight · x + bias.
struct MlpLayer {
  Eigen::MatrixXd weight;  // out × in
  Eigen::VectorXd bias;    // out
};

// Everything that defines the function: what the file stores, what the trainer fits.
struct MlpParameters {
  MlpWrench wrench = MlpWrench::Planar;  // F = 2 inputs, w = 3 outputs per vertex; spatial: 3 and 6
  MlpActivation activation = MlpActivation::Tanh;
  Eigen::VectorXd input_mean = Eigen::VectorXd::Zero(2);  // F: (φ, β) or (φ, β, γ)
  Eigen::VectorXd input_std = Eigen::VectorXd::Ones(2);   // F, > 0
  Eigen::VectorXd output_scale;                          // wK
  Eigen::VectorXd output_offset;                         // wK
  std::vector<MlpLayer> layers;                          // L hidden layers, then the output layer
  MlpOutputEnvelope output_envelope = MlpOutputEnvelope::None;  // W = N, or W = m(φ) ⊙ N
  double envelope_width = 0.0;  // w of the SoftDepth envelope (m, > 0); unused by the others
  Eigen::MatrixXd anchors = Eigen::MatrixXd(0, 2);  // A × F zero anchors (φ, β[, γ]); none by default
  double anchor_radius = 0.0;                         // R of the anchors' bumps (normalized input units)

  int featureCount() const { return mlpFeatureCount(wrench); }  // F
  int wrenchWidth() const { return mlpWrenchWidth(wrench); }    // w
  int vertexCount() const;        // K (0 when there are no layers)
  std::vector<int> sizes() const;  // F, H_1, ..., H_L, wK
};

// "" when `p` is consistent, else what is wrong, naming the dataset of the file format
// (e.g. "dataset '/mlp/layer_1/weight' is 64 x 32, expected 64 x 64 (...)").
std::string mlpParameterProblem(const MlpParameters& p);

// The anchors' bumps b_a at the features (B × F; b: B × A; see "Zero anchors" above), and their
// derivatives in feature d into *db[d] where db[d] is not null. Zero columns when p has no anchors.
void mlpAnchorBumps(const MlpParameters& p, const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::MatrixXd& b,
                    const std::array<Eigen::MatrixXd*, 3>& db = {});

// A network with the torch default initialization (weights and biases uniform in ±1/√in), identity
// normalization (mean 0, std 1, scale 1, offset 0). Deterministic for a seed on every platform
// (std::mt19937 words mapped to [0, 1) by hand, no std::uniform_real_distribution).
MlpParameters randomMlpParameters(int hidden_layers, int width, int vertices, MlpActivation activation,
                                  std::uint32_t seed, MlpWrench wrench = MlpWrench::Planar);

enum class MlpJacobian { ForwardMode, DoubleBackward, Tangents };
const char* mlpJacobianName(MlpJacobian jacobian);  // "forward-mode", "double-backward", "tangents"
bool parseMlpJacobian(const std::string& name, MlpJacobian* jacobian);  // false when unknown

// Either kind behind the interface of its kind; the other interface's evaluate throws
// std::logic_error (a planar MLP has no γ, a spatial one no planar wrench).
class MlpFunction : public FeatureWrenchFunction, public SpatialFeatureFunction {
 public:
  // Throws std::invalid_argument when mlpParameterProblem(parameters) is not empty (the file loader
  // reports the same problems as InputError first). Calls torch::set_num_threads(1) (see above).
  explicit MlpFunction(MlpParameters parameters, MlpJacobian jacobian = MlpJacobian::ForwardMode);
  ~MlpFunction() override;
  MlpFunction(const MlpFunction&) = delete;
  MlpFunction& operator=(const MlpFunction&) = delete;

  int vertexCount() const override { return params_.vertexCount(); }
  // Autograd (ForwardMode, DoubleBackward) or Analytic (Tangents).
  DerivativeSupport derivative() const override {
    return jacobian_ == MlpJacobian::Tangents ? DerivativeSupport::Analytic : DerivativeSupport::Autograd;
  }
  // e.g. "MLP 2-64-64-78 tanh, 26 vertices, forward-mode autograd"; with the depth envelope
  // "MLP 2-64-64-78 tanh, W = (-phi) N depth envelope, 26 vertices, forward-mode autograd".
  std::string describe() const override;
  // Planar: features B×2 rows (φ, β); W, dW_dphi, dW_dbeta: B×3K (resized). One network pass per call.
  void evaluate(const Eigen::MatrixX2d& features, Eigen::MatrixXd& W, Eigen::MatrixXd* dW_dphi,
                Eigen::MatrixXd* dW_dbeta) const override;
  // Spatial: features B×3 rows (φ, β, γ); W and (*dW)[d] = ∂W/∂f_d: B×6K (resized).
  void evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W, std::array<Eigen::MatrixXd, 3>* dW) const override;
  MlpWrench wrench() const { return params_.wrench; }

  const MlpParameters& parameters() const { return params_; }
  const std::vector<MlpLayer>& layers() const { return params_.layers; }
  MlpJacobian jacobian() const { return jacobian_; }

 private:
  // Either kind: W and ∂W/∂f_d into *dW[d] (d < F) where not null.
  void evaluateAny(const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::MatrixXd& W,
                   std::array<Eigen::MatrixXd*, 3> dW) const;
  // N and its derivatives (the network without the output envelope), by the jacobian scheme.
  void evaluateNetwork(const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::MatrixXd& N,
                       std::array<Eigen::MatrixXd*, 3> dN) const;

  struct Torch;  // the layers as libtorch tensors (mlp_function.cpp)
  MlpParameters params_;
  Eigen::MatrixXd anchor_values_;  // A × wK: N at the anchors
  MlpJacobian jacobian_;
  std::unique_ptr<const Torch> torch_;
};

struct MlpModelFile {
  MlpParameters parameters;
  PlanarGeometry geometry;  // a spatial file's cut-off and band, torque_centre 0 (it has none)
  SpatialGeometry spatialGeometry() const { return SpatialGeometry{geometry.cutoff, geometry.cutoff_width}; }
};

// Reads and validates an HDF5 model file (format above). Throws InputError naming the file and the
// dataset or attribute.
MlpModelFile loadMlpModel(const std::string& path);

// Writes the HDF5 model file atomically (path + ".partial", renamed on success). Throws
// std::invalid_argument on inconsistent parameters or a non-positive cutoff_width, InputError when
// the file cannot be written.
void saveMlpModel(const std::string& path, const MlpParameters& parameters, const PlanarGeometry& geometry);
void saveMlpModel(const std::string& path, const MlpFunction& function, const PlanarGeometry& geometry);
// Writes the model (the format above) into an open file, e.g. one that also gets the trainer's
// /fit group (training/mlp/mlp_fit.hpp), which loadMlpModel ignores. Same checks as saveMlpModel.
void writeMlpModel(h5::File& file, const MlpParameters& parameters, const PlanarGeometry& geometry);
// The same for a spatial MLP (parameters.wrench = Spatial; the planar overloads refuse one).
void saveMlpModel(const std::string& path, const MlpParameters& parameters, const SpatialGeometry& geometry);
void writeMlpModel(h5::File& file, const MlpParameters& parameters, const SpatialGeometry& geometry);

}  // namespace nmdp
