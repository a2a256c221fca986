// `nmdp fit --model rbf` on 3-D data (training/spatial_points.hpp): the fit of rbf_fit.hpp (one code
// path for planar and spatial points: solveRbfSystem) giving a SpatialRbfFunction
// (contact_models/spatial_rbf_function.hpp), with the planar fit's report and /fit group.
//
// FIT.json for 3-D data: augmentation.scale, augmentation.above_surface.heights, rbf.kernel,
// rbf.epsilon, rbf.scaling (three numbers [s_phi, s_beta, s_gamma]; default [20, 1, 1]), rbf.ridge,
// rbf.polynomial_tail (1, φ, β, γ), geometry.cutoff and cutoff_width (decided from the data as for
// planar data when left out). Refused with an InputError naming the file and the key: the planar
// mirror (augmentation.mirror true, mirror_vertices "reversed"), augmentation.above_surface.angles
// (the zero-wrench points take every (β, γ) of the data), geometry.torque_centre (the torque is
// about the foot point) and a scaling of two numbers.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/spatial_rbf_function.hpp"
#include "training/fit_config.hpp"
#include "training/rbf_fit.hpp"
#include "training/spatial_points.hpp"

namespace nmdp {

struct SpatialRbfFitRecord {
  nlohmann::ordered_json settings;     // every key with the value used (parses back to the same fit)
  SpatialPoints points;                // the fitted points, augmented
  SpatialRbfParameters parameters;     // centres = the fitted points
  RbfSolution fit;                     // weights, tail, leave-one-point-out error
  std::string data;                    // the data set it came from
  double seconds = 0;                  // wall time of augmentation and fit
  std::vector<std::string> from_data;  // the settings decided from the data
  std::vector<FitWarning> warnings;    // the leave-one-point-out error
};

struct SpatialRbfFitOutcome {
  SpatialRbfFitRecord record;
  SpatialGeometry geometry;
};

// Throws InputError "`config.where`.<key>: ..." for a key 3-D data cannot take (see above).
void requireSpatialFitConfig(const FitConfig& config, const std::string& data_name);

// Group, decide what the configuration leaves to the data, augment, fit, check. Throws InputError
// for bad data (groupSpatialSamples, solveRbfSystem) and bad keys (requireSpatialFitConfig).
SpatialRbfFitOutcome fitSpatialRbfToDataset(const ForceDataset& data, const FitConfig& config,
                                            const std::string& data_name);

// The report of formatRbfFitReport for a spatial fit: the points name (phi, beta, gamma); the
// vertices' errors are the largest of their six entries relative to the largest wrench at the point.
std::string formatSpatialRbfFitReport(const SpatialRbfFitRecord& record);

// Writes the spatial model file (spatial_rbf_function.hpp), which the "rbf" contact model loads, plus
// the /fit group of saveRbfFit (rbf_fit.hpp) with /fit/points P×3 and /fit/values, /fit/loo_error
// P×6K. Atomically (path + ".partial", renamed on success).
void saveSpatialRbfFit(const std::string& path, const SpatialRbfFitOutcome& fit);

}  // namespace nmdp
