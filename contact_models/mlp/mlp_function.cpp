#include "contact_models/mlp/mlp_function.hpp"

#include <torch/csrc/autograd/forward_grad.h>
#include <torch/torch.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <mutex>
#include <random>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "common/limits.hpp"
#include "common/named_enum.hpp"
#include "common/text.hpp"
#include "contact_models/mlp/mlp_names.hpp"

namespace nmdp {

namespace {

constexpr double kSoftplusThreshold = 36.0;  // log1p(exp(-36)) < half an ulp of 36: the switch is invisible

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

std::string layerName(size_t i) { return "/mlp/layer_" + std::to_string(i); }

// libtorch 1.13 keeps one forward-AD level for the whole process ("nested forward mode AD is not
// supported"): evaluations with forward-mode derivatives take turns.
std::mutex& forwardModeMutex() {
  static std::mutex mutex;
  return mutex;
}

// Enters a forward-AD level and leaves it on every path out.
class DualLevel {
 public:
  DualLevel() : index_(torch::autograd::ForwardADLevel::get_next_idx()) {}
  ~DualLevel() { torch::autograd::ForwardADLevel::release_idx(index_); }
  DualLevel(const DualLevel&) = delete;
  DualLevel& operator=(const DualLevel&) = delete;
  int64_t index() const { return static_cast<int64_t>(index_); }

 private:
  uint64_t index_;
};

constexpr EnumName<MlpJacobian> kJacobians[] = {{MlpJacobian::ForwardMode, "forward-mode"},
                                                {MlpJacobian::DoubleBackward, "double-backward"},
                                                {MlpJacobian::Tangents, "tangents"}};

// The normalized input of R rows (the batch repeated), augmented with a column of ones (layer 0
// holds its bias as a weight row): R × (F + 1).
RowMatrix augmentedInput(const Eigen::Ref<const Eigen::MatrixXd>& features, const Eigen::RowVectorXd& mean,
                         const Eigen::RowVectorXd& inv_std, Eigen::Index R) {
  const Eigen::Index B = features.rows(), F = features.cols();
  RowMatrix x(R, F + 1);
  for (Eigen::Index r = 0; r < R; ++r) {
    x.row(r).head(F) = (features.row(r % B) - mean).cwiseProduct(inv_std);
    x(r, F) = 1.0;
  }
  return x;
}

// "(phi, beta)" or "(phi, beta, gamma)": the network's input, for messages.
std::string inputText(const MlpParameters& p) {
  return p.wrench == MlpWrench::Spatial ? "(phi, beta, gamma)" : "(phi, beta)";
}

}  // namespace

// ----- activations and parameters ----------------------------------------------------------------

const char* mlpActivationName(MlpActivation activation) { return nameOf(kMlpActivations, activation); }

bool parseMlpActivation(const std::string& name, MlpActivation* activation) {
  return assignIfNamed(kMlpActivations, name, activation);
}

std::string mlpActivationProblem(const std::string& name) {
  MlpActivation a;
  if (parseMlpActivation(name, &a)) return "";
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.find("relu") != std::string::npos)
    return "activation '" + name + "' is not allowed: ReLU has a kink at 0 and the solver needs a contact model that "
           "is at least C1; use tanh, softplus or silu";
  return "unknown activation '" + name + "'; valid activations: tanh, softplus, silu";
}

const char* mlpJacobianName(MlpJacobian jacobian) { return nameOf(kJacobians, jacobian); }

bool parseMlpJacobian(const std::string& name, MlpJacobian* jacobian) { return assignIfNamed(kJacobians, name, jacobian); }

int MlpParameters::vertexCount() const {
  return layers.empty() ? 0 : static_cast<int>(layers.back().weight.rows() / wrenchWidth());
}

std::vector<int> MlpParameters::sizes() const {
  std::vector<int> out{featureCount()};
  for (const MlpLayer& l : layers) out.push_back(static_cast<int>(l.weight.rows()));
  return out;
}

