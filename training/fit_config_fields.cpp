// The declarations of the "rbf" and "mlp" sections of FIT.json: each key once, with its default
// (from the settings structs), range, unit and use; they drive parsing, the dump and --schema.
#include <algorithm>
#include <cctype>
#include <cmath>

#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "config/schema.hpp"
#include "training/fit_config.hpp"

namespace nmdp {

namespace {

using json = nlohmann::json;

Field<RbfFitSettings> scalingField() {
  Field<RbfFitSettings> f = Fields<RbfFitSettings>::make("scaling", "[number, number(, number)]", "(0, inf)", "",
                                     "S = diag(s_phi, s_beta) of the kernel's distance; diag(s_phi, s_beta, s_gamma) for 3-D data");
  f.value = [](const RbfFitSettings& s) {
    if (s.scaling_given == 3) return json::array({s.spatial_scaling[0], s.spatial_scaling[1], s.spatial_scaling[2]});
    return json::array({s.spec.scaling[0], s.spec.scaling[1]});
  };
  f.read = [](const json& object, RbfFitSettings& s, const KeyPath& w) {
    if (!object.contains("scaling")) return;
    const json& v = object.at("scaling");
    const std::vector<double> scaling = readNumbers(object, "scaling", {}, ConfigContext{w.str(), ""});
    const bool positive = std::all_of(scaling.begin(), scaling.end(), [](double x) { return x > 0.0; });
    if ((scaling.size() != 2 && scaling.size() != 3) || !positive)
      (w / "scaling").fail("expected two positive numbers [s_phi, s_beta] (planar data) or three [s_phi, s_beta, "
                           "s_gamma] (3-D data), got " + jsonForMessage(v));
    s.scaling_given = static_cast<int>(scaling.size());
    if (scaling.size() == 2)
      s.spec.scaling = Eigen::Vector2d(scaling[0], scaling[1]);
    else
      s.spatial_scaling = Eigen::Vector3d(scaling[0], scaling[1], scaling[2]);
  };
  return f;
}

Field<RbfFitSettings> kernelField() {
  Field<RbfFitSettings> f = Fields<RbfFitSettings>::make("kernel", "string", join(namesOf(kRbfKernels), " | "), "",
                                                         "the radial basis function (contact_models/rbf_function.hpp)");
  f.value = [](const RbfFitSettings& s) { return json(nameOf(kRbfKernels, s.spec.kernel)); };
  f.read = [](const json& object, RbfFitSettings& s, const KeyPath& w) {
    const std::string kernel = read::string(object, "kernel", nameOf(kRbfKernels, s.spec.kernel), w);
    const auto found = enumFromName(kRbfKernels, kernel);
    if (!found) (w / "kernel").fail("unknown kernel \"" + kernel + "\"; valid kernels: " + rbfKernelNames());
    s.spec.kernel = *found;
  };
  return f;
}

Fields<RbfFitSettings> declareRbfFields() {
  using S = RbfFitSettings;
  Fields<S> f;
  f.custom(kernelField())
      .number("epsilon", [](S& s) -> auto& { return s.spec.epsilon; }, above(0), kNoHigh, "",
              "shape parameter of gaussian and the multiquadrics")
      .custom(scalingField())
      .outOfRangeMessages()
      .number("ridge", &S::ridge, atLeast(0), kNoHigh, "", "lambda on the kernel matrix's diagonal (0: interpolation)")
      .boolean("polynomial_tail", &S::polynomial, "add the linear tail a + b phi + c beta");
  return f;
}

Field<MlpFitSettings> activationField() {
  Field<MlpFitSettings> f = Fields<MlpFitSettings>::make("activation", "string", join(namesOf(kMlpActivations), " | "), "",
                                     "hidden units' activation (never ReLU: the solver needs a C1 model)");
  f.value = [](const MlpFitSettings& s) { return json(nameOf(kMlpActivations, s.activation)); };
  f.read = [](const json& object, MlpFitSettings& s, const KeyPath& w) {
    const std::string activation = read::string(object, "activation", nameOf(kMlpActivations, s.activation), w);
    if (const auto found = enumFromName(kMlpActivations, activation)) {
      s.activation = *found;
      return;
    }
    std::string lower = activation;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower.find("relu") != std::string::npos)
      (w / "activation").fail("\"" + activation + "\" is not allowed: ReLU has a kink at 0 and the solver needs a "
                              "contact model that is at least C1; use tanh, softplus or silu");
    (w / "activation").fail("unknown activation \"" + activation + "\"; valid activations: tanh, softplus, silu");
  };
  return f;
}

Field<MlpFitSettings> seedField() {
  Field<MlpFitSettings> f = Fields<MlpFitSettings>::make("seed", "integer", "[0, 4294967295]", "",
                                     "initialization, split and batch order");
  f.value = [](const MlpFitSettings& s) { return json(s.seed); };
  f.read = [](const json& object, MlpFitSettings& s, const KeyPath& w) {
    const double seed = read::number(object, "seed", s.seed, w, kNoLow, kNoHigh);
    if (!(seed >= 0.0 && seed < 4294967296.0) || seed != std::floor(seed))
      (w / "seed").fail("must be an integer in [0, 4294967295], got " + jsonForMessage(object.at("seed")));
    s.seed = static_cast<std::uint32_t>(seed);
  };
  return f;
}

Field<MlpFitSettings> teacherGridField() {
  Field<MlpFitSettings> f = Fields<MlpFitSettings>::make("teacher_grid", "[integer, integer]", "", "",
                                     "[n_phi, n_beta] samples of the rbf section's RBF added as teacher rows; [0, 0]: no teacher");
  f.value = [](const MlpFitSettings& s) { return json::array({s.teacher_grid[0], s.teacher_grid[1]}); };
  f.read = [](const json& object, MlpFitSettings& s, const KeyPath& w) {
    const std::vector<double> grid = readNumbers(object, "teacher_grid", {0.0, 0.0}, ConfigContext{w.str(), ""});
    if (grid.size() != 2 || grid[0] < 0 || grid[1] < 0 || grid[0] != std::floor(grid[0]) ||
        grid[1] != std::floor(grid[1]) || grid[0] * grid[1] > 1e6 || ((grid[0] == 0) != (grid[1] == 0)))
      (w / "teacher_grid").fail("expected [n_phi, n_beta]: two integers >= 1 with n_phi n_beta <= 1e6 (the RBF teacher's grid), or [0, 0] for none, got " +
                                jsonForMessage(object.at("teacher_grid")));
    s.teacher_grid = {static_cast<int>(grid[0]), static_cast<int>(grid[1])};
  };
  return f;
}

Field<MlpFitSettings> teacherRefinementField() {
  Field<MlpFitSettings> f = Fields<MlpFitSettings>::make("teacher_refinement", "[number]", "(0, 10)", "rad",
                                     "extra teacher columns at every data angle plus and minus each of these");
  f.value = [](const MlpFitSettings& s) { return json(s.teacher_refinement); };
  f.read = [](const json& object, MlpFitSettings& s, const KeyPath& w) {
    s.teacher_refinement = readNumbers(object, "teacher_refinement", s.teacher_refinement, ConfigContext{w.str(), ""});
    if (s.teacher_refinement.size() > 100) (w / "teacher_refinement").fail("more than 100 angle offsets");
    for (double offset : s.teacher_refinement)
      if (!(offset > 0.0 && offset < 10.0))
        (w / "teacher_refinement").fail("expected angle offsets in (0, 10) rad, got " + jsonForMessage(object.at("teacher_refinement")));
  };
  return f;
}

Fields<MlpFitSettings> declareMlpFields() {
  using S = MlpFitSettings;
  Fields<S> f;
  f.integer("hidden_layers", &S::hidden_layers, 0, 100, "", "hidden layers of the network")
      .integer("width", &S::width, 1, 100000, "", "units of each hidden layer")
      .custom(activationField())
      .integer("max_epochs", &S::max_epochs, 1, 100000000, "", "passes over the training points",
               "an integer of at least 1 (the number of passes over the training points) and at most 100000000")
      .number("learning_rate", &S::learning_rate, above(0), kNoHigh, "", "Adam's step at the first epoch")
      .number("final_learning_rate", &S::final_learning_rate, above(0), kNoHigh, "",
              "the step it decays to exponentially at max_epochs")
      .integer("batch_size", &S::batch_size, 0, read::kNoIntegerLimit, "", "points per Adam step; 0: full batch")
      .number("validation_fraction", &S::validation_fraction, atLeast(0), below(1), "",
              "share of the points held out (per origin, with or without a wrench) for early stopping")
      .integer("patience", &S::patience, 0, 100000000, "",
               "stop after this many epochs without a better validation loss; 0: run every epoch")
      .custom(seedField())
      .number("weight_decay", &S::weight_decay, atLeast(0), kNoHigh, "", "Adam's L2 penalty")
      .choice("loss", &S::loss, kMlpLosses, "loss", "relative: divided by each point's wrench scale; mse: plain",
              "expected \"relative\" or \"mse\"")
      .number("relative_floor", &S::relative_floor, above(0), kNoHigh, "",
              "the relative loss divides by at least this times the largest wrench")
      .integer("threads", &S::threads, 1, 1024, "", "libtorch threads; 1 makes the result bit-reproducible")
      .custom(teacherGridField())
      .choice("output_envelope", &S::output_envelope, kMlpOutputEnvelopes, "envelope",
              "what multiplies the network's output (contact_models/mlp/mlp_function.hpp)",
              "expected \"none\" (W = N), \"depth\" (W = (-phi) N, zero at the surface) or \"soft_depth\" "
              "(W = w softplus(-phi/w) N)")
      .number("envelope_width", &S::envelope_width, above(0), atMost(10), "m", "w of soft_depth")
      .custom(teacherRefinementField())
      .integer("lbfgs_iterations", &S::lbfgs_iterations, 0, 100000000, "", "full-batch L-BFGS iterations after Adam")
      .integer("lbfgs_history", &S::lbfgs_history, 1, 10000, "", "L-BFGS memory")
      .boolean("zero_anchors", &S::zero_anchors, "W exactly zero at the zero-wrench training points")
      .number("teacher_depth_power", &S::teacher_depth_power, atLeast(1), atMost(100), "",
              "teacher rows packed towards the surface (1: evenly spaced)");
  return f;
}

}  // namespace

