#include "training/augmentation.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "common/input_error.hpp"
#include "common/limits.hpp"
#include "common/named_enum.hpp"

namespace nmdp {

namespace {

// Index of the row of `features` (first `rows` rows) equal to (phi, beta), or −1.
Eigen::Index findPoint(const Eigen::MatrixX2d& features, Eigen::Index rows, double phi, double beta) {
  for (Eigen::Index i = 0; i < rows; ++i)
    if (features(i, 0) == phi && features(i, 1) == beta) return i;
  return -1;
}

constexpr EnumName<PointOrigin> kPointOrigins[] = {
    {PointOrigin::Measured, "measured"}, {PointOrigin::Mirrored, "mirrored"}, {PointOrigin::AboveSurface, "above_surface"}};
}  // namespace

const char* pointOriginName(PointOrigin origin) { return nameOf(kPointOrigins, origin); }

std::string featurePointText(const Eigen::Ref<const Eigen::MatrixXd>& features, Eigen::Index i, int precision) {
  static const char* const kNames[] = {"phi", "beta", "gamma"};
  std::ostringstream s;
  s.precision(precision);
  s << "(";
  for (Eigen::Index c = 0; c < features.cols(); ++c)
    s << (c ? ", " : "") << (c < 3 ? kNames[c] : "f" + std::to_string(c)) << " " << features(i, c);
  s << ")";
  return s.str();
}

PlanarPoints groupPlanarSamples(const ForceDataset& data, const std::string& where) {
  validateForceDataset(data, where);
  if (data.features.cols() != 2 || data.feature_names != std::vector<std::string>{"phi", "beta"})
    throw InputError(where +
                     ": dataset '/features' must have the 2 features \"phi, beta\" of the planar contact "
                     "models (signed distance, sagittal leg angle), it has \"" +
                     joinNames(data.feature_names) + "\"");
  if (data.wrench.cols() != 3)
    throw InputError(where + ": dataset '/wrench' must be N x 3 (F_x, F_z, tau_y) for a planar model, it is N x " +
                     std::to_string(data.wrench.cols()));
  GroupedSamples grouped = groupSamplesByPoint(data, where);
  PlanarPoints out;
  out.features = grouped.features;
  out.values = std::move(grouped.values);
  out.origin.assign(out.features.rows(), PointOrigin::Measured);
  return out;
}

GroupedSamples groupSamplesByPoint(const ForceDataset& data, const std::string& where) {
  const Eigen::Index N = data.features.rows(), F = data.features.cols(), W = data.wrench.cols();
  const int K = data.vertex.maxCoeff() + 1;
  if (K > N) {  // checked before sizing anything by K: every point needs all K vertices
    Eigen::Index row = 0;
    data.vertex.maxCoeff(&row);
    throw InputError(where + ": dataset '/vertex' has the index " + std::to_string(K - 1) + " at row " +
                     std::to_string(row) + ", but there are only " + std::to_string(N) +
                     " samples: every point needs one sample of each vertex 0.." + std::to_string(K - 1));
  }
  const auto point = [&](Eigen::Index s) {
    std::vector<double> f(F);
    for (Eigen::Index c = 0; c < F; ++c) f[c] = data.features(s, c);
    return f;
  };
  std::map<std::vector<double>, int> index;  // point → row of the output
  std::vector<Eigen::Index> first_row;       // the first sample of each point
  for (Eigen::Index s = 0; s < N; ++s)
    if (index.emplace(point(s), static_cast<int>(first_row.size())).second) first_row.push_back(s);
  const Eigen::Index P = static_cast<Eigen::Index>(first_row.size());

  GroupedSamples out;
  out.features.resize(P, F);
  out.values.resize(P, W * K);
  std::vector<Eigen::Index> sample_of(P * K, -1);  // (point, vertex) → sample row
  for (Eigen::Index s = 0; s < N; ++s) {
    const int p = index.at(point(s));
    const int v = data.vertex[s];
    Eigen::Index& seen = sample_of[p * K + v];
    if (seen >= 0)
      throw InputError(where + ": duplicate sample: rows " + std::to_string(seen) + " and " + std::to_string(s) +
                       " both give vertex " + std::to_string(v) + " at the point " +
                       featurePointText(data.features, s) + "; remove one");
    seen = s;
    out.features.row(p) = data.features.row(s);
    out.values.block(p, W * v, 1, W) = data.wrench.row(s);
  }
  for (Eigen::Index p = 0; p < P; ++p)
    for (int v = 0; v < K; ++v)
      if (sample_of[p * K + v] < 0)
        throw InputError(where + ": the point " + featurePointText(out.features, p) + " (first row " +
                         std::to_string(first_row[p]) + ") has no sample of vertex " + std::to_string(v) +
                         ": every point needs all " + std::to_string(K) + " vertices (0.." + std::to_string(K - 1) +
                         ")");
  return out;
}

bool dataCoversOneSide(const PlanarPoints& points) {
  if (points.pointCount() == 0) return false;
  const double lowest = points.features.col(1).minCoeff(), highest = points.features.col(1).maxCoeff();
  return (lowest >= 0.0 || highest <= 0.0) && (lowest != 0.0 || highest != 0.0);
}

std::vector<double> scaledPublishedHeights(const PlanarPoints& points) {
  return scaledPublishedHeights(points.features.col(0));
}

std::vector<double> scaledPublishedHeights(const Eigen::Ref<const Eigen::VectorXd>& phi) {
  // The published sand model's zero-wrench heights (granular/README.md), for its 7 cm of data.
  static constexpr double kPublishedHeights[] = {0.01, 0.03, 0.05, 0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0};
  constexpr double kPublishedDepthSpan = 0.07;
  const double lowest = phi.size() > 0 ? phi.minCoeff() : 0.0;
  const double span = lowest < 0.0 ? -lowest : kPublishedDepthSpan;
  std::vector<double> heights;
  for (double h : kPublishedHeights) heights.push_back(h * (span / kPublishedDepthSpan));
  return heights;
}

std::vector<double> defaultAboveSurfaceHeights(const PlanarPoints& points) {
  if (points.pointCount() > 0 && points.features.col(0).maxCoeff() > 0.0) return {};
  return scaledPublishedHeights(points);
}

AugmentationSettings resolveAugmentation(const PlanarPoints& points, const AugmentationSettings& settings) {
  AugmentationSettings out = settings;
  if (!out.mirror) out.mirror = dataCoversOneSide(points);
  if (!out.above_heights) {
    out.above_heights = defaultAboveSurfaceHeights(points);
    if (out.above_angles.empty() && !out.above_heights->empty()) {
      std::vector<double> angles;
      for (int i = 0; i < points.pointCount(); ++i) {
        angles.push_back(points.features(i, 1));
        if (*out.mirror) angles.push_back(-points.features(i, 1));
      }
      std::sort(angles.begin(), angles.end());
      angles.erase(std::unique(angles.begin(), angles.end()), angles.end());
      if (static_cast<int>(angles.size()) > kMaxDefaultAboveAngles) {
        const double first = angles.front(), last = angles.back();
        out.above_angles.resize(kMaxDefaultAboveAngles);
        for (int k = 0; k < kMaxDefaultAboveAngles; ++k)
          out.above_angles[k] = k + 1 < kMaxDefaultAboveAngles
                                    ? first + (last - first) * k / (kMaxDefaultAboveAngles - 1)
                                    : last;  // the range's ends exactly
      }
    }
  }
  return out;
}

PlanarPoints augment(const PlanarPoints& points, const AugmentationSettings& requested) {
  if (!(std::isfinite(requested.scale) && requested.scale != 0.0))
    throw std::invalid_argument("augment: the scale must be finite and non-zero");
  const AugmentationSettings settings = resolveAugmentation(points, requested);
  const std::vector<double>& heights = *settings.above_heights;
  for (double h : heights)
    if (!(std::isfinite(h) && h > 0.0)) throw std::invalid_argument("augment: heights above the surface must be > 0");
  for (double a : settings.above_angles)
    if (!std::isfinite(a)) throw std::invalid_argument("augment: angles must be finite");

  const Eigen::Index P = points.features.rows();
  const int K = points.vertexCount();
  // Worst case: every point mirrored, every (height, angle) added.
  const Eigen::Index angle_bound = settings.above_angles.empty() ? 2 * P : settings.above_angles.size();
  const Eigen::Index capacity = 2 * P + static_cast<Eigen::Index>(heights.size()) * angle_bound;
  if (capacity * 3 * K > limits::kMaxArrayEntries)
    throw InputError("augmentation.above_surface: " + std::to_string(heights.size()) + " heights x " +
                     std::to_string(angle_bound) + " angles over " + std::to_string(P) + " points of " + std::to_string(K) +
                     " vertices is more data than a fit takes (" + std::to_string(limits::kMaxArrayEntries) + " values)");
  PlanarPoints out;
  out.features.resize(capacity, 2);
  out.values.resize(capacity, 3 * K);
  out.features.topRows(P) = points.features;
  out.values.topRows(P) = settings.scale * points.values;
  out.origin = points.origin;
  Eigen::Index n = P;

  if (*settings.mirror) {
    for (Eigen::Index i = 0; i < P; ++i) {
      const double phi = points.features(i, 0), beta = points.features(i, 1);
      if (beta == 0.0 || findPoint(out.features, n, phi, -beta) >= 0) continue;  // on the mirror plane, or measured
      out.features.row(n) << phi, -beta;
      for (int j = 0; j < K; ++j) {
        const int source = settings.mirror_vertices == MirrorVertices::Same ? j : (K - j) % K;
        // x → −x: F_x and the moment about y change sign, F_z does not.
        out.values(n, 3 * j) = -out.values(i, 3 * source);
        out.values(n, 3 * j + 1) = out.values(i, 3 * source + 1);
        out.values(n, 3 * j + 2) = -out.values(i, 3 * source + 2);
      }
      out.origin.push_back(PointOrigin::Mirrored);
      ++n;
    }
  }

  std::vector<double> angles = settings.above_angles;
  if (angles.empty())
    for (Eigen::Index i = 0; i < n; ++i)
      if (std::find(angles.begin(), angles.end(), out.features(i, 1)) == angles.end())
        angles.push_back(out.features(i, 1));
  for (double h : heights) {
    for (double a : angles) {
      if (findPoint(out.features, n, h, a) >= 0) continue;
      out.features.row(n) << h, a;
      out.values.row(n).setZero();
      out.origin.push_back(PointOrigin::AboveSurface);
      ++n;
    }
  }
  out.features.conservativeResize(n, 2);
  out.values.conservativeResize(n, 3 * K);
  return out;
}

Eigen::VectorXd pointScales(const Eigen::MatrixXd& values) {
  const double overall = values.size() ? values.cwiseAbs().maxCoeff() : 0.0;
  Eigen::VectorXd scale(values.rows());
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    const double local = values.row(i).cwiseAbs().maxCoeff();
    scale[i] = local > 0.0 ? local : overall;
  }
  return scale;
}

Eigen::MatrixXd relativeVertexErrors(const Eigen::MatrixXd& error, const Eigen::VectorXd& scale, int wrench_size) {
  const Eigen::Index P = error.rows(), W = wrench_size, K = error.cols() / W;
  Eigen::MatrixXd relative(P, K);
  for (Eigen::Index i = 0; i < P; ++i)
    for (Eigen::Index j = 0; j < K; ++j)
      relative(i, j) = error.block(i, W * j, 1, W).cwiseAbs().maxCoeff() / (scale[i] > 0.0 ? scale[i] : 1.0);
  return relative;
}

}  // namespace nmdp
