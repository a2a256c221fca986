#include "training/mlp/mlp_points.hpp"

#include <stdexcept>
#include <utility>

#include "training/spatial_points.hpp"

namespace nmdp {

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

bool isSpatialMlpDataset(const ForceDataset& data) { return isSpatialDataset(data); }

MlpPoints groupSpatialMlpSamples(const ForceDataset& data, const std::string& where) {
  SpatialPoints grouped = groupSpatialSamples(data, where);
  MlpPoints out;
  out.wrench = MlpWrench::Spatial;
  out.features = grouped.features;
  out.values = std::move(grouped.values);
  out.origin = std::move(grouped.origin);
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
