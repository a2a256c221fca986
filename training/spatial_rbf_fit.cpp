#include "training/spatial_rbf_fit.hpp"

#include <chrono>
#include <sstream>

#include "common/input_error.hpp"
#include "training/fit_report.hpp"

namespace nmdp {

namespace {
std::string text(const std::vector<double>& xs) {
  std::ostringstream s;
  s << "[";
  for (size_t i = 0; i < xs.size(); ++i) s << (i ? ", " : "") << xs[i];
  s << "]";
  return s.str();
}

// The settings used, in FIT.json's layout (parses back to the same fit).
nlohmann::ordered_json spatialSettingsJson(const FitConfig& c) {
  nlohmann::ordered_json out;
  out["augmentation"] = {{"scale", c.augmentation.scale},
                         {"mirror", false},
                         {"above_surface", {{"heights", *c.augmentation.above_heights}, {"angles", "data"}}}};
  out["rbf"] = rbfFitFields().dump<nlohmann::ordered_json>(c.rbf);
  out["geometry"] = {{"cutoff", *c.cutoff}, {"cutoff_width", *c.cutoff_width}};
  return out;
}
}  // namespace

void requireSpatialFitConfig(const FitConfig& config, const std::string& data_name) {
  const std::string data = " (" + data_name + " is 3-D data: phi, beta, gamma)";
  if (config.torque_centre)
    throw InputError(config.where + ".geometry.torque_centre: 3-D models take the torque about the foot point" +
                     data + "; remove the key");
  if (config.augmentation.mirror.value_or(false) || config.augmentation.mirror_vertices != MirrorVertices::Same)
    throw InputError(config.where + ".augmentation." +
                     (config.augmentation.mirror.value_or(false) ? "mirror" : "mirror_vertices") +
                     ": the mirror copies planar data across beta = 0; 3-D data is not mirrored" + data +
                     ": remove the key");
  if (!config.augmentation.above_angles.empty())
    throw InputError(config.where + ".augmentation.above_surface.angles: the zero-wrench points of 3-D data take "
                     "every (beta, gamma) of the data" + data + "; remove the key");
  if (config.rbf.scaling_given == 2)
    throw InputError(config.where + ".rbf.scaling: 3-D data needs three numbers [s_phi, s_beta, s_gamma], got two" +
                     data);
}

SpatialRbfFitOutcome fitSpatialRbfToDataset(const ForceDataset& data, const FitConfig& config,
                                            const std::string& data_name) {
  const auto start = std::chrono::steady_clock::now();
  const SpatialPoints grouped = groupSpatialSamples(data, data_name);  // shape errors first
  requireSpatialFitConfig(config, data_name);

  FitConfig c = config;
  std::vector<std::string> from_data;
  c.augmentation.mirror = false;
  c.rbf.scaling_given = 3;  // the settings record the three numbers used
  if (!c.augmentation.above_heights) {
    c.augmentation.above_heights = grouped.pointCount() > 0 && grouped.features.col(0).maxCoeff() > 0.0
                                       ? std::vector<double>{}
                                       : scaledPublishedHeights(grouped.features.col(0));
    from_data.push_back("augmentation.above_surface.heights = " + text(*c.augmentation.above_heights) +
                        (c.augmentation.above_heights->empty()
                             ? " (the data has points above the surface)"
                             : " (the published heights x the data's depth span / 0.07 m)"));
  }
  resolveCutoff(viewOf(grouped), *c.augmentation.above_heights, c, from_data);

  SpatialRbfFitOutcome out;
  out.geometry.cutoff = *c.cutoff;
  out.geometry.cutoff_width = *c.cutoff_width;
  SpatialRbfFitRecord& r = out.record;
  r.points = augmentSpatial(grouped, c.augmentation.scale, *c.augmentation.above_heights);
  const RbfFitSettings& s = c.rbf;
  r.fit = solveRbfSystem(viewOf(r.points), s.spec.kernel, s.spatial_scaling, s.spec.epsilon, s.ridge, s.polynomial,
                         data_name);
  r.parameters.kernel = s.spec.kernel;
  r.parameters.scaling = s.spatial_scaling;
  r.parameters.epsilon = s.spec.epsilon;
  r.parameters.centres = r.points.features;
  r.parameters.weights = r.fit.weights;
  r.parameters.polynomial = r.fit.polynomial;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.settings = spatialSettingsJson(c);
  r.from_data = std::move(from_data);
  r.data = data_name;
  if (auto w = looWarning(r.fit.loo_relative, viewOf(r.points))) r.warnings.push_back(*w);
  return out;
}

std::string formatSpatialRbfFitReport(const SpatialRbfFitRecord& r) {
  std::string s = fitReportOpening("3-D RBF", r.data, r.settings, r.from_data);
  s += formatRbfLooReport(viewOf(r.points), r.fit, r.seconds);
  const double cutoff = r.settings.at("geometry").at("cutoff").get<double>();
  if (cutoff <= 0.0)
    s += formatAboveSurface(AboveSurfaceCheck{});
  else
    s += "above the surface: not checked for 3-D models (the cut-off is " + std::to_string(cutoff) +
         " m above the surface)\n";
  return s + formatFitWarnings(r.warnings);
}

}  // namespace nmdp
