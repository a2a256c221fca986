#include "training/fit_config.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <sstream>

#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "training/fit_warnings.hpp"

namespace nmdp {

namespace {
[[noreturn]] void fail(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}

// The activation names of contact_models/mlp/mlp_function.hpp, repeated here: that file is in the
// libtorch library and this one in the core (test_fit links the core only).
const char* activationName(MlpActivation a) {
  switch (a) {
    case MlpActivation::Tanh: return "tanh";
    case MlpActivation::Softplus: return "softplus";
    case MlpActivation::Silu: return "silu";
  }
  return "?";
}
bool parseActivation(const std::string& name, MlpActivation* a) {
  for (MlpActivation x : {MlpActivation::Tanh, MlpActivation::Softplus, MlpActivation::Silu})
    if (name == activationName(x)) {
      *a = x;
      return true;
    }
  return false;
}

// "data": the setting is decided from the data (resolveFitConfig), as when the key is left out.
bool fromData(const nlohmann::json& section, const std::string& key) {
  return !section.contains(key) || (section.at(key).is_string() && section.at(key) == "data");
}

ConfigContext child(const ConfigContext& ctx, const std::string& key) { return {ctx.where + "." + key, ctx.base_dir}; }

const nlohmann::json& section(const nlohmann::json& config, const std::string& key, const ConfigContext& ctx) {
  static const nlohmann::json empty = nlohmann::json::object();
  if (!config.contains(key)) return empty;
  if (!config.at(key).is_object()) fail(ctx, key, "expected a JSON object, got " + jsonForMessage(config.at(key)));
  return config.at(key);
}
}  // namespace

FitConfig parseFitConfig(const nlohmann::json& config, const ConfigContext& ctx) {
  requireKnownKeys(config, {"augmentation", "rbf", "mlp", "geometry"}, ctx);
  FitConfig out;

  const ConfigContext actx = child(ctx, "augmentation");
  const nlohmann::json& a = section(config, "augmentation", ctx);
  requireKnownKeys(a, {"scale", "mirror", "mirror_vertices", "above_surface"}, actx);
  AugmentationSettings& aug = out.augmentation;
  aug.scale = readNumber(a, "scale", 1.0, actx);
  if (aug.scale == 0.0) fail(actx, "scale", "must be non-zero");
  if (!fromData(a, "mirror")) aug.mirror = readBool(a, "mirror", false, actx);
  const std::string vertices = readString(a, "mirror_vertices", "same", actx);
  if (vertices == "same")
    aug.mirror_vertices = MirrorVertices::Same;
  else if (vertices == "reversed")
    aug.mirror_vertices = MirrorVertices::Reversed;
  else
    fail(actx, "mirror_vertices", "expected \"same\" or \"reversed\", got \"" + vertices + "\"");
  const ConfigContext sctx = child(actx, "above_surface");
  const nlohmann::json& above = section(a, "above_surface", actx);
  requireKnownKeys(above, {"heights", "angles"}, sctx);
  if (!fromData(above, "heights")) aug.above_heights = readNumbers(above, "heights", {}, sctx);
  if (aug.above_heights && aug.above_heights->size() > 1000) fail(sctx, "heights", "more than 1000 heights");
  for (double h : aug.above_heights.value_or(std::vector<double>{}))
    if (!(h > 0.0))
      fail(sctx, "heights", "every height must be > 0 (above the surface), got " + jsonForMessage(above.at("heights")));
  if (above.contains("angles") && !(above.at("angles").is_string() && above.at("angles") == "data")) {
    if (!above.at("angles").is_array() || above.at("angles").empty())
      fail(sctx, "angles", "expected \"data\" or a non-empty list of angles (rad), got " + jsonForMessage(above.at("angles")));
    aug.above_angles = readNumbers(above, "angles", {}, sctx);
    if (aug.above_angles.size() > 1000) fail(sctx, "angles", "more than 1000 angles");
  }

  const ConfigContext rctx = child(ctx, "rbf");
  const nlohmann::json& r = section(config, "rbf", ctx);
  requireKnownKeys(r, {"kernel", "epsilon", "scaling", "ridge", "polynomial_tail"}, rctx);
  RbfFitSettings& rbf = out.rbf;
  const std::string kernel = readString(r, "kernel", rbfKernelName(rbf.spec.kernel), rctx);
  if (!parseRbfKernel(kernel, &rbf.spec.kernel))
    fail(rctx, "kernel", "unknown kernel \"" + kernel + "\"; valid kernels: " + rbfKernelNames());
  rbf.spec.epsilon = readNumber(r, "epsilon", rbf.spec.epsilon, rctx);
  if (!(rbf.spec.epsilon > 0.0)) fail(rctx, "epsilon", "must be > 0");
  const std::vector<double> scaling = readNumbers(r, "scaling", {rbf.spec.scaling[0], rbf.spec.scaling[1]}, rctx);
  if (scaling.size() != 2 || !(scaling[0] > 0.0) || !(scaling[1] > 0.0))
    fail(rctx, "scaling", "expected two positive numbers [s_phi, s_beta], got " + jsonForMessage(r.at("scaling")));
  rbf.spec.scaling = Eigen::Vector2d(scaling[0], scaling[1]);
  rbf.ridge = readNumber(r, "ridge", 0.0, rctx, 0.0);
  rbf.polynomial = readBool(r, "polynomial_tail", false, rctx);

  const ConfigContext mctx = child(ctx, "mlp");
  const nlohmann::json& m = section(config, "mlp", ctx);
  requireKnownKeys(m,
                   {"hidden_layers", "width", "activation", "max_epochs", "learning_rate", "final_learning_rate",
                    "batch_size", "validation_fraction", "patience", "seed", "weight_decay", "loss", "relative_floor",
                    "threads", "teacher_grid", "output_envelope", "envelope_width", "teacher_refinement", "lbfgs_iterations", "lbfgs_history", "zero_anchors", "teacher_depth_power"},
                   mctx);
  MlpFitSettings& mlp = out.mlp;
  mlp.hidden_layers = readInteger(m, "hidden_layers", mlp.hidden_layers, mctx, 0, 100);
  mlp.width = readInteger(m, "width", mlp.width, mctx, 1, 100000);
  // The network's weights, for up to 256 vertices: as many as a contact-model file may hold (1e7).
  const double weights = static_cast<double>(mlp.hidden_layers > 0 ? mlp.hidden_layers - 1 : 0) * mlp.width * mlp.width +
                         static_cast<double>(mlp.width) * (3.0 * limits::kMaxVertices + 3.0);
  if (weights > 1e7)
    fail(mctx, "width", "a network of " + std::to_string(mlp.hidden_layers) + " hidden layers of " + std::to_string(mlp.width) +
                            " units has more than the 1e7 weights a contact-model MLP may have");
  const std::string activation = readString(m, "activation", activationName(mlp.activation), mctx);
  if (!parseActivation(activation, &mlp.activation)) {
    std::string lower = activation;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower.find("relu") != std::string::npos)
      fail(mctx, "activation", "\"" + activation + "\" is not allowed: ReLU has a kink at 0 and the solver needs a "
           "contact model that is at least C1; use tanh, softplus or silu");
    fail(mctx, "activation", "unknown activation \"" + activation + "\"; valid activations: tanh, softplus, silu");
  }
  if (m.contains("max_epochs") && m.at("max_epochs").is_number() && m.at("max_epochs").get<double>() < 1)
    fail(mctx, "max_epochs", "must be at least 1 (the number of passes over the training points), got " +
                                 jsonForMessage(m.at("max_epochs")));
  mlp.max_epochs = readInteger(m, "max_epochs", mlp.max_epochs, mctx, 1, 100000000);
  mlp.learning_rate = readNumber(m, "learning_rate", mlp.learning_rate, mctx);
  if (!(mlp.learning_rate > 0.0)) fail(mctx, "learning_rate", "must be > 0");
  mlp.final_learning_rate = readNumber(m, "final_learning_rate", mlp.final_learning_rate, mctx);
  if (!(mlp.final_learning_rate > 0.0)) fail(mctx, "final_learning_rate", "must be > 0");
  mlp.batch_size = readInteger(m, "batch_size", mlp.batch_size, mctx, 0, 1000000000);
  mlp.validation_fraction = readNumber(m, "validation_fraction", mlp.validation_fraction, mctx);
  if (!(mlp.validation_fraction >= 0.0 && mlp.validation_fraction < 1.0))
    fail(mctx, "validation_fraction",
         "must be in [0, 1) (the share of the points held out for early stopping), got " +
             jsonForMessage(m.at("validation_fraction")));
  mlp.patience = readInteger(m, "patience", mlp.patience, mctx, 0, 100000000);
  const double seed = readNumber(m, "seed", mlp.seed, mctx);
  if (!(seed >= 0.0 && seed < 4294967296.0) || seed != std::floor(seed))
    fail(mctx, "seed", "must be an integer in [0, 4294967295], got " + jsonForMessage(m.at("seed")));
  mlp.seed = static_cast<std::uint32_t>(seed);
  mlp.weight_decay = readNumber(m, "weight_decay", mlp.weight_decay, mctx, 0.0);
  const std::string loss = readString(m, "loss", mlpLossName(mlp.loss), mctx);
  if (loss == "relative")
    mlp.loss = MlpLoss::Relative;
  else if (loss == "mse")
    mlp.loss = MlpLoss::Mse;
  else
    fail(mctx, "loss", "expected \"relative\" or \"mse\", got \"" + loss + "\"");
  mlp.relative_floor = readNumber(m, "relative_floor", mlp.relative_floor, mctx);
  if (!(mlp.relative_floor > 0.0)) fail(mctx, "relative_floor", "must be > 0");
  mlp.threads = readInteger(m, "threads", mlp.threads, mctx, 1, 1024);
  const std::vector<double> grid = readNumbers(m, "teacher_grid", {0.0, 0.0}, mctx);
  if (grid.size() != 2 || grid[0] < 0 || grid[1] < 0 || grid[0] != std::floor(grid[0]) ||
      grid[1] != std::floor(grid[1]) || grid[0] * grid[1] > 1e6 || ((grid[0] == 0) != (grid[1] == 0)))
    fail(mctx, "teacher_grid",
         "expected [n_phi, n_beta]: two integers >= 1 with n_phi n_beta <= 1e6 (the RBF teacher's grid), or [0, 0] for none, got " +
             jsonForMessage(m.at("teacher_grid")));
  mlp.teacher_grid = {static_cast<int>(grid[0]), static_cast<int>(grid[1])};
  mlp.teacher_refinement = readNumbers(m, "teacher_refinement", mlp.teacher_refinement, mctx);
  if (mlp.teacher_refinement.size() > 100) fail(mctx, "teacher_refinement", "more than 100 angle offsets");
  for (double offset : mlp.teacher_refinement)
    if (!(offset > 0.0 && offset < 10.0))
      fail(mctx, "teacher_refinement", "expected angle offsets in (0, 10) rad, got " + jsonForMessage(m.at("teacher_refinement")));
  const std::string envelope = readString(m, "output_envelope", mlpOutputEnvelopeName(mlp.output_envelope), mctx);
  if (!parseMlpOutputEnvelope(envelope, &mlp.output_envelope))
    fail(mctx, "output_envelope",
         "expected \"none\" (W = N), \"depth\" (W = (-phi) N, zero at the surface) or \"soft_depth\" "
         "(W = w softplus(-phi/w) N), got \"" + envelope + "\"");
  mlp.envelope_width = readNumber(m, "envelope_width", mlp.envelope_width, mctx);
  if (!(mlp.envelope_width > 0.0 && mlp.envelope_width <= 10.0))
    fail(mctx, "envelope_width", "must be in (0, 10] m (the soft_depth envelope's width w)");

