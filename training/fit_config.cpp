#include "training/fit_config.hpp"

#include <chrono>

#include "io/input_error.hpp"

namespace nmdp {

namespace {
[[noreturn]] void fail(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}

ConfigContext child(const ConfigContext& ctx, const std::string& key) { return {ctx.where + "." + key, ctx.base_dir}; }

const nlohmann::json& section(const nlohmann::json& config, const std::string& key, const ConfigContext& ctx) {
  static const nlohmann::json empty = nlohmann::json::object();
  if (!config.contains(key)) return empty;
  if (!config.at(key).is_object()) fail(ctx, key, "expected a JSON object, got " + config.at(key).dump());
  return config.at(key);
}
}  // namespace

FitConfig parseFitConfig(const nlohmann::json& config, const ConfigContext& ctx) {
  requireKnownKeys(config, {"augmentation", "rbf", "geometry"}, ctx);
  FitConfig out;

  const ConfigContext actx = child(ctx, "augmentation");
  const nlohmann::json& a = section(config, "augmentation", ctx);
  requireKnownKeys(a, {"scale", "mirror", "mirror_vertices", "above_surface"}, actx);
  AugmentationSettings& aug = out.augmentation;
  aug.scale = readNumber(a, "scale", 1.0, actx);
  if (aug.scale == 0.0) fail(actx, "scale", "must be non-zero");
  aug.mirror = readBool(a, "mirror", false, actx);
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
  aug.above_heights = readNumbers(above, "heights", {}, sctx);
  for (double h : aug.above_heights)
    if (!(h > 0.0))
      fail(sctx, "heights", "every height must be > 0 (above the surface), got " + above.at("heights").dump());
  if (above.contains("angles") && !(above.at("angles").is_string() && above.at("angles") == "data")) {
    if (!above.at("angles").is_array() || above.at("angles").empty())
      fail(sctx, "angles", "expected \"data\" or a non-empty list of angles (rad), got " + above.at("angles").dump());
    aug.above_angles = readNumbers(above, "angles", {}, sctx);
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
    fail(rctx, "scaling", "expected two positive numbers [s_phi, s_beta], got " + r.at("scaling").dump());
  rbf.spec.scaling = Eigen::Vector2d(scaling[0], scaling[1]);
  rbf.ridge = readNumber(r, "ridge", 0.0, rctx, 0.0);
  rbf.polynomial = readBool(r, "polynomial_tail", false, rctx);

  const ConfigContext gctx = child(ctx, "geometry");
  const nlohmann::json& g = section(config, "geometry", ctx);
  requireKnownKeys(g, {"torque_centre", "cutoff", "cutoff_width"}, gctx);
  if (g.contains("torque_centre") && !(g.at("torque_centre").is_string() && g.at("torque_centre") == "data"))
    out.torque_centre = readNumber(g, "torque_centre", 0.0, gctx);
  out.cutoff = readNumber(g, "cutoff", out.cutoff, gctx);
  out.cutoff_width = readNumber(g, "cutoff_width", out.cutoff_width, gctx);
  if (!(out.cutoff_width > 0.0)) fail(gctx, "cutoff_width", "must be > 0 (the wrenches blend to zero over this band)");
  return out;
}

nlohmann::ordered_json fitConfigJson(const FitConfig& c, double torque_centre) {
  nlohmann::ordered_json above;
  above["heights"] = c.augmentation.above_heights;
  if (c.augmentation.above_angles.empty())
    above["angles"] = "data";
  else
    above["angles"] = c.augmentation.above_angles;
  nlohmann::ordered_json out;
  out["augmentation"] = {{"scale", c.augmentation.scale},
                         {"mirror", c.augmentation.mirror},
                         {"mirror_vertices", mirrorVerticesName(c.augmentation.mirror_vertices)},
                         {"above_surface", above}};
  out["rbf"] = {{"kernel", rbfKernelName(c.rbf.spec.kernel)},
                {"epsilon", c.rbf.spec.epsilon},
                {"scaling", {c.rbf.spec.scaling[0], c.rbf.spec.scaling[1]}},
                {"ridge", c.rbf.ridge},
                {"polynomial_tail", c.rbf.polynomial}};
  out["geometry"] = {{"torque_centre", torque_centre}, {"cutoff", c.cutoff}, {"cutoff_width", c.cutoff_width}};
  return out;
}

RbfFitOutcome fitRbfToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name) {
  const auto start = std::chrono::steady_clock::now();
  const PlanarPoints grouped = groupPlanarSamples(data, data_name);  // shape errors first
  RbfFitOutcome out;
  if (config.torque_centre)
    out.geometry.torque_centre = *config.torque_centre;
  else if (data.torque_centre)
    out.geometry.torque_centre = *data.torque_centre;
  else
    throw InputError(data_name +
                     ": the dataset has no torque_centre attribute: set geometry.torque_centre (m up "
                     "the leg from the foot point, about which tau_y is taken) in the fit configuration");
  out.geometry.cutoff = config.cutoff;
  out.geometry.cutoff_width = config.cutoff_width;

  RbfFitRecord& r = out.record;
  r.points = augment(grouped, config.augmentation);
  r.fit = fitRbf(r.points, config.rbf, data_name);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.settings = fitConfigJson(config, out.geometry.torque_centre);
  r.data = data_name;
  return out;
}

}  // namespace nmdp
