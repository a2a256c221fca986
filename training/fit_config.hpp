// The settings of `nmdp fit` (FIT.json). Every key is optional; unknown keys are an InputError
// naming the closest valid key; `nmdp fit --schema` prints every key with its default. Settings
// left out or given as "data" are decided from the data (resolveFitConfig): the published model's
// augmentation. The "rbf" section is used by --model rbf (and by the MLP's optional teacher grid),
// the "mlp" section by --model mlp only (training/mlp/mlp_fit.hpp).
#pragma once
#include <nlohmann/json.hpp>
#include <optional>

#include "contact_models/planar_wrench_model.hpp"
#include "config/fields.hpp"
#include "config/json_params.hpp"
#include "config/schema.hpp"
#include "training/augmentation.hpp"
#include "training/mlp_fit_settings.hpp"
#include "training/rbf_fit.hpp"

namespace nmdp {

struct FitConfig {
  AugmentationSettings augmentation;  // mirror and above_heights: none = decided from the data
  RbfFitSettings rbf;
  MlpFitSettings mlp;
  std::optional<double> torque_centre;  // none: the dataset's
  std::optional<double> cutoff;         // none: decided from the data (resolveFitConfig)
  std::optional<double> cutoff_width;   // none: decided from the data
  std::string where = "the fit configuration";  // what parseFitConfig read, for messages about its keys
};

// The declarations of the "rbf" and "mlp" sections (training/fit_config_fields.cpp).
const Fields<RbfFitSettings>& rbfFitFields();
const Fields<MlpFitSettings>& mlpFitFields();
// The "mlp" section over `mlp`'s values, with the checks across its keys.
void readMlpFitSettings(const nlohmann::json& section, const KeyPath& w, MlpFitSettings& mlp);
// Every key of FIT.json with its type, default, range, unit and use, by section.
nlohmann::ordered_json fitConfigSchema();
// The keys of the sections read by hand ("" for the top level, "augmentation",
// "augmentation.above_surface", "geometry").
const std::vector<KeyDoc>& fitSectionKeys(const std::string& section);

// Throws InputError "ctx.where.key: ..." on an unknown key (with the closest valid one), a wrong
// type or an out-of-range value.
FitConfig parseFitConfig(const nlohmann::json& config, const ConfigContext& ctx);

// Every key with the value in use (torque_centre resolved to the number stored; a setting still
// left to the data as "data"); parses back to the same FitConfig. `model` ("rbf" or "mlp") picks
// the section of the model fitted.
nlohmann::ordered_json fitConfigJson(const FitConfig& config, double torque_centre, const std::string& model = "rbf");

// The configuration with every setting left to the data decided (the published model's
// augmentation, DESIGN.md §9, granular/README.md), and what was decided:
//   * augmentation.mirror: true when the data's angles lie on one side of β = 0 (dataCoversOneSide);
//   * augmentation.above_surface.heights: defaultAboveSurfaceHeights;
//   * geometry.cutoff: the lowest zero-wrench point above the highest point that carries a wrench:
//     a point of the data or of the augmentation, or the surface φ = 0 itself (a foot above it
//     touches nothing), blended (cutoff_width) over the band between the two, so the model is zero
//     above the ground and wherever the data above its wrenches is zero, and every data point keeps
//     its value (σ = 1 at the highest wrench, the points above it are zero); when the data carries
//     a wrench at or above the surface and nothing is zero above it: that height plus the first of
//     scaledPublishedHeights;
//   * geometry.cutoff_width given a cut-off: the band from that highest point to it (the first of
//     scaledPublishedHeights when the cut-off is at or below it);
//   * torque_centre: the dataset's (an InputError naming the data when neither has one).
// `grouped` are the data's points (groupPlanarSamples).
struct ResolvedFitConfig {
  FitConfig config;                     // every optional set
  std::vector<std::string> from_data;   // "augmentation.mirror = true (...)", one per decided key
};
ResolvedFitConfig resolveFitConfig(const FitConfig& config, const ForceDataset& data, const PlanarPoints& grouped,
                                   const std::string& data_name);

// The cut-off (geometry.cutoff, cutoff_width) of `c` where not given, decided as above from the
// grouped points (planar or spatial) and the zero-wrench heights; what was decided is appended.
void resolveCutoff(const PointSetView& grouped, const std::vector<double>& above_heights, FitConfig& c,
                   std::vector<std::string>& from_data);

// The geometry stored in the model file, of a resolved configuration.
PlanarGeometry fitGeometry(const FitConfig& resolved);

// The whole RBF pipeline on a dataset: group by point, decide what the configuration leaves to the
// data, augment, fit, check (fit_warnings.hpp), with the settings and the timing recorded.
// `data_name` names the data in messages and the record. Throws InputError for bad data
// (groupPlanarSamples, fitRbf) and for a torque centre that neither the configuration nor the
// dataset gives.
struct RbfFitOutcome {
  RbfFitRecord record;
  PlanarGeometry geometry;
};
// Throws InputError "`config.where`.rbf.scaling: ..." when the configuration gives the scaling of 3-D
// data (three numbers): the planar fit needs [s_phi, s_beta].
RbfFitOutcome fitRbfToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name);

}  // namespace nmdp