namespace {

// The layers: shapes chained from the F inputs, finite values. Sets *outputs to the last layer's rows.
std::string layerProblem(const MlpParameters& p, Eigen::Index* outputs) {
  Eigen::Index in = p.featureCount();
  for (size_t i = 0; i < p.layers.size(); ++i) {
    const MlpLayer& l = p.layers[i];
    const std::string w = layerName(i) + "/weight", b = layerName(i) + "/bias";
    if (l.weight.rows() < 1 || l.weight.cols() != in) {
      const std::string why = i == 0 ? "the input is " + inputText(p)
                                     : "the previous layer " + layerName(i - 1) + " has " + std::to_string(in) + " outputs";
      return "dataset '" + w + "' is " + shapeText(l.weight) + ", expected (outputs) x " + std::to_string(in) + ": " + why;
    }
    if (const std::string bad = firstNonFinite(l.weight); !bad.empty())
      return "dataset '" + w + "' has a non-finite value (NaN or inf) at " + bad;
    if (l.bias.size() != l.weight.rows())
      return "dataset '" + b + "' has " + std::to_string(l.bias.size()) + " values, expected " +
             std::to_string(l.weight.rows()) + " (the rows of '" + w + "')";
    if (const std::string bad = firstNonFinite(l.bias); !bad.empty())
      return "dataset '" + b + "' has a non-finite value (NaN or inf) at " + bad;
    in = l.weight.rows();
  }
  *outputs = in;
  return "";
}

std::string anchorProblem(const MlpParameters& p) {
  if (const std::string bad = firstNonFinite(p.anchors); !bad.empty())
    return "dataset '/mlp/anchors' has a non-finite value (NaN or inf) at " + bad;
  if (!(p.anchor_radius > 0.0) || !std::isfinite(p.anchor_radius))
    return "attribute 'anchor_radius' of '/mlp' must be a positive finite number";
  if (p.output_envelope == MlpOutputEnvelope::Depth)
    return "zero anchors ('/mlp/anchors') and output_envelope \"" + std::string(mlpOutputEnvelopeName(p.output_envelope)) +
           "\" cannot be combined";
  if (p.anchors.cols() != p.featureCount())
    return "dataset '/mlp/anchors' is " + shapeText(p.anchors) + ", expected (anchors) x " +
           std::to_string(p.featureCount()) + ": the points " + inputText(p);
  const Eigen::ArrayXd inv_std = p.input_std.cwiseInverse().array();
  for (Eigen::Index a = 0; a < p.anchors.rows(); ++a)
    for (Eigen::Index c = a + 1; c < p.anchors.rows(); ++c) {
      const double d = ((p.anchors.row(a) - p.anchors.row(c)).transpose().array() * inv_std).matrix().norm();
      if (d < p.anchor_radius)
        return "anchors " + std::to_string(a) + " and " + std::to_string(c) + " of '/mlp/anchors' are " +
               std::to_string(d) + " apart (normalized), less than attribute 'anchor_radius' " +
               std::to_string(p.anchor_radius) + ": each anchor's bump must vanish at the others";
    }
  return "";
}

// Finite numbers can still overflow: bound |outputs| and |d outputs / d features| layer by layer
// for features within ±kMaxModelFeature (|Wx + b| ≤ row-sum(|W|)·|x| + |b|; tanh ≤ 1, softplus
// ≤ |x| + log 2, SiLU ≤ |x|; their slopes ≤ 1.1).
std::string overflowProblem(const MlpParameters& p) {
  double value = 0.0, slope = 0.0;
  for (int c = 0; c < p.featureCount(); ++c) {
    value = std::max(value, (limits::kMaxModelFeature + std::abs(p.input_mean[c])) / p.input_std[c]);
    slope = std::max(slope, 1.0 / p.input_std[c]);
  }
  for (size_t i = 0; i < p.layers.size(); ++i) {
    const double gain = p.layers[i].weight.cwiseAbs().rowwise().sum().maxCoeff();
    value = gain * value + p.layers[i].bias.cwiseAbs().maxCoeff();
    slope = gain * slope;
    if (i + 1 < p.layers.size()) {
      value = p.activation == MlpActivation::Tanh ? std::min(value, 1.0) : value + std::log(2.0);
      slope *= 1.1;
    }
  }
  const double scale = p.output_scale.cwiseAbs().maxCoeff();
  value = scale * value + p.output_offset.cwiseAbs().maxCoeff();
  slope *= scale;
  if (value <= limits::kMaxModelOutputBound && slope <= limits::kMaxModelOutputBound) return "";
  std::ostringstream out;
  out << "the weights of '/mlp' are so large that its output or derivative could overflow (bound " << std::max(value, slope)
      << " for features within " << limits::kMaxModelFeature << "): not a trained network";
  return out.str();
}

}  // namespace

