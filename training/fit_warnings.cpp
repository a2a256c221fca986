#include "training/fit_warnings.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nmdp {

namespace {
std::string percent(double share) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(share < 0.1 ? 2 : 1);
  s << 100.0 * share << " %";
  return s.str();
}

std::string number(double x) {
  std::ostringstream s;
  s.precision(4);
  s << x;
  return s.str();
}
}  // namespace

std::string formatFitWarnings(const std::vector<FitWarning>& warnings) {
  if (warnings.empty()) return "warnings: none\n";
  std::string out;
  for (const FitWarning& w : warnings) out += "warning: " + w.what + "\n  suggestion: " + w.suggestion + "\n";
  return out;
}

AboveSurfaceCheck checkAboveSurface(const FeatureWrenchFunction& model, const PlanarGeometry& geometry,
                                    const PlanarPoints& points) {
  AboveSurfaceCheck check;
  double beta_lo = 0.0, beta_hi = 0.0;
  bool any_below = false;
  for (int i = 0; i < points.pointCount(); ++i) {
    if (points.features(i, 0) > 0.0) continue;
    const double beta = points.features(i, 1);
    beta_lo = any_below ? std::min(beta_lo, beta) : beta;
    beta_hi = any_below ? std::max(beta_hi, beta) : beta;
    any_below = true;
    check.largest_below = std::max(check.largest_below, points.values.row(i).cwiseAbs().maxCoeff());
  }
  if (!any_below || !(geometry.cutoff > 0.0)) return check;

  const int n_angles = beta_hi > beta_lo ? kAboveSurfaceAngles : 1;
  Eigen::MatrixX2d grid((kAboveSurfaceHeights - 1) * n_angles, 2);
  int row = 0;
  for (int k = 1; k < kAboveSurfaceHeights; ++k)
    for (int a = 0; a < n_angles; ++a, ++row)
      grid.row(row) << geometry.cutoff * k / kAboveSurfaceHeights,
          n_angles > 1 ? beta_lo + (beta_hi - beta_lo) * a / (n_angles - 1) : beta_lo;
  Eigen::MatrixXd W;
  model.evaluate(grid, W, nullptr, nullptr);
  check.grid_points = static_cast<int>(grid.rows());
  for (Eigen::Index r = 0; r < grid.rows(); ++r) {
    const double largest = cutoffStep(geometry, grid(r, 0), nullptr) * W.row(r).cwiseAbs().maxCoeff();
    if (largest > check.largest_above) {
      check.largest_above = largest;
      check.phi = grid(r, 0);
      check.beta = grid(r, 1);
    }
  }
  return check;
}

std::optional<FitWarning> aboveSurfaceWarning(const AboveSurfaceCheck& check, const PlanarGeometry& geometry) {
  if (check.grid_points == 0 || !(check.share() > kAboveSurfaceWarnShare)) return std::nullopt;
  FitWarning w;
  w.what = "the model pushes above the surface: up to " + number(check.largest_above) + " (" +
           percent(check.share()) + " of the largest wrench below the surface, " + number(check.largest_below) +
           ") at phi " + number(check.phi) + " m, beta " + number(check.beta) + " rad, below the cut-off at " +
           number(geometry.cutoff) + " m";
  w.suggestion =
      "add zero-wrench points closer to the surface (augmentation.above_surface.heights) or lower geometry.cutoff "
      "towards the surface (leaving both out picks them from the data)";
  return w;
}

std::string formatAboveSurface(const AboveSurfaceCheck& check) {
  if (check.grid_points == 0) return "above the surface: zero (the cut-off is at or below the surface)\n";
  return "above the surface (" + std::to_string(check.grid_points) +
         " points between the surface and the cut-off): largest wrench " + number(check.largest_above) + " at (phi " +
         number(check.phi) + ", beta " + number(check.beta) + "), " + percent(check.share()) +
         " of the largest below the surface (" + number(check.largest_below) + ")\n";
}

double measuredRms(const Eigen::MatrixXd& relative, const PointSetView& points) {
  double sum2 = 0.0;
  long n = 0;
  for (int i = 0; i < points.pointCount(); ++i) {
    if (points.origin[i] != PointOrigin::Measured || !(points.values.row(i).cwiseAbs().maxCoeff() > 0.0)) continue;
    const double worst = relative.row(i).maxCoeff();
    sum2 += worst * worst;
    ++n;
  }
  return n > 0 ? std::sqrt(sum2 / static_cast<double>(n)) : 0.0;
}

std::optional<FitWarning> looWarning(const Eigen::MatrixXd& loo_relative, const PointSetView& points) {
  const double rms = measuredRms(loo_relative, points);
  if (!(rms > kLooWarnRms)) return std::nullopt;
  Eigen::Index worst_point = 0, worst_vertex = 0;
  double worst = -1.0;
  for (int i = 0; i < points.pointCount(); ++i)
    if (points.origin[i] == PointOrigin::Measured)
      for (Eigen::Index j = 0; j < loo_relative.cols(); ++j)
        if (loo_relative(i, j) > worst) {
          worst = loo_relative(i, j);
          worst_point = i;
          worst_vertex = j;
        }
  FitWarning w;
  w.what = "the leave-one-point-out error is large: RMS " + percent(rms) +
           " over the measured points with a wrench (warned above " + percent(kLooWarnRms) + "), worst " +
           percent(worst) + " at " + featurePointText(points.features, worst_point, 4) + ", vertex " +
           std::to_string(worst_vertex);
  w.suggestion =
      "add samples between the measured ones, where the error is worst first; until then trust the model between "
      "samples only to about this much";
  return w;
}

std::optional<FitWarning> epochLimitWarning(bool stopped_early, int epochs, int total_epochs, int best_epoch,
                                            int patience) {
  if (patience <= 0 || stopped_early || epochs < total_epochs) return std::nullopt;
  FitWarning w;
  w.what = "MLP training stopped at its epoch limit (" + std::to_string(epochs) + " epochs, best epoch " +
           std::to_string(best_epoch) + "): early stopping (patience " + std::to_string(patience) +
           ") never ended it, so the loss was still improving";
  w.suggestion = "raise mlp.max_epochs (or mlp.learning_rate) until early stopping ends the training";
  return w;
}

int loadedValidationPoints(const std::vector<bool>& validation, const PlanarPoints& points) {
  int n = 0;
  for (int i = 0; i < points.pointCount(); ++i)
    if (validation[i] && points.values.row(i).cwiseAbs().maxCoeff() > 0.0) ++n;
  return n;
}

std::optional<FitWarning> validationSizeWarning(const std::vector<bool>& validation, const PlanarPoints& points,
                                                double validation_fraction) {
  if (!(validation_fraction > 0.0)) return std::nullopt;
  const int loaded = loadedValidationPoints(validation, points);
  if (loaded >= kMinValidationPoints) return std::nullopt;
  const long held_out = std::count(validation.begin(), validation.end(), true);
  FitWarning w;
  w.what = "the validation set is too small to mean anything: " + std::to_string(loaded) +
           " validation points carry a wrench (of " + std::to_string(held_out) + " held out; at least " +
           std::to_string(kMinValidationPoints) +
           " wanted), so the validation loss and early stopping are mostly noise";
  w.suggestion = "raise mlp.validation_fraction (now " + number(validation_fraction) +
                 ") or add data; or set it to 0 to train on every point without early stopping";
  return w;
}

}  // namespace nmdp
