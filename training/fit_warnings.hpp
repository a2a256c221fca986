// The warnings of a fit report (`nmdp fit`): checks of a fitted model that a first fit can fail
// without any error, each a finding with its numbers and a one-line suggestion, printed with the
// report and stored in the model file's /fit group (rbf_fit.hpp, mlp_fit.hpp).
//   * above the surface: the model (cut-off applied) on a grid of heights between the surface and
//     the cut-off, over the fitted points' angles, pushes more than 1 % of the largest wrench below
//     the surface (a foot in the air would be pushed);
//   * RBF, leave-one-point-out: over the measured points that carry a wrench, the RMS of each one's
//     leave-one-point-out error (its worst vertex, relative to its largest wrench) exceeds 25 %
//     (the data does not pin the model down between its samples);
//   * MLP, epoch limit: early stopping was on (patience > 0) and never stopped the training;
//   * MLP, validation: fewer than 8 validation points carry a wrench, so the validation loss (and
//     the early stopping it drives) is mostly noise.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "contact_models/planar_wrench_model.hpp"
#include "training/augmentation.hpp"

namespace nmdp {

struct FitWarning {
  std::string what;        // the finding, with its numbers
  std::string suggestion;  // one line: what to do about it
};

// "warnings: none" or one "warning: <what>" line and one "  suggestion: ..." line per warning.
std::string formatFitWarnings(const std::vector<FitWarning>& warnings);

// ---- above the surface -----------------------------------------------------------------------------
// The share of the largest wrench below the surface that the model may push above it unwarned.
constexpr double kAboveSurfaceWarnShare = 0.01;
// The grid: heights cutoff · k / kAboveSurfaceHeights, k = 1 .. kAboveSurfaceHeights − 1 (the cut-off
// itself is zero by construction), times kAboveSurfaceAngles angles evenly over the fitted points'
// range of β (both ends included).
constexpr int kAboveSurfaceHeights = 20;
constexpr int kAboveSurfaceAngles = 91;

struct AboveSurfaceCheck {
  int grid_points = 0;          // 0 when the cut-off is at or below the surface: nothing to check
  double largest_above = 0.0;   // the largest |entry| of σ(φ) W(φ, β) on the grid
  double phi = 0.0, beta = 0.0; // where it is
  double largest_below = 0.0;   // the largest |entry| of the fitted values at φ ≤ 0
  double share() const { return largest_below > 0.0 ? largest_above / largest_below : 0.0; }
};
// `model` is the fitted feature function, `geometry` the cut-off stored with it, `points` the
// fitted (augmented) points.
AboveSurfaceCheck checkAboveSurface(const FeatureWrenchFunction& model, const PlanarGeometry& geometry,
                                    const PlanarPoints& points);
std::optional<FitWarning> aboveSurfaceWarning(const AboveSurfaceCheck& check, const PlanarGeometry& geometry);
// One report line: the largest wrench on the grid, where, and its share of the largest below.
std::string formatAboveSurface(const AboveSurfaceCheck& check);

// ---- RBF: leave-one-point-out error ----------------------------------------------------------------
// The leave-one-point-out RMS above which the report warns: left-out samples missed by a quarter of
// their wrench on average say the samples are too far apart for the interpolant between them to
// mean much. (The sand samples, 1–2 cm and 0.3 rad apart, give about 50 %.)
constexpr double kLooWarnRms = 0.25;
// `relative`: P×K relative errors (RbfFit::loo_relative); the RMS over the measured points with a
// non-zero wrench of each one's largest entry (0 without such points).
// Planar or spatial points (the warning names the point by all its features).
double measuredRms(const Eigen::MatrixXd& relative, const PointSetView& points);
inline double measuredRms(const Eigen::MatrixXd& relative, const PlanarPoints& points) {
  return measuredRms(relative, viewOf(points));
}
std::optional<FitWarning> looWarning(const Eigen::MatrixXd& loo_relative, const PointSetView& points);
inline std::optional<FitWarning> looWarning(const Eigen::MatrixXd& loo_relative, const PlanarPoints& points) {
  return looWarning(loo_relative, viewOf(points));
}


// ---- MLP: training ---------------------------------------------------------------------------------
// The fewest validation points that carry a wrench for the validation loss to mean something: with
// n points the RMS error is known to about 1/√(2n), ±25 % at 8 (±50 % at 2). The zero-wrench points
// do not count (they are fitted easily and say nothing about the wrench).
constexpr int kMinValidationPoints = 8;
// Early stopping on (patience > 0) that did not stop the training before `total_epochs`.
std::optional<FitWarning> epochLimitWarning(bool stopped_early, int epochs, int total_epochs, int best_epoch,
                                            int patience);
// `validation`: per point, held out. Nothing when validation_fraction is 0 (no validation by choice).
std::optional<FitWarning> validationSizeWarning(const std::vector<bool>& validation, const PlanarPoints& points,
                                                double validation_fraction);
int loadedValidationPoints(const std::vector<bool>& validation, const PlanarPoints& points);

}  // namespace nmdp