std::string mlpParameterProblem(const MlpParameters& p) {
  if (p.layers.empty()) return "group '/mlp' has no layers: attribute 'layers' must be at least 1";
  const int F = p.featureCount();
  for (const auto& [name, v] : {std::pair<const char*, const Eigen::VectorXd*>{"/mlp/input_mean", &p.input_mean},
                                {"/mlp/input_std", &p.input_std}})
    if (v->size() != F)
      return "dataset '" + std::string(name) + "' has " + std::to_string(v->size()) + " values, expected " +
             std::to_string(F) + " (one per feature " + inputText(p) + ")";
  Eigen::Index in = F;
  if (std::string problem = layerProblem(p, &in); !problem.empty()) return problem;
  const std::string last = layerName(p.layers.size() - 1) + "/weight";
  if (in % p.wrenchWidth() != 0)
    return "dataset '" + last + "' has " + std::to_string(in) + " rows: the output layer must give " +
           (p.wrench == MlpWrench::Spatial ? "6 values (tau_x, tau_y, tau_z, F_x, F_y, F_z)"
                                           : "3 values (F_x, F_z, tau_y)") +
           " per vertex";
  if (!p.input_mean.allFinite()) return "dataset '/mlp/input_mean' has a non-finite value";
  if (!p.input_std.allFinite() || !(p.input_std.minCoeff() > 0.0))
    return "dataset '/mlp/input_std' must hold " + std::to_string(F) + " positive finite numbers";
  for (const auto& [name, v] : {std::pair<const char*, const Eigen::VectorXd*>{"/mlp/output_scale", &p.output_scale},
                                {"/mlp/output_offset", &p.output_offset}}) {
    if (v->size() != in)
      return "dataset '" + std::string(name) + "' has " + std::to_string(v->size()) + " values, expected " +
             std::to_string(in) + " (the rows of '" + last + "')";
    if (const std::string bad = firstNonFinite(*v); !bad.empty())
      return "dataset '" + std::string(name) + "' has a non-finite value (NaN or inf) at " + bad;
  }
  if (p.output_envelope == MlpOutputEnvelope::SoftDepth && !(p.envelope_width > 0.0 && std::isfinite(p.envelope_width)))
    return "attribute 'envelope_width' of '/mlp' must be a positive finite number (m) with output_envelope \"soft_depth\"";
  if (p.anchors.rows() > 0)
    if (std::string problem = anchorProblem(p); !problem.empty()) return problem;
  return overflowProblem(p);
}

