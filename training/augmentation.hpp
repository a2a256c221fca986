// From a force dataset to the points a planar wrench-space fit interpolates, and the augmentation
// the published sand model used (DESIGN.md §9, granular/README.md):
//   * scale      every wrench times a factor (the published model is 3 × the sand samples);
//   * mirror     each point (φ, β ≠ 0) gets a copy at (φ, −β) with F_x and τ_y negated, F_z kept:
//                the sagittal mirror x → −x. Vertex j stays vertex j ("same", what the published
//                model did: its weights reproduce the mirrored samples that way to 1e-7 N, while
//                with j → K − j they miss by up to 75 N at (−0.01, ±0.3)) or becomes vertex (K − j) mod K ("reversed",
//                for data whose probing direction j mirrors to K − j, like data/granular's hand-made model);
//   * above_surface  zero-wrench points at heights φ > 0 for a list of angles (by default every
//                angle of the points after mirroring), so the fitted force fades above the ground.
// Augmented points that coincide with an existing point are skipped: measured data wins.
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "training/force_dataset.hpp"

namespace nmdp {

enum class PointOrigin { Measured = 0, Mirrored = 1, AboveSurface = 2 };
const char* pointOriginName(PointOrigin origin);  // "measured", "mirrored", "above_surface"

// P feature points (φ, β) with all K vertices' planar wrenches: row i of `values` holds vertex j's
// (F_x, F_z, τ_y) in columns 3j..3j+2 (the layout of RbfFunction's weights).
struct PlanarPoints {
  Eigen::MatrixX2d features;        // P×2
  Eigen::MatrixXd values;           // P×3K
  std::vector<PointOrigin> origin;  // P
  int pointCount() const { return static_cast<int>(features.rows()); }
  int vertexCount() const { return static_cast<int>(values.cols() / 3); }
};

// Groups the samples of a planar dataset by feature point (points in order of first appearance).
// Requires the features (phi, beta) and W = 3 (F_x, F_z, tau_y), and at every point one sample of
// each vertex 0..K−1, K = the largest index + 1. Throws InputError "`where`: ..." naming the
// dataset, the point and the vertex otherwise (a duplicate sample, a missing vertex).
PlanarPoints groupPlanarSamples(const ForceDataset& data, const std::string& where);

enum class MirrorVertices { Same, Reversed };
const char* mirrorVerticesName(MirrorVertices m);  // "same", "reversed"

struct AugmentationSettings {
  double scale = 1.0;  // finite, non-zero
  bool mirror = false;
  MirrorVertices mirror_vertices = MirrorVertices::Same;
  std::vector<double> above_heights;  // φ > 0 of the zero-wrench points; empty = none
  std::vector<double> above_angles;   // their β; empty = every β of the points after mirroring
};

// The augmented points: the input (scaled), then the mirrored copies, then the zero-wrench points
// (for each height, each angle), the order the published model's centres have. Throws
// std::invalid_argument on settings that parseFitConfig rejects (a zero scale, a height ≤ 0).
PlanarPoints augment(const PlanarPoints& points, const AugmentationSettings& settings);

// What the fit reports divide errors by: at each point the largest |value| entry, "the largest
// wrench at that point"; at zero-wrench points (above the surface) the largest of all the values.
Eigen::VectorXd pointScales(const PlanarPoints& points);
// P×K: for each point and vertex, the largest |error| over (F_x, F_z, τ_y) divided by the point's
// scale (by 1 where the scale is 0, i.e. all the data is zero). error is P×3K, in the layout of values.
Eigen::MatrixXd relativeVertexErrors(const Eigen::MatrixXd& error, const Eigen::VectorXd& scale);

}  // namespace nmdp
