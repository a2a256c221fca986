// The settings of `nmdp fit` (FIT.json). Every key is optional; unknown keys are an InputError
// naming the closest valid key. Defaults: the published model's augmentation decided from the data
// (mirror when the data covers one side of β = 0, zero-wrench rows above the surface, a cut-off at
// the lowest zero-wrench point above the data's wrenches; resolveFitConfig), scale 1, a thin-plate RBF with the published scaling
// diag(5, 1), no ridge, no tail; for --model mlp a 2-64-64-3K tanh network trained by full-batch
// Adam with early stopping (training/mlp/mlp_fit.hpp). "data" as a value asks for the default. The
// "rbf" section is used by --model rbf (and by the MLP's optional teacher grid), the "mlp" section
// by --model mlp only.
//
//   {
//     "augmentation": {
//       "scale": 1,                   wrenches × scale (finite, non-zero)
//       "mirror": "data",             true: add (φ, −β) copies with F_x, τ_y negated (augmentation.hpp);
//                                     "data": when every β of the data is ≥ 0 (or every β ≤ 0)
//       "mirror_vertices": "same",    or "reversed": vertex j of the copy is vertex (K − j) mod K
//       "above_surface": {            zero-wrench points above the ground
//         "heights": "data",          φ > 0, m; [] = none; "data": the published heights
//                                     [0.01 .. 1.0] × the data's depth span / 0.07 m (none
//                                     when the data has points above the surface)
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
//     "mlp": {                        training/mlp/mlp_fit.hpp
//       "hidden_layers": 2,           L ≥ 0 hidden layers ...
//       "width": 64,                  ... of this many units (≥ 1)
//       "activation": "tanh",         tanh, softplus or silu (never ReLU: the solver needs C¹)
//       "max_epochs": 10000,          ≥ 1 passes over the training points
//       "learning_rate": 1e-2,        Adam's step at the first epoch (> 0) ...
//       "final_learning_rate": 1e-5,  ... decaying exponentially to this at max_epochs (> 0)
//       "batch_size": 0,              points per Adam step; 0 = full batch
//       "validation_fraction": 0.3,   in [0, 1): points held out (per origin, and with or without a
//                                     wrench) for early stopping
//       "patience": 1000,             stop after this many epochs without a better validation
//                                     loss, keeping the best weights; 0 = run all epochs
//       "seed": 1,                    0 ≤ seed < 2³²: initialization, split and batch order
//       "weight_decay": 0,            ≥ 0, Adam's L2 penalty
//       "loss": "relative",           or "mse" (see mlp_fit.hpp)
//       "relative_floor": 0.05,       > 0: the relative loss divides by at least this × the largest
//                                     wrench of all points
//       "threads": 1,                 libtorch threads (≥ 1); 1 makes the result bit-reproducible
//       "teacher_grid": [0, 0],       [n_φ, n_β] ≥ 1: also train on the "rbf" section's RBF through
//                                     the same points, sampled on this grid over the points at or
//                                     below the surface; [0, 0] = no teacher (mlp_fit.hpp)
//       "output_envelope": "none",    or "depth": the model is W = (−φ) N, zero at the surface, or
//                                     "soft_depth": W = w softplus(−φ/w) N, ≈ −φ N below the surface
//                                     (contact_models/mlp/mlp_function.hpp, mlp_fit.hpp)
//       "envelope_width": 0.005,      m in (0, 10]: w of "soft_depth"
//       "teacher_refinement": [],     rad in (0, 10): extra teacher columns at every data angle ±
//                                     each of these (where the thin-plate teacher bends sharply)
//       "lbfgs_iterations": 0,        ≥ 0: full-batch L-BFGS iterations after the Adam epochs
//       "lbfgs_history": 50,          ≥ 1: L-BFGS memory
//       "zero_anchors": false,        true: W exactly zero at the zero-wrench training points
//                                     (mlp_function.hpp; not with output_envelope "depth", whose
//                                     factor is zero at the surface already)
//       "teacher_depth_power": 1      in [1, 100]: teacher rows packed towards the surface
//     },
//     "geometry": {                   stored in the model file (planar_wrench_model.hpp)
//       "torque_centre": "data",      m up the leg; "data" = the dataset's (an error if it has none)
//       "cutoff": "data",             m: zero wrench for φ ≥ cutoff; "data": the lowest zero-wrench
//                                     point above the data's wrenches, or the surface (0 m for
//                                     the sand samples, whose depth-0 samples are zero)
//       "cutoff_width": "data"        m > 0: blending band below the cut-off; "data": from the
//                                     highest point with a wrench to the cut-off (0.01 m)
//     }
//   }
#pragma once
#include <nlohmann/json.hpp>
#include <optional>

#include "contact_models/planar_wrench_model.hpp"
#include "config/json_params.hpp"
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
};

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
RbfFitOutcome fitRbfToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name);

}  // namespace nmdp