namespace {

// mlpAnchorBumps for F features, in fixed-size arithmetic (the same operations for every F).
template <int F>
void anchorBumps(const MlpParameters& p, const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::MatrixXd& b,
                 const std::array<Eigen::MatrixXd*, 3>& db) {
  using Point = Eigen::Array<double, F, 1>;
  const Eigen::Index B = features.rows(), A = p.anchors.rows();
  const Point inv_std = p.input_std.head<F>().cwiseInverse().array();
  const double R = p.anchor_radius;
  for (Eigen::Index i = 0; i < B; ++i)
    for (Eigen::Index a = 0; a < A; ++a) {
      const Point d =
          (features.row(i).template head<F>() - p.anchors.row(a).template head<F>()).transpose().array() * inv_std;  // x̂ − x̂_a
      const double r = std::sqrt(d.square().sum()) / R;
      if (!(r < 1.0)) continue;
      const double u = 1.0 - r, u2 = u * u, u5 = u2 * u2 * u;
      b(i, a) = u5 * u * (35.0 * r * r + 18.0 * r + 3.0) / 3.0;
      // dψ/dr / r = −(56/3)(5r + 1)(1 − r)⁵, and dr/dx̂ = (x̂ − x̂_a) / (r R²): no 0/0 at the centre.
      const double g = -(56.0 / 3.0) * (5.0 * r + 1.0) * u5 / (R * R);
      for (int c = 0; c < F; ++c)
        if (db[c]) (*db[c])(i, a) = g * d[c] * inv_std[c];
    }
}

}  // namespace

void mlpAnchorBumps(const MlpParameters& p, const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::MatrixXd& b,
                    const std::array<Eigen::MatrixXd*, 3>& db) {
  const Eigen::Index B = features.rows(), A = p.anchors.rows();
  const int F = p.featureCount();
  if (features.cols() != F || p.anchors.cols() != F)
    throw std::invalid_argument("mlpAnchorBumps: features and anchors need " + std::to_string(F) + " columns");
  b.setZero(B, A);
  for (int c = 0; c < F; ++c)
    if (db[c]) db[c]->setZero(B, A);
  if (A == 0) return;
  if (F == 3)
    anchorBumps<3>(p, features, b, db);
  else
    anchorBumps<2>(p, features, b, db);
}

MlpParameters randomMlpParameters(int hidden_layers, int width, int vertices, MlpActivation activation,
                                  std::uint32_t seed, MlpWrench wrench) {
  if (hidden_layers < 0 || width < 1 || vertices < 1)
    throw std::invalid_argument("randomMlpParameters: needs hidden_layers >= 0, width >= 1, vertices >= 1");
  std::mt19937 rng(seed);
  const auto uniform = [&](double bound) {  // in (−bound, bound)
    const double u = (static_cast<double>(rng()) + 0.5) / 4294967296.0;
    return bound * (2.0 * u - 1.0);
  };
  MlpParameters p;
  p.wrench = wrench;
  p.activation = activation;
  p.input_mean = Eigen::VectorXd::Zero(p.featureCount());
  p.input_std = Eigen::VectorXd::Ones(p.featureCount());
  p.anchors.resize(0, p.featureCount());
  int in = p.featureCount();
  const int outputs = p.wrenchWidth() * vertices;
  for (int i = 0; i <= hidden_layers; ++i) {
    const int out = i < hidden_layers ? width : outputs;
    const double bound = 1.0 / std::sqrt(static_cast<double>(in));
    MlpLayer l;
    l.weight.resize(out, in);
    for (int r = 0; r < out; ++r)
      for (int c = 0; c < in; ++c) l.weight(r, c) = uniform(bound);
    l.bias.resize(out);
    for (int r = 0; r < out; ++r) l.bias[r] = uniform(bound);
    p.layers.push_back(std::move(l));
    in = out;
  }
  p.output_scale = Eigen::VectorXd::Ones(outputs);
  p.output_offset = Eigen::VectorXd::Zero(outputs);
  return p;
}

// ----- the function --------------------------------------------------------------------------------

