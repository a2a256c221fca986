// From a 3-D force dataset to the points a spatial wrench-space fit interpolates (the conventions
// of contact_models/spatial_wrench_model.hpp): features (φ, β, γ) in (m, rad, rad), at each point
// K vertices of six entries (τ_x, τ_y, τ_z, F_x, F_y, F_z) in (N m, N m, N m, N, N, N), the torque
// about the foot point. The augmentation of the planar fit (augmentation.hpp) minus the mirror:
//   * scale          every wrench times a factor;
//   * above_surface  zero-wrench points at heights φ > 0 for every (β, γ) of the data, so that the
//                    fitted wrench fades above the ground.
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "training/augmentation.hpp"
#include "training/force_dataset.hpp"

namespace nmdp {

struct SpatialPoints {
  Eigen::MatrixX3d features;        // P×3, rows (φ, β, γ)
  Eigen::MatrixXd values;           // P×6K, vertex j in columns 6j .. 6j + 5
  std::vector<PointOrigin> origin;  // P
  int pointCount() const { return static_cast<int>(features.rows()); }
  int vertexCount() const { return static_cast<int>(values.cols() / 6); }
};
inline PointSetView viewOf(const SpatialPoints& p) { return {p.features, p.values, p.origin, 6}; }

// Whether the dataset is one for the spatial models: it has 3 feature columns (any other count is
// planar data or an error of the planar fit).
bool isSpatialDataset(const ForceDataset& data);

// Groups the samples by feature point (in order of first appearance). Requires the features
// "phi, beta, gamma" and W = 6, and at every point one sample of each vertex 0..K−1. Throws
// InputError "`where`: ..." naming the dataset (and the point and vertex) otherwise.
SpatialPoints groupSpatialSamples(const ForceDataset& data, const std::string& where);

// The points scaled, then the zero-wrench points: for each height, each distinct (β, γ) of the points
// in order of first appearance; those coinciding with a point of the data are skipped. Throws
// std::invalid_argument on a zero or non-finite scale or a height that is not > 0, InputError when
// the result would exceed limits::kMaxArrayEntries values.
SpatialPoints augmentSpatial(const SpatialPoints& points, double scale, const std::vector<double>& heights);

}  // namespace nmdp