  mlp.lbfgs_iterations = readInteger(m, "lbfgs_iterations", mlp.lbfgs_iterations, mctx, 0, 100000000);
  mlp.lbfgs_history = readInteger(m, "lbfgs_history", mlp.lbfgs_history, mctx, 1, 10000);
  mlp.zero_anchors = readBool(m, "zero_anchors", mlp.zero_anchors, mctx);
  mlp.teacher_depth_power = readNumber(m, "teacher_depth_power", mlp.teacher_depth_power, mctx);
  if (!(mlp.teacher_depth_power >= 1.0 && mlp.teacher_depth_power <= 100.0))
    fail(mctx, "teacher_depth_power", "must be in [1, 100] (1: evenly spaced teacher rows; more: denser near the surface)");
  if (mlp.zero_anchors && mlp.output_envelope == MlpOutputEnvelope::Depth)
    fail(mctx, "zero_anchors", "cannot be combined with output_envelope \"depth\" (the envelope is zero at the surface already)");

  const ConfigContext gctx = child(ctx, "geometry");
  const nlohmann::json& g = section(config, "geometry", ctx);
  requireKnownKeys(g, {"torque_centre", "cutoff", "cutoff_width"}, gctx);
  if (g.contains("torque_centre") && !(g.at("torque_centre").is_string() && g.at("torque_centre") == "data"))
    out.torque_centre = readNumber(g, "torque_centre", 0.0, gctx);
  if (!fromData(g, "cutoff")) out.cutoff = readNumber(g, "cutoff", 0.0, gctx);
  if (!fromData(g, "cutoff_width")) {
    out.cutoff_width = readNumber(g, "cutoff_width", 0.0, gctx);
    if (!(*out.cutoff_width > 0.0))
      fail(gctx, "cutoff_width", "must be > 0 (the wrenches blend to zero over this band)");
  }
  return out;
}