// The layers as torch tensors, laid out for few ATen calls per layer (each call costs microseconds of
// dispatch at these sizes, the arithmetic far less):
//   * layer 0 reads the input augmented with a column of ones, (x̂_φ, x̂_β[, x̂_γ], 1), so its bias is the last
//     row of weight_t[0] and the layer is one torch::mm;
//   * middle layers are one torch::addmm (bias + h A_iᵀ);
//   * the last layer is a torch::mm without its bias, which evaluate() adds in Eigen together with the
//     output scaling (one rounded addition per entry, as in addmm: bit-identical with OpenBLAS here).
// Every scheme and the value-only pass run this same sequence of operations.
struct MlpFunction::Torch {
  std::vector<torch::Tensor> weight_t;     // in × out, contiguous (A_iᵀ); layer 0: 3 × out, last row b_0
  std::vector<torch::Tensor> bias;         // out; undefined for layer 0 and for the last layer
  std::vector<torch::Tensor> weight_zero;  // zeros like weight_t: forward-mode tangents of the parameters
  std::vector<torch::Tensor> bias_zero;    // zeros like bias (undefined where bias is)
  Eigen::RowVectorXd output_bias;          // b_L, added in Eigen (empty when layer 0 is the only layer)
  MlpActivation activation = MlpActivation::Tanh;

  torch::Tensor activate(const torch::Tensor& x) const {
    switch (activation) {
      case MlpActivation::Tanh: return torch::tanh(x);
      case MlpActivation::Softplus: return torch::softplus(x, 1.0, kSoftplusThreshold);
      case MlpActivation::Silu: return torch::silu(x);
    }
    return x;
  }

  // σ'(z) given z and h = σ(z) (softplus: the logistic function; above the threshold autograd uses 1,
  // which the logistic function equals to within 2.3e-16).
  torch::Tensor slope(const torch::Tensor& z, const torch::Tensor& h) const {
    switch (activation) {
      case MlpActivation::Tanh: return 1.0 - h * h;
      case MlpActivation::Softplus: return torch::sigmoid(z);
      case MlpActivation::Silu: {
        const torch::Tensor s = torch::sigmoid(z);
        return s * (1.0 + z * (1.0 - s));
      }
    }
    return torch::ones_like(z);
  }

  // MlpJacobian::Tangents: values on the first B rows of `input` exactly as in the value-only pass;
  // the D·B tangent rows (seeded by `seed`) through the same weights: dz = dh A_iᵀ, dh' = σ'(z) ⊙ dz
  // (σ'(z) broadcast over the D direction blocks). Returns {values, tangents}.
  std::pair<torch::Tensor, torch::Tensor> tangents(const torch::Tensor& input, const torch::Tensor& seed, int64_t B,
                                                   int64_t D) const {
    torch::NoGradGuard no_grad;
    torch::Tensor h = input.slice(0, 0, B), T = seed;
    const size_t n = weight_t.size();
    for (size_t i = 0; i < n; ++i) {
      const torch::Tensor z = affine(h, weight_t[i], bias[i]);
      T = torch::mm(T, weight_t[i]);
      if (i + 1 == n) {
        h = z;
        break;
      }
      h = activate(z);
      T = (T.view({D, B, -1}) * slope(z, h)).view({D * B, -1});
    }
    return {h, T};
  }

  // MlpJacobian::DoubleBackward: g(u) = Jᵀu, then ∂(g · seed)/∂u = J seed. Returns {values, tangents}.
  std::pair<torch::Tensor, torch::Tensor> doubleBackward(const torch::Tensor& input, const torch::Tensor& seed) const {
    torch::AutoGradMode grad_mode(true);
    const torch::Tensor leaf = input.detach().requires_grad_(true);
    const torch::Tensor y = forward(leaf);
    const torch::Tensor u = torch::zeros_like(y).requires_grad_(true);
    const torch::Tensor g = torch::autograd::grad({y}, {leaf}, {u}, /*retain_graph=*/true, /*create_graph=*/true)[0];
    const torch::Tensor tangent = torch::autograd::grad({g}, {u}, {seed})[0];
    return {y.detach(), tangent.detach()};
  }

  // Pre-activation of layer i.
  static torch::Tensor affine(const torch::Tensor& h, const torch::Tensor& weight_t, const torch::Tensor& bias) {
    return bias.defined() ? torch::addmm(bias, h, weight_t) : torch::mm(h, weight_t);
  }

