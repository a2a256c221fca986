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
// Mirror and heights not given are decided from the data (resolveAugmentation): the published
// model's augmentation, so that a fit with no configuration pushes no force on a foot in the air.
#pragma once
#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "common/named_enum.hpp"
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

// Any fit's points as the fitting code sees them: P points of F features (2 planar, 3 spatial) with
// K vertices of W entries each (3 planar, 6 spatial), vertex j in columns W j .. W j + W − 1.
struct PointSetView {
  Eigen::Ref<const Eigen::MatrixXd> features;  // P×F
  const Eigen::MatrixXd& values;               // P×WK
  const std::vector<PointOrigin>& origin;      // P
  int wrench_size;                             // W
  Eigen::Index pointCount() const { return features.rows(); }
  Eigen::Index vertexCount() const { return values.cols() / wrench_size; }
};
inline PointSetView viewOf(const PlanarPoints& p) { return {p.features, p.values, p.origin, 3}; }

// "(phi -0.01, beta 0.3)" or "(phi -0.01, beta 0.3, gamma 0.6)": row i by its 2 or 3 features.
std::string featurePointText(const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::Index i, int precision = 6);

// The samples of a dataset grouped by feature point (in order of first appearance): P×F features
// and P×WK values, vertex v of a point in columns W v .. W v + W − 1 (W = the wrench's columns).
// Throws InputError "`where`: ..." naming the point and the vertex for a duplicate sample, a missing
// vertex or an index beyond the sample count. The callers check the feature names and W first.
struct GroupedSamples {
  Eigen::MatrixXd features, values;
};
GroupedSamples groupSamplesByPoint(const ForceDataset& data, const std::string& where);

// Groups the samples of a planar dataset by feature point (points in order of first appearance).
// Requires the features (phi, beta) and W = 3 (F_x, F_z, tau_y), and at every point one sample of
// each vertex 0..K−1, K = the largest index + 1. Throws InputError "`where`: ..." naming the
// dataset, the point and the vertex otherwise (a duplicate sample, a missing vertex).
PlanarPoints groupPlanarSamples(const ForceDataset& data, const std::string& where);

enum class MirrorVertices { Same, Reversed };
inline constexpr EnumName<MirrorVertices> kMirrorVertices[] = {{MirrorVertices::Same, "same"},
                                                               {MirrorVertices::Reversed, "reversed"}};
inline const char* mirrorVerticesName(MirrorVertices m) { return nameOf(kMirrorVertices, m); }

struct AugmentationSettings {
  double scale = 1.0;  // finite, non-zero
  std::optional<bool> mirror;  // none: decided from the data (dataCoversOneSide)
  MirrorVertices mirror_vertices = MirrorVertices::Same;
  // φ > 0 of the zero-wrench points; empty = none; none (std::nullopt): defaultAboveSurfaceHeights.
  // (Assign std::vector<double>{} for "none": `= {}` would reset the optional to "from the data".)
  std::optional<std::vector<double>> above_heights;
  std::vector<double> above_angles;   // their β; empty = every β of the points after mirroring
};

// Whether every angle of the points lies on one side of β = 0 (all ≥ 0 or all ≤ 0, some ≠ 0):
// then the default augmentation mirrors them.
bool dataCoversOneSide(const PlanarPoints& points);

// The published model's heights, [0.01, 0.03, 0.05, 0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0] m for data
// 7 cm deep, scaled by the data's depth span (−the lowest φ; 7 cm when no point is below the
// surface), so that data of another depth range gets rows as far above the surface relative to its
// own depths.
std::vector<double> scaledPublishedHeights(const PlanarPoints& points);
// The default zero-wrench heights: scaledPublishedHeights, or none when the data has points above
// the surface already (it brings its own).
std::vector<double> defaultAboveSurfaceHeights(const PlanarPoints& points);

// The most angles the default zero-wrench rows get: scattered data (every point at its own angle)
// would otherwise get heights × points of them (a grid like the sand samples has 7 angles mirrored).
constexpr int kMaxDefaultAboveAngles = 25;

// The settings with mirror and above_heights decided from the points where not given; the rest as
// given, except that default heights with angles "data" over more than kMaxDefaultAboveAngles
// distinct angles (after mirroring) get that many angles evenly over their range instead.
AugmentationSettings resolveAugmentation(const PlanarPoints& points, const AugmentationSettings& settings);

// The augmented points: the input (scaled), then the mirrored copies, then the zero-wrench points
// (for each height, each angle), the order the published model's centres have. Settings not given
// are decided from the points first (resolveAugmentation). Throws std::invalid_argument on settings
// that parseFitConfig rejects (a zero scale, a height ≤ 0).
PlanarPoints augment(const PlanarPoints& points, const AugmentationSettings& settings);

// What the fit reports divide errors by: at each point the largest |value| entry, "the largest
// wrench at that point"; at zero-wrench points (above the surface) the largest of all the values.
Eigen::VectorXd pointScales(const Eigen::MatrixXd& values);
inline Eigen::VectorXd pointScales(const PlanarPoints& points) { return pointScales(points.values); }
// P×K: for each point and vertex, the largest |error| over the vertex's W entries ((F_x, F_z, τ_y)
// planar) divided by the point's scale (by 1 where the scale is 0, i.e. all the data is zero).
// error is P×WK, in the layout of values.
Eigen::MatrixXd relativeVertexErrors(const Eigen::MatrixXd& error, const Eigen::VectorXd& scale, int wrench_size = 3);

// The published heights scaled by the depth span of points whose depths are `phi` (see below).
std::vector<double> scaledPublishedHeights(const Eigen::Ref<const Eigen::VectorXd>& phi);

}  // namespace nmdp