nlohmann::ordered_json fitConfigJson(const FitConfig& c, double torque_centre, const std::string& model) {
  const auto orData = [](const auto& value) {
    return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json("data");
  };
  nlohmann::ordered_json above;
  above["heights"] = orData(c.augmentation.above_heights);
  if (c.augmentation.above_angles.empty())
    above["angles"] = "data";
  else
    above["angles"] = c.augmentation.above_angles;
  nlohmann::ordered_json out;
  out["augmentation"] = {{"scale", c.augmentation.scale},
                         {"mirror", orData(c.augmentation.mirror)},
                         {"mirror_vertices", mirrorVerticesName(c.augmentation.mirror_vertices)},
                         {"above_surface", above}};
  if (model == "mlp") {
    const MlpFitSettings& m = c.mlp;
    out["mlp"] = {{"hidden_layers", m.hidden_layers},
                  {"width", m.width},
                  {"activation", activationName(m.activation)},
                  {"max_epochs", m.max_epochs},
                  {"learning_rate", m.learning_rate},
                  {"final_learning_rate", m.final_learning_rate},
                  {"batch_size", m.batch_size},
                  {"validation_fraction", m.validation_fraction},
                  {"patience", m.patience},
                  {"seed", m.seed},
                  {"weight_decay", m.weight_decay},
                  {"loss", mlpLossName(m.loss)},
                  {"relative_floor", m.relative_floor},
                  {"threads", m.threads},
                  {"teacher_grid", {m.teacher_grid[0], m.teacher_grid[1]}},
                  {"output_envelope", mlpOutputEnvelopeName(m.output_envelope)},
                  {"envelope_width", m.envelope_width},
                  {"teacher_refinement", m.teacher_refinement},
                  {"lbfgs_iterations", m.lbfgs_iterations},
                  {"lbfgs_history", m.lbfgs_history},
                  {"zero_anchors", m.zero_anchors},
                  {"teacher_depth_power", m.teacher_depth_power}};
    if (m.teacher_grid[0] > 0)
      out["rbf"] = {{"kernel", rbfKernelName(c.rbf.spec.kernel)},
                    {"epsilon", c.rbf.spec.epsilon},
                    {"scaling", {c.rbf.spec.scaling[0], c.rbf.spec.scaling[1]}},
                    {"ridge", c.rbf.ridge},
                    {"polynomial_tail", c.rbf.polynomial}};
  } else {
    out["rbf"] = {{"kernel", rbfKernelName(c.rbf.spec.kernel)},
                  {"epsilon", c.rbf.spec.epsilon},
                  {"scaling", {c.rbf.spec.scaling[0], c.rbf.spec.scaling[1]}},
                  {"ridge", c.rbf.ridge},
                  {"polynomial_tail", c.rbf.polynomial}};
  }
  out["geometry"] = {
      {"torque_centre", torque_centre}, {"cutoff", orData(c.cutoff)}, {"cutoff_width", orData(c.cutoff_width)}};
  return out;
}