  // The network on the augmented input (R × (F + 1)), without the output bias. With dual_level ≥ 0 (inside a
  // forward-AD level, h a dual tensor) the parameters enter as dual tensors with (cached) zero
  // tangents. Without a tangent, libtorch 1.13's forward formulas (addmm: b_t + h_t A + h A_t) get a
  // ZeroTensor, whose additions run through the Meta device and a copy and whose products go through a
  // boxed fallback that materializes the zeros: slower than the real products and sums with zeros.
  // The tangents are only read (no in-place op touches them) and ForwardMode runs under its mutex.
  torch::Tensor forward(torch::Tensor h, int64_t dual_level = -1) const {
    const size_t n = weight_t.size();
    for (size_t i = 0; i < n; ++i) {
      if (dual_level >= 0) {
        const torch::Tensor w = at::_make_dual(weight_t[i], weight_zero[i], dual_level);
        const torch::Tensor b = bias[i].defined() ? at::_make_dual(bias[i], bias_zero[i], dual_level) : bias[i];
        h = affine(h, w, b);
      } else {
        h = affine(h, weight_t[i], bias[i]);
      }
      if (i + 1 < n) h = activate(h);
    }
    return h;
  }
};

MlpFunction::MlpFunction(MlpParameters parameters, MlpJacobian jacobian)
    : params_(std::move(parameters)), jacobian_(jacobian) {
  if (const std::string problem = mlpParameterProblem(params_); !problem.empty())
    throw std::invalid_argument("MLP parameters: " + problem);
  torch::set_num_threads(1);  // process-global: deterministic single-threaded evaluation
  auto t = std::make_unique<Torch>();
  t->activation = params_.activation;
  const auto options = torch::TensorOptions().dtype(torch::kFloat64);
  const size_t n = params_.layers.size();
  for (size_t i = 0; i < n; ++i) {
    const MlpLayer& l = params_.layers[i];
    // The column-major out×in weight is, read row-major, its in×out transpose.
    torch::Tensor w =
        torch::from_blob(const_cast<double*>(l.weight.data()), {l.weight.cols(), l.weight.rows()}, options).clone();
    torch::Tensor b = torch::from_blob(const_cast<double*>(l.bias.data()), {l.bias.size()}, options).clone();
    if (i == 0) {
      w = torch::cat({w, b.unsqueeze(0)}, 0).contiguous();  // (in + 1) × out: the bias as the last row
      b = torch::Tensor();
    } else if (i + 1 == n) {
      t->output_bias = l.bias.transpose();
      b = torch::Tensor();
    }
    t->weight_zero.push_back(torch::zeros_like(w));
    t->bias_zero.push_back(b.defined() ? torch::zeros_like(b) : torch::Tensor());
    t->weight_t.push_back(std::move(w));
    t->bias.push_back(std::move(b));
  }
  torch_ = std::move(t);
  if (params_.anchors.rows() > 0) evaluateNetwork(params_.anchors, anchor_values_, {});
}

MlpFunction::~MlpFunction() = default;

std::string MlpFunction::describe() const {
  std::ostringstream s;
  s << "MLP ";
  const std::vector<int> sizes = params_.sizes();
  for (size_t i = 0; i < sizes.size(); ++i) s << (i ? "-" : "") << sizes[i];
  s << " " << mlpActivationName(params_.activation);
  if (params_.wrench == MlpWrench::Spatial) s << ", spatial (tau, F) wrenches of (phi, beta, gamma)";
  if (params_.output_envelope == MlpOutputEnvelope::Depth) s << ", W = (-phi) N depth envelope";
  if (params_.output_envelope == MlpOutputEnvelope::SoftDepth)
    s << ", W = w softplus(-phi/w) N soft depth envelope (w = " << params_.envelope_width << " m)";
  if (params_.anchors.rows() > 0) s << ", " << params_.anchors.rows() << " zero anchors";
  s << ", " << vertexCount() << " vertices, "
    << (jacobian_ == MlpJacobian::Tangents ? "hand-coded tangents" : std::string(mlpJacobianName(jacobian_)) + " autograd");
  return s.str();
}

