#include "training/mlp/mlp_points.hpp"

#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "common/input_error.hpp"

namespace nmdp {

namespace {

const std::vector<std::string> kSpatialFeatureNames = {"phi", "beta", "gamma"};
const std::vector<std::string> kSpatialWrenchNames = {"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"};

std::string pointText(const Eigen::MatrixXd& features, Eigen::Index row) {
  std::ostringstream s;
  s << "(phi " << features(row, 0) << ", beta " << features(row, 1) << ", gamma " << features(row, 2) << ")";
  return s.str();
}

}  // namespace

MlpPoints mlpPoints(const PlanarPoints& points) {
  MlpPoints out;
  out.features = points.features;
  out.values = points.values;
  out.origin = points.origin;
  return out;
}

PlanarPoints planarPoints(const MlpPoints& points) {
  if (points.wrench != MlpWrench::Planar) throw std::logic_error("planarPoints: spatial points");
  PlanarPoints out;
  out.features = points.features;
  out.values = points.values;
  out.origin = points.origin;
  return out;
}

bool isSpatialMlpDataset(const ForceDataset& data) { return data.features.cols() == 3; }

MlpPoints groupSpatialMlpSamples(const ForceDataset& data, const std::string& where) {
  validateForceDataset(data, where);
  if (data.features.cols() != 3 || data.feature_names != kSpatialFeatureNames)
    throw InputError(where + ": dataset '/features' must have the 3 features \"phi, beta, gamma\" of the spatial "
                     "contact models (signed depth, sagittal and lateral leg lean), it has \"" +
                     joinNames(data.feature_names) + "\"");
  if (data.wrench.cols() != 6 || data.wrench_names != kSpatialWrenchNames)
    throw InputError(where + ": dataset '/wrench' must have the 6 columns \"" + joinNames(kSpatialWrenchNames) +
                     "\" for a spatial model, it has \"" + joinNames(data.wrench_names) + "\"");
  const Eigen::Index N = data.features.rows();
  const int K = data.vertex.maxCoeff() + 1;
  if (K > N) {  // checked before sizing anything by K: every point needs all K vertices
    Eigen::Index row = 0;
    data.vertex.maxCoeff(&row);
    throw InputError(where + ": dataset '/vertex' has the index " + std::to_string(K - 1) + " at row " +
                     std::to_string(row) + ", but there are only " + std::to_string(N) +
                     " samples: every point needs one sample of each vertex 0.." + std::to_string(K - 1));
  }
  using Key = std::tuple<double, double, double>;
  const auto key = [&](Eigen::Index s) { return Key{data.features(s, 0), data.features(s, 1), data.features(s, 2)}; };
  std::map<Key, int> index;          // point → row of the output
  std::vector<Eigen::Index> first_row;  // the first sample of each point
  for (Eigen::Index s = 0; s < N; ++s)
    if (index.emplace(key(s), static_cast<int>(first_row.size())).second) first_row.push_back(s);
  const Eigen::Index P = static_cast<Eigen::Index>(first_row.size());

  MlpPoints out;
  out.wrench = MlpWrench::Spatial;
  out.features.resize(P, 3);
  out.values.resize(P, 6 * K);
  out.origin.assign(P, PointOrigin::Measured);
  std::vector<Eigen::Index> sample_of(P * K, -1);  // (point, vertex) → sample row
  for (Eigen::Index s = 0; s < N; ++s) {
    const int p = index.at(key(s));
    const int v = data.vertex[s];
    Eigen::Index& seen = sample_of[p * K + v];
    if (seen >= 0)
      throw InputError(where + ": duplicate sample: rows " + std::to_string(seen) + " and " + std::to_string(s) +
                       " both give vertex " + std::to_string(v) + " at the point " + pointText(data.features, s) +
                       "; remove one");
    seen = s;
    out.features.row(p) = data.features.row(s);
    out.values.block(p, 6 * v, 1, 6) = data.wrench.row(s);
  }
  for (Eigen::Index p = 0; p < P; ++p)
    for (int v = 0; v < K; ++v)
      if (sample_of[p * K + v] < 0)
        throw InputError(where + ": the point " + pointText(out.features, p) + " (first row " +
                         std::to_string(first_row[p]) + ") has no sample of vertex " + std::to_string(v) +
                         ": every point needs all " + std::to_string(K) + " vertices (0.." + std::to_string(K - 1) + ")");
  return out;
}

Eigen::VectorXd mlpPointScales(const MlpPoints& points) {
  const double overall = points.values.size() ? points.values.cwiseAbs().maxCoeff() : 0.0;
  Eigen::VectorXd scale(points.pointCount());
  for (int i = 0; i < points.pointCount(); ++i) {
    const double local = points.values.row(i).cwiseAbs().maxCoeff();
    scale[i] = local > 0.0 ? local : overall;
  }
  return scale;
}

Eigen::MatrixXd mlpRelativeVertexErrors(const Eigen::MatrixXd& error, const Eigen::VectorXd& scale, int w) {
  const Eigen::Index P = error.rows(), K = error.cols() / w;
  Eigen::MatrixXd relative(P, K);
  for (Eigen::Index i = 0; i < P; ++i)
    for (Eigen::Index j = 0; j < K; ++j)
      relative(i, j) = error.block(i, w * j, 1, w).cwiseAbs().maxCoeff() / (scale[i] > 0.0 ? scale[i] : 1.0);
  return relative;
}

}  // namespace nmdp