namespace {
std::string text(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}
std::string text(const std::vector<double>& xs) {
  std::string out = "[";
  for (size_t i = 0; i < xs.size(); ++i) out += (i ? ", " : "") + text(xs[i]);
  return out + "]";
}
}  // namespace

ResolvedFitConfig resolveFitConfig(const FitConfig& config, const ForceDataset& data, const PlanarPoints& grouped,
                                   const std::string& data_name) {
  ResolvedFitConfig out{config, {}};
  FitConfig& c = out.config;
  if (!c.torque_centre) {
    if (!data.torque_centre)
      throw InputError(data_name +
                       ": the dataset has no torque_centre attribute: set geometry.torque_centre (m up "
                       "the leg from the foot point, about which tau_y is taken) in the fit configuration");
    c.torque_centre = *data.torque_centre;
  }
  c.augmentation = resolveAugmentation(grouped, config.augmentation);
  if (!config.augmentation.mirror)
    out.from_data.push_back(
        std::string("augmentation.mirror = ") + (*c.augmentation.mirror ? "true" : "false") +
        (*c.augmentation.mirror ? " (the data's angles lie on one side of beta = 0)"
                                 : " (the data's angles are not all on one side of beta = 0)"));
  if (!config.augmentation.above_heights)
    out.from_data.push_back("augmentation.above_surface.heights = " + text(*c.augmentation.above_heights) +
                            (c.augmentation.above_heights->empty()
                                 ? " (the data has points above the surface)"
                                 : " (the published heights x the data's depth span / 0.07 m)"));
  if (!config.augmentation.above_heights && config.augmentation.above_angles.empty() &&
      !c.augmentation.above_angles.empty())
    out.from_data.push_back("augmentation.above_surface.angles = " + std::to_string(c.augmentation.above_angles.size()) +
                            " from " + text(c.augmentation.above_angles.front()) + " to " +
                            text(c.augmentation.above_angles.back()) + " (the data has more distinct angles)");

  // The highest point that carries a wrench, and the lowest zero-wrench point above it: of the
  // data, of the augmentation, or the surface itself (a foot point above it touches nothing).
  std::optional<double> loaded_top;
  for (int i = 0; i < grouped.pointCount(); ++i)
    if (grouped.values.row(i).cwiseAbs().maxCoeff() > 0.0)
      loaded_top = std::max(loaded_top.value_or(grouped.features(i, 0)), grouped.features(i, 0));
  const double top = loaded_top.value_or(0.0);
  std::optional<double> lowest_zero;
  const auto consider = [&](double phi) {
    if (phi > top && (!lowest_zero || phi < *lowest_zero)) lowest_zero = phi;
  };
  for (int i = 0; i < grouped.pointCount(); ++i) consider(grouped.features(i, 0));
  for (double h : *c.augmentation.above_heights) consider(h);
  consider(0.0);
  const double first_height = scaledPublishedHeights(grouped).front();
  if (!c.cutoff) {
    c.cutoff = lowest_zero.value_or(top + first_height);
    out.from_data.push_back("geometry.cutoff = " + text(*c.cutoff) +
                            (lowest_zero ? " (the lowest zero-wrench point above the data's wrenches)"
                                         : " (the data's top plus the first published height, scaled)"));
  }
  if (!c.cutoff_width) {
    c.cutoff_width = *c.cutoff > top ? *c.cutoff - top : first_height;
    out.from_data.push_back("geometry.cutoff_width = " + text(*c.cutoff_width) +
                            (*c.cutoff > top ? " (from the highest point with a wrench, phi " + text(top) +
                                                   " m, to the cut-off)"
                                             : " (the first published height, scaled)"));
  }
  return out;
}

