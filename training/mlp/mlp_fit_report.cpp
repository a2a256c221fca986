#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "training/fit_report.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace nmdp {

namespace {

// Points by origin (measured, mirrored, above the surface), of all or the selected ones.
std::array<int, 3> countByOrigin(const MlpPoints& points, const std::vector<bool>* selected = nullptr) {
  std::array<int, 3> counts{0, 0, 0};
  for (size_t i = 0; i < points.origin.size(); ++i)
    if (!selected || (*selected)[i]) ++counts[static_cast<int>(points.origin[i])];
  return counts;
}

// "φ, β" or "φ, β, γ" of point i, comma separated, in the stream's current format.
void writeFeatures(std::ostream& s, const MlpPoints& pts, Eigen::Index i) {
  for (Eigen::Index c = 0; c < pts.features.cols(); ++c) s << (c ? ", " : "") << pts.features(i, c);
}

}  // namespace

std::string formatMlpFitReport(const MlpFitRecord& r) {
  const MlpPoints& pts = r.points;
  const MlpFit& fit = r.fit;
  const Eigen::Index P = pts.features.rows(), K = pts.vertexCount();
  std::ostringstream s(fitReportOpening("MLP", r.data, r.settings, r.from_data), std::ios::ate);
  const std::array<int, 3> counts = countByOrigin(pts), val_counts = countByOrigin(pts, &fit.validation);
  const int n_val = val_counts[0] + val_counts[1] + val_counts[2];
  if (pts.wrench == MlpWrench::Spatial)
    s << "3-D data: features (phi, beta, gamma), 6 wrench entries (tau_x, tau_y, tau_z, F_x, F_y, F_z) per vertex, "
         "fitted without augmentation\n";
  s << "points: " << P << " (" << counts[0] << " measured, " << counts[1] << " mirrored, " << counts[2]
    << " zero-wrench above the surface), " << K << " vertices; " << P - n_val << " for training, " << n_val
    << " for validation (" << val_counts[0] << " measured, " << val_counts[1] << " mirrored, " << val_counts[2]
    << " above the surface)\n";
  const std::vector<int> sizes = fit.parameters.sizes();
  long n_params = 0;
  for (const MlpLayer& l : fit.parameters.layers) n_params += static_cast<long>(l.weight.size() + l.bias.size());
  if (fit.teacher_samples > 0)
    s << "plus " << fit.teacher_samples << " teacher samples for training (the \"rbf\" section's RBF through these "
      << "points, on an mlp.teacher_grid over the points at or below the surface)\n";
  if (fit.parameters.anchors.rows() > 0)
    s << "zero anchors: the " << fit.parameters.anchors.rows() << " zero-wrench training points (bump radius "
      << fit.parameters.anchor_radius << " in normalized inputs): the model is exactly zero there\n";
  s << "network: ";
  for (size_t i = 0; i < sizes.size(); ++i) s << (i ? "-" : "") << sizes[i];
  s << " " << mlpActivationName(fit.parameters.activation) << ", " << n_params << " parameters\n";
  s << "epochs: " << fit.epochs << (fit.stopped_early ? " (stopped early: no better loss for the patience)" : "")
    << ", best epoch " << fit.best_epoch << " (its weights are kept); loss at the best epoch: training "
    << std::setprecision(4) << fit.train_loss << ", validation ";
  if (std::isnan(fit.validation_loss))
    s << "- (no validation points)";
  else
    s << fit.validation_loss;
  s << "\n" << std::fixed << std::setprecision(2) << "training time " << r.seconds << " s\n" << std::defaultfloat;
  s << "error of the fit, relative to the largest wrench at the point (%):\n";
  s << "  vertex   max(valid.)  rms(valid.)  max(train)   worst point (all)\n";
  for (Eigen::Index j = 0; j < K; ++j) {
    double max_val = 0.0, sum2 = 0.0, max_train = 0.0, max_all = -1.0;
    Eigen::Index worst = 0;
    for (Eigen::Index i = 0; i < P; ++i) {
      const double e = fit.relative(i, j);
      if (fit.validation[i]) {
        max_val = std::max(max_val, e);
        sum2 += e * e;
      } else {
        max_train = std::max(max_train, e);
      }
      if (e > max_all) {
        max_all = e;
        worst = i;
      }
    }
    s << "  " << std::setw(6) << j << std::fixed << std::setprecision(2);
    if (n_val > 0)
      s << std::setw(13) << 100 * max_val << std::setw(13) << 100 * std::sqrt(sum2 / n_val);
    else
      s << std::setw(13) << "-" << std::setw(13) << "-";
    s << std::setw(12) << 100 * max_train << std::defaultfloat << std::setprecision(4) << "   " << worst << " (";
    writeFeatures(s, pts, worst);
    s << ", " << pointOriginName(pts.origin[worst]) << (fit.validation[worst] ? ", validation" : ", training") << ")\n";
  }
  std::vector<Eigen::Index> order;
  for (Eigen::Index i = 0; i < P; ++i)
    if (fit.validation[i]) order.push_back(i);
  const bool validation = !order.empty();
  if (!validation)
    for (Eigen::Index i = 0; i < P; ++i) order.push_back(i);
  const Eigen::VectorXd per_point = fit.relative.rowwise().maxCoeff();
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return per_point[a] > per_point[b]; });
  s << "worst " << (validation ? "validation" : "training") << " points (largest over the vertices, %):";
  for (size_t n = 0; n < std::min<size_t>(5, order.size()); ++n) {
    const Eigen::Index i = order[n];
    s << (n ? "," : "") << " " << i << " (";
    writeFeatures(s, pts, i);
    s << ") " << std::fixed << std::setprecision(2) << 100 * per_point[i] << std::defaultfloat << std::setprecision(6);
  }
  s << "\n" << formatAboveSurface(r.above_surface) << formatFitWarnings(r.warnings);
  return s.str();
}

}  // namespace nmdp
