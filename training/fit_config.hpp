// The settings of `nmdp fit` (FIT.json). Every key is optional; unknown keys are an InputError
// naming the closest valid key. Defaults: no augmentation, a thin-plate RBF with the published
// scaling diag(5, 1), no ridge, no tail, the published model's cut-off.
//
//   {
//     "augmentation": {
//       "scale": 1,                   wrenches × scale (finite, non-zero)
//       "mirror": false,              add (φ, −β) copies with F_x, τ_y negated (augmentation.hpp)
//       "mirror_vertices": "same",    or "reversed": vertex j of the copy is vertex (K − j) mod K
//       "above_surface": {            zero-wrench points above the ground
//         "heights": [],              φ > 0, m
//         "angles": "data"            or a list of β (rad); "data" = every β after mirroring
//       }
//     },
//     "rbf": {
//       "kernel": "thin_plate",       contact_models/rbf_function.hpp: thin_plate, gaussian, ...
//       "epsilon": 1,                 shape parameter (gaussian, multiquadrics) > 0
//       "scaling": [5, 1],            S = diag(s_φ, s_β) > 0
//       "ridge": 0,                   λ ≥ 0 on the kernel matrix's diagonal (0 = interpolation)
//       "polynomial_tail": false      the linear tail a + b φ + c β
//     },
//     "geometry": {                   stored in the model file (planar_wrench_model.hpp)
//       "torque_centre": "data",      m up the leg; "data" = the dataset's (an error if it has none)
//       "cutoff": 0.1,                m: zero wrench for φ ≥ cutoff
//       "cutoff_width": 0.02          m > 0: blending band below the cut-off
//     }
//   }
#pragma once
#include <nlohmann/json.hpp>
#include <optional>

#include "contact_models/planar_wrench_model.hpp"
#include "io/json_params.hpp"
#include "training/augmentation.hpp"
#include "training/rbf_fit.hpp"

namespace nmdp {

struct FitConfig {
  AugmentationSettings augmentation;
  RbfFitSettings rbf;
  std::optional<double> torque_centre;  // none: the dataset's
  double cutoff = 0.1;
  double cutoff_width = 0.02;
};

// Throws InputError "ctx.where.key: ..." on an unknown key (with the closest valid one), a wrong
// type or an out-of-range value.
FitConfig parseFitConfig(const nlohmann::json& config, const ConfigContext& ctx);

// Every key with the value in use (torque_centre resolved to the number stored); parses back to
// the same FitConfig.
nlohmann::ordered_json fitConfigJson(const FitConfig& config, double torque_centre);

// The whole RBF pipeline on a dataset: group by point, augment, fit, with the settings and the
// timing recorded. `data_name` names the data in messages and the record. Throws InputError for
// bad data (groupPlanarSamples, fitRbf) and for a torque centre that neither the configuration
// nor the dataset gives.
struct RbfFitOutcome {
  RbfFitRecord record;
  PlanarGeometry geometry;
};
RbfFitOutcome fitRbfToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name);

}  // namespace nmdp