void MlpFunction::evaluate(const Eigen::MatrixX2d& features, Eigen::MatrixXd& W, Eigen::MatrixXd* dW_dphi,
                           Eigen::MatrixXd* dW_dbeta) const {
  if (params_.wrench != MlpWrench::Planar)
    throw std::logic_error("MlpFunction: a spatial MLP evaluated as a planar feature function");
  evaluateAny(features, W, {dW_dphi, dW_dbeta, nullptr});
}

void MlpFunction::evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W,
                           std::array<Eigen::MatrixXd, 3>* dW) const {
  if (params_.wrench != MlpWrench::Spatial)
    throw std::logic_error("MlpFunction: a planar MLP evaluated as a spatial feature function");
  std::array<Eigen::MatrixXd*, 3> d{};
  if (dW) d = {&(*dW)[0], &(*dW)[1], &(*dW)[2]};
  evaluateAny(features, W, d);
}

void MlpFunction::evaluateAny(const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::MatrixXd& W,
                              std::array<Eigen::MatrixXd*, 3> dW) const {
  const int F = params_.featureCount();
  evaluateNetwork(features, W, dW);
  if (params_.anchors.rows() > 0 && features.rows() > 0) {
    Eigen::MatrixXd b;
    std::array<Eigen::MatrixXd, 3> db;
    std::array<Eigen::MatrixXd*, 3> db_asked{};
    for (int d = 0; d < F; ++d)
      if (dW[d]) db_asked[d] = &db[d];
    mlpAnchorBumps(params_, features, b, db_asked);
    W.noalias() -= b * anchor_values_;
    for (int d = 0; d < F; ++d)
      if (dW[d]) dW[d]->noalias() -= db[d] * anchor_values_;
  }
  if (params_.output_envelope == MlpOutputEnvelope::Depth && features.rows() > 0) {
    // W = (−φ) ⊙ N: dW/dφ = −N + (−φ) ⊙ dN/dφ, dW/df_d = (−φ) ⊙ dN/df_d for the angles (W still
    // holds N here). Not the soft branch's loop with m' = −1: that one may contract m' N + m dN into
    // an FMA, and files of this envelope keep their bits.
    const Eigen::ArrayXd depth = 0.0 - features.col(0).array();  // 0.0 − φ: +0 at the surface
    if (dW[0]) *dW[0] = (dW[0]->array().colwise() * depth - W.array()).matrix();
    for (int d = 1; d < F; ++d)
      if (dW[d]) dW[d]->array().colwise() *= depth;
    W.array().colwise() *= depth;
  } else if (params_.output_envelope == MlpOutputEnvelope::SoftDepth) {
    // W = m(φ) ⊙ N: dW/dφ = m' N + m dN/dφ, dW/df_d = m dN/df_d for the angles (W still holds N,
    // anchored, here: the anchors stay exact zeros).
    for (Eigen::Index i = 0; i < features.rows(); ++i) {
      double m, dm;
      mlpEnvelopeFactor(params_.output_envelope, params_.envelope_width, features(i, 0), &m, &dm);
      if (dW[0]) dW[0]->row(i) = dW[0]->row(i) * m + W.row(i) * dm;
      for (int d = 1; d < F; ++d)
        if (dW[d]) dW[d]->row(i) *= m;
      W.row(i) *= m;
    }
  }
}