PlanarGeometry fitGeometry(const FitConfig& resolved) {
  PlanarGeometry g;
  g.torque_centre = resolved.torque_centre.value();
  g.cutoff = resolved.cutoff.value();
  g.cutoff_width = resolved.cutoff_width.value();
  return g;
}

RbfFitOutcome fitRbfToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name) {
  const auto start = std::chrono::steady_clock::now();
  const PlanarPoints grouped = groupPlanarSamples(data, data_name);  // shape errors first
  const ResolvedFitConfig resolved = resolveFitConfig(config, data, grouped, data_name);
  RbfFitOutcome out;
  out.geometry = fitGeometry(resolved.config);

  RbfFitRecord& r = out.record;
  r.points = augment(grouped, resolved.config.augmentation);
  r.fit = fitRbf(r.points, resolved.config.rbf, data_name);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.settings = fitConfigJson(resolved.config, out.geometry.torque_centre);
  r.from_data = resolved.from_data;
  r.data = data_name;
  r.above_surface = checkAboveSurface(RbfFunction(r.fit.parameters), out.geometry, r.points);
  if (auto w = looWarning(r.fit.loo_relative, r.points)) r.warnings.push_back(*w);
  if (auto w = aboveSurfaceWarning(r.above_surface, out.geometry)) r.warnings.push_back(*w);
  return out;
}

}  // namespace nmdp
