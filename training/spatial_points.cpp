#include "training/spatial_points.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "common/input_error.hpp"
#include "common/limits.hpp"

namespace nmdp {

bool isSpatialDataset(const ForceDataset& data) { return data.features.cols() == 3; }

SpatialPoints groupSpatialSamples(const ForceDataset& data, const std::string& where) {
  validateForceDataset(data, where);
  const SampleLayout& layout = spatialSampleLayout();
  if (data.features.cols() != 3 || data.feature_names != layout.feature_names)
    throw InputError(where +
                     ": dataset '/features' must have the 3 features \"phi, beta, gamma\" of the 3-D contact models "
                     "(signed depth, sagittal and lateral leg lean), it has \"" +
                     joinNames(data.feature_names) + "\"");
  if (data.wrench.cols() != 6)
    throw InputError(where + ": dataset '/wrench' must be N x 6 (tau_x, tau_y, tau_z, F_x, F_y, F_z) for a 3-D "
                     "model (features phi, beta, gamma), it is N x " + std::to_string(data.wrench.cols()));
  // Columns in another order would be fitted silently as the wrong components.
  if (data.wrench_names != layout.wrench_names)
    throw InputError(where + ": dataset '/wrench' must have the 6 columns \"" + joinNames(layout.wrench_names) +
                     "\" of a 3-D model, in that order; it has \"" + joinNames(data.wrench_names) + "\"");
  GroupedSamples grouped = groupSamplesByPoint(data, where);
  SpatialPoints out;
  out.features = grouped.features;
  out.values = std::move(grouped.values);
  out.origin.assign(out.features.rows(), PointOrigin::Measured);
  return out;
}

SpatialPoints augmentSpatial(const SpatialPoints& points, double scale, const std::vector<double>& heights) {
  if (!(std::isfinite(scale) && scale != 0.0))
    throw std::invalid_argument("augmentSpatial: the scale must be finite and non-zero");
  for (double h : heights)
    if (!(std::isfinite(h) && h > 0.0)) throw std::invalid_argument("augmentSpatial: heights must be > 0");

  const Eigen::Index P = points.features.rows();
  const int K = points.vertexCount();
  // The distinct tilts (β, γ) of the data, in order of first appearance.
  std::vector<std::pair<double, double>> tilts;
  for (Eigen::Index i = 0; i < P; ++i) {
    const std::pair<double, double> t(points.features(i, 1), points.features(i, 2));
    if (std::find(tilts.begin(), tilts.end(), t) == tilts.end()) tilts.push_back(t);
  }
  const Eigen::Index capacity = P + static_cast<Eigen::Index>(heights.size() * tilts.size());
  if (capacity * 6 * K > limits::kMaxArrayEntries)
    throw InputError("augmentation.above_surface: " + std::to_string(heights.size()) + " heights x " +
                     std::to_string(tilts.size()) + " tilts over " + std::to_string(P) + " points of " +
                     std::to_string(K) + " vertices is more data than a fit takes (" +
                     std::to_string(limits::kMaxArrayEntries) + " values)");
  SpatialPoints out;
  out.features.resize(capacity, 3);
  out.values.resize(capacity, 6 * K);
  out.features.topRows(P) = points.features;
  out.values.topRows(P) = scale * points.values;
  out.origin = points.origin;
  Eigen::Index n = P;
  for (double h : heights)
    for (const auto& [beta, gamma] : tilts) {
      const Eigen::RowVector3d f(h, beta, gamma);
      bool present = false;
      for (Eigen::Index i = 0; i < P && !present; ++i) present = points.features.row(i) == f;
      if (present) continue;  // measured data wins
      out.features.row(n) = f;
      out.values.row(n).setZero();
      out.origin.push_back(PointOrigin::AboveSurface);
      ++n;
    }
  out.features.conservativeResize(n, 3);
  out.values.conservativeResize(n, 6 * K);
  return out;
}

}  // namespace nmdp