void MlpFunction::evaluateNetwork(const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::MatrixXd& W,
                                  std::array<Eigen::MatrixXd*, 3> outputs) const {
  // Derivatives in some features are computed in all of them and the others dropped: the stacked
  // batch then has the same shape (so the BLAS the same kernels) whichever derivatives are asked for,
  // and dW/dφ alone is dW/dφ of the set bit for bit. The wrench models always ask for all.
  const int F = params_.featureCount();
  std::array<Eigen::MatrixXd, 3> dropped;
  bool any = false;
  for (int d = 0; d < F; ++d) any = any || outputs[d];
  if (any)
    for (int d = 0; d < F; ++d)
      if (!outputs[d]) outputs[d] = &dropped[d];
  const Eigen::Index B = features.rows();
  const Eigen::Index O = static_cast<Eigen::Index>(params_.wrenchWidth()) * vertexCount();
  W.resize(B, O);
  for (int d = 0; d < F; ++d)
    if (outputs[d]) outputs[d]->resize(B, O);
  if (B == 0) return;
  // The batch is stacked once per feature when derivatives are asked for (D = F), else D = 0.
  const int D = any ? F : 0;
  const Eigen::Index R = B * std::max(D, 1);

  const Eigen::RowVectorXd inv_std = params_.input_std.cwiseInverse().transpose();
  RowMatrix x = augmentedInput(features, params_.input_mean.transpose(), inv_std, R);
  const auto options = torch::TensorOptions().dtype(torch::kFloat64);
  const torch::Tensor input = torch::from_blob(x.data(), {R, F + 1}, options);
  const Torch& t = *torch_;
  const auto scale = params_.output_scale.transpose().array();
  const auto offset = params_.output_offset.transpose().array();
  const auto storeValues = [&](const torch::Tensor& y) {  // first B rows of R×O (without b_L) → W
    const torch::Tensor c = y.contiguous();
    const Eigen::Map<const RowMatrix> Y(c.data_ptr<double>(), y.size(0), O);
    if (t.output_bias.size() > 0)
      W = (((Y.topRows(B).rowwise() + t.output_bias).array().rowwise() * scale).rowwise() + offset).matrix();
    else
      W = ((Y.topRows(B).array().rowwise() * scale).rowwise() + offset).matrix();
  };
  const auto storeTangents = [&](const torch::Tensor& tangent) {  // block k of R×O → dW/df_d
    const torch::Tensor c = tangent.contiguous();
    const Eigen::Map<const RowMatrix> T(c.data_ptr<double>(), R, O);
    for (int k = 0; k < D; ++k) *outputs[k] = (T.middleRows(k * B, B).array().rowwise() * scale).matrix();
  };

  if (D == 0) {
    torch::NoGradGuard no_grad;
    storeValues(t.forward(input));
    return;
  }

  // Seeds: block k carries e_k / std_k, so the tangents are derivatives with respect to the raw
  // features (the column of ones is constant).
  RowMatrix seed = RowMatrix::Zero(R, F + 1);
  for (int k = 0; k < D; ++k) seed.block(k * B, k, B, 1).setConstant(inv_std[k]);
  const torch::Tensor seed_t = torch::from_blob(seed.data(), {R, F + 1}, options);

  if (jacobian_ == MlpJacobian::Tangents) {
    const auto [values, tangents] = t.tangents(input, seed_t, B, D);
    storeValues(values);
    storeTangents(tangents);
    return;
  }

  if (jacobian_ == MlpJacobian::ForwardMode) {
    std::lock_guard<std::mutex> lock(forwardModeMutex());
    torch::NoGradGuard no_grad;  // forward-mode AD does not need the reverse graph
    DualLevel level;
    const torch::Tensor y = t.forward(at::_make_dual(input, seed_t, level.index()), level.index());
    const auto [primal, tangent] = at::_unpack_dual(y, level.index());
    storeValues(primal);
    storeTangents(tangent);  // copied out before the level (and the tangent with it) is released
    return;
  }

  const auto [values, tangents] = t.doubleBackward(input, seed_t);
  torch::NoGradGuard no_grad;
  storeValues(values);
  storeTangents(tangents);
}

}  // namespace nmdp
