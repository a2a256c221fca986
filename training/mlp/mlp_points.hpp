// The points an MLP is fitted to, of either kind (contact_models/mlp/mlp_function.hpp, MlpWrench):
// planar points (φ, β) with (F_x, F_z, τ_y) per vertex, as the planar pipeline groups and augments
// them (training/augmentation.hpp), or spatial points (φ, β, γ) with (τ_x, τ_y, τ_z, F_x, F_y, F_z)
// per vertex, grouped from a 3-D force dataset (the conventions of
// contact_models/spatial_wrench_model.hpp) and fitted as they are: the planar augmentation (mirror in
// β, zero points above the surface) does not apply, and the spatial model's cut-off zeroes the
// wrench at and above the surface.
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "contact_models/mlp/mlp_names.hpp"
#include "training/augmentation.hpp"
#include "training/force_dataset.hpp"

namespace nmdp {

struct MlpPoints {
  MlpWrench wrench = MlpWrench::Planar;
  Eigen::MatrixXd features;         // P×F, F = 2 (φ, β) or 3 (φ, β, γ)
  Eigen::MatrixXd values;           // P×wK: vertex j in columns wj .. wj + w − 1, w = 3 or 6
  std::vector<PointOrigin> origin;  // P
  int featureCount() const { return mlpFeatureCount(wrench); }
  int wrenchWidth() const { return mlpWrenchWidth(wrench); }
  int pointCount() const { return static_cast<int>(features.rows()); }
  int vertexCount() const { return static_cast<int>(values.cols() / wrenchWidth()); }
};

// The planar points as MLP points (an exact copy).
MlpPoints mlpPoints(const PlanarPoints& points);
// Back to planar points (an exact copy; points.wrench must be Planar).
PlanarPoints planarPoints(const MlpPoints& points);

// Whether a force dataset holds 3-D samples (training/spatial_points.hpp: isSpatialDataset).
bool isSpatialMlpDataset(const ForceDataset& data);

// The 3-D samples grouped by feature point, as the RBF fit groups them (groupSpatialSamples: the
// features "phi, beta, gamma", the 6 wrench columns in order, every vertex at every point; an
// InputError naming the dataset otherwise), as MLP points.
MlpPoints groupSpatialMlpSamples(const ForceDataset& data, const std::string& where);

// At each point the largest |value| entry (the largest of all at zero-wrench points), as pointScales.
Eigen::VectorXd mlpPointScales(const MlpPoints& points);
// P×K: for each point and vertex the largest |error| over the vertex's w entries divided by the
// point's scale (by 1 where it is 0), as relativeVertexErrors for w = 3.
Eigen::MatrixXd mlpRelativeVertexErrors(const Eigen::MatrixXd& error, const Eigen::VectorXd& scale, int w);

}  // namespace nmdp