const std::vector<KeyDoc>& fitSectionKeys(const std::string& section) {
  static const std::vector<KeyDoc> top = {
      {"augmentation", "object", nullptr, "", "", "copies and zero-wrench rows added to the data"},
      {"rbf", "object", nullptr, "", "", "the RBF fit (--model rbf, and the MLP's teacher)"},
      {"mlp", "object", nullptr, "", "", "the MLP fit (--model mlp)"},
      {"geometry", "object", nullptr, "", "", "stored in the model file (planar_wrench_model.hpp)"}};
  static const std::vector<KeyDoc> augmentation = {
      {"scale", "number", 1.0, "non-zero", "", "wrenches times scale"},
      {"mirror", "boolean | \"data\"", "data", "", "",
       "add (phi, -beta) copies with F_x, tau_y negated; data: when the data's angles lie on one side of 0"},
      {"mirror_vertices", "string", "same", "same | reversed", "", "reversed: vertex j of a copy is vertex (K - j) mod K"},
      {"above_surface", "object", nullptr, "", "", "zero-wrench points above the ground"}};
  static const std::vector<KeyDoc> above_surface = {
      {"heights", "[number] | \"data\"", "data", "(0, inf)", "m",
       "phi of the zero-wrench rows; data: the published heights scaled to the data's depth span"},
      {"angles", "[number] | \"data\"", "data", "", "rad", "beta of the zero-wrench rows; data: every beta after mirroring"}};
  static const std::vector<KeyDoc> geometry = {
      {"torque_centre", "number | \"data\"", "data", "", "m", "up the leg from the foot point; data: the dataset's"},
      {"cutoff", "number | \"data\"", "data", "", "m", "zero wrench for phi >= cutoff; data: the lowest zero-wrench point above the wrenches"},
      {"cutoff_width", "number | \"data\"", "data", "(0, inf)", "m", "blending band below the cut-off; data: from the highest wrench to it"}};
  static const std::vector<KeyDoc> none;
  if (section.empty()) return top;
  if (section == "augmentation") return augmentation;
  if (section == "augmentation.above_surface") return above_surface;
  if (section == "geometry") return geometry;
  return none;
}

