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
  requireKnownKeys(config, keysOf(fitSectionKeys("")), ctx);
  FitConfig out;
  out.where = ctx.where;

  const ConfigContext actx = child(ctx, "augmentation");
  const nlohmann::json& a = section(config, "augmentation", ctx);
  requireKnownKeys(a, keysOf(fitSectionKeys("augmentation")), actx);
  AugmentationSettings& aug = out.augmentation;
  aug.scale = readNumber(a, "scale", 1.0, actx);
  if (aug.scale == 0.0) fail(actx, "scale", "must be non-zero");
  if (!fromData(a, "mirror")) aug.mirror = readBool(a, "mirror", false, actx);
  const std::string vertices = readString(a, "mirror_vertices", mirrorVerticesName(aug.mirror_vertices), actx);
  if (const auto found = enumFromName(kMirrorVertices, vertices))
    aug.mirror_vertices = *found;
  else
    fail(actx, "mirror_vertices", "expected \"same\" or \"reversed\", got \"" + vertices + "\"");
  const ConfigContext sctx = child(actx, "above_surface");
  const nlohmann::json& above = section(a, "above_surface", actx);
  requireKnownKeys(above, keysOf(fitSectionKeys("augmentation.above_surface")), sctx);
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

  const nlohmann::json& r = section(config, "rbf", ctx);
  rbfFitFields().readInto(r, out.rbf, KeyPath{ctx.where + ".rbf", "", "."});
  const nlohmann::json& m = section(config, "mlp", ctx);
  readMlpFitSettings(m, KeyPath{ctx.where + ".mlp", "", "."}, out.mlp);

  const ConfigContext gctx = child(ctx, "geometry");
  const nlohmann::json& g = section(config, "geometry", ctx);
  requireKnownKeys(g, keysOf(fitSectionKeys("geometry")), gctx);
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
    out["mlp"] = mlpFitFields().dump<nlohmann::ordered_json>(c.mlp);
    if (c.mlp.teacher_grid[0] > 0) out["rbf"] = rbfFitFields().dump<nlohmann::ordered_json>(c.rbf);
  } else {
    out["rbf"] = rbfFitFields().dump<nlohmann::ordered_json>(c.rbf);
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

  resolveCutoff(viewOf(grouped), *c.augmentation.above_heights, c, out.from_data);
  return out;
}

void resolveCutoff(const PointSetView& grouped, const std::vector<double>& above_heights, FitConfig& c,
                   std::vector<std::string>& from_data) {
  // The highest point that carries a wrench, and the lowest zero-wrench point above it: of the
  // data, of the augmentation, or the surface itself (a foot point above it touches nothing).
  std::optional<double> loaded_top;
  for (Eigen::Index i = 0; i < grouped.pointCount(); ++i)
    if (grouped.values.row(i).cwiseAbs().maxCoeff() > 0.0)
      loaded_top = std::max(loaded_top.value_or(grouped.features(i, 0)), grouped.features(i, 0));
  const double top = loaded_top.value_or(0.0);
  std::optional<double> lowest_zero;
  const auto consider = [&](double phi) {
    if (phi > top && (!lowest_zero || phi < *lowest_zero)) lowest_zero = phi;
  };
  for (Eigen::Index i = 0; i < grouped.pointCount(); ++i) consider(grouped.features(i, 0));
  for (double h : above_heights) consider(h);
  consider(0.0);
  const double first_height = scaledPublishedHeights(grouped.features.col(0)).front();
  if (!c.cutoff) {
    c.cutoff = lowest_zero.value_or(top + first_height);
    from_data.push_back("geometry.cutoff = " + text(*c.cutoff) +
                            (lowest_zero ? " (the lowest zero-wrench point above the data's wrenches)"
                                         : " (the data's top plus the first published height, scaled)"));
  }
  if (!c.cutoff_width) {
    c.cutoff_width = *c.cutoff > top ? *c.cutoff - top : first_height;
    from_data.push_back("geometry.cutoff_width = " + text(*c.cutoff_width) +
                            (*c.cutoff > top ? " (from the highest point with a wrench, phi " + text(top) +
                                                   " m, to the cut-off)"
                                             : " (the first published height, scaled)"));
  }
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
  if (config.rbf.scaling_given == 3)
    throw InputError(config.where + ".rbf.scaling: three numbers are the scaling of 3-D data (phi, beta, gamma); " +
                     data_name + " is planar (phi, beta): give [s_phi, s_beta]");
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