nlohmann::ordered_json fitConfigSchema() {
  nlohmann::ordered_json out;
  out[""] = schemaRows(fitSectionKeys(""));
  out["augmentation"] = schemaRows(fitSectionKeys("augmentation"));
  out["augmentation.above_surface"] = schemaRows(fitSectionKeys("augmentation.above_surface"));
  out["rbf"] = rbfFitFields().schema();
  out["mlp"] = mlpFitFields().schema();
  out["geometry"] = schemaRows(fitSectionKeys("geometry"));
  return out;
}

const Fields<RbfFitSettings>& rbfFitFields() {
  static const Fields<RbfFitSettings> fields = declareRbfFields();
  return fields;
}

const Fields<MlpFitSettings>& mlpFitFields() {
  static const Fields<MlpFitSettings> fields = declareMlpFields();
  return fields;
}

void readMlpFitSettings(const json& m, const KeyPath& w, MlpFitSettings& mlp) {
  mlpFitFields().readInto(m, mlp, w);
  // The network's weights, for up to 256 vertices: as many as a contact-model file may hold (1e7).
  const double weights = static_cast<double>(mlp.hidden_layers > 0 ? mlp.hidden_layers - 1 : 0) * mlp.width * mlp.width +
                         static_cast<double>(mlp.width) * (3.0 * limits::kMaxVertices + 3.0);
  if (weights > 1e7)
    (w / "width").fail("a network of " + std::to_string(mlp.hidden_layers) + " hidden layers of " + std::to_string(mlp.width) +
                       " units has more than the 1e7 weights a contact-model MLP may have");
  if (mlp.zero_anchors && mlp.output_envelope == MlpOutputEnvelope::Depth)
    (w / "zero_anchors").fail("cannot be combined with output_envelope \"depth\" (the envelope is zero at the surface already)");
}

}  // namespace nmdp
