// MLP fitting of planar and spatial wrench spaces (DESIGN.md §7.3, §9): a multilayer perceptron of
// contact_models/mlp/mlp_function.hpp trained with libtorch on the points of a force dataset (for
// planar data the augmented points the RBF fit interpolates: groupPlanarSamples + augment; for 3-D
// data the grouped points as they are, mlp_points.hpp), so the result is an MlpFunction that the
// "mlp" contact model loads as it is. Everything below holds for both kinds with (φ, β) read as the
// F features and "3K outputs" as wK (w = 6 for spatial data); the teacher grid is planar only.
//
// Training (fitMlp):
//   * normalization, stored in the model: input_mean/input_std = mean and standard deviation of
//     (φ, β) over the training points with a non-zero wrench (all training points if fewer than 2
//     have one: the zero-wrench points up to 1 m above the surface would squeeze the few cm of depth
//     into a sliver of the normalized input); output_offset/output_scale = mean and standard deviation of
//     each of the 3K outputs over the training points (scale 1 where an output is constant), so the
//     network fits values of order 1;
//   * output envelope (mlp.output_envelope, "none" by default): with "depth" the model is
//     W = (−φ) ⊙ N (contact_models/mlp/mlp_function.hpp), zero at the surface. output_offset/output_scale
//     are then the mean and standard deviation of W_data / (−φ) over the training points below the
//     surface (φ < 0), so N is of order 1, and the loss below is evaluated on W = (−φ) ⊙ N against
//     W_data inside the torch graph (points at φ = 0 contribute exactly zero error; "mse" divides by
//     the standard deviation of each W output). The teacher grid, the report, /fit, validation and early
//     stopping all work on W unchanged. "soft_depth" (width w = envelope_width) is the same with the
//     factor m(φ) = w softplus(−φ/w) instead of −φ: the network fits W / m, whose size varies far less
//     than W's over the depths (the granular wrench grows about linearly with depth), so one absolute
//     accuracy of N is about one relative accuracy of W. It goes with the zero anchors (the factor
//     multiplies the anchored network). With it the relative loss's floor follows the factor:
//     relative_floor · S · m(min(φ_i, 0)) / m(φ_S), φ_S the depth of the largest wrench, so that near
//     the surface, where the wrench is small, the loss stays relative;
//   * split by feature point, stratified by origin (measured, mirrored, above the surface) and by
//     whether the point carries a wrench: of each stratum's points round(validation_fraction · count)
//     go to validation, picked by a Fisher–Yates shuffle driven by std::mt19937(seed) (portable:
//     rng() % n, not std::shuffle);
//   * the network starts from randomMlpParameters(hidden_layers, width, K, activation, seed) (torch's
//     default initialization, reproducible on every platform); torch::manual_seed(seed) is set too,
//     though nothing in the trainer draws from torch's generator;
//   * the loss: the mean over the training points and outputs of
//         ((W_fit − W_data)_c / s_i)²,   s_i = max(largest |W_data| entry at point i, relative_floor · S)
//     with S the largest |W_data| entry of the training points ("relative", the default: the error relative to
//     the largest wrench at the point, what the report and the acceptance measure; the floor keeps the
//     zero-wrench points above the surface from dominating), or ((W_fit − W_data)_c / output_scale_c)²
//     ("mse": plain mean squared error of the normalized outputs);
//   * Adam (torch::optim::Adam, weight_decay as Adam's L2 term), in float64, full batch
//     (batch_size 0) or mini-batches reshuffled every epoch by the same std::mt19937; the learning
//     rate decays exponentially from learning_rate to final_learning_rate over max_epochs;
//   * teacher grid (optional, mlp.teacher_grid [n_φ, n_β], off by default): the RBF of the "rbf"
//     section (rbf_fit.hpp) is fitted to the training points (not the validation points) and sampled on an n_φ × n_β grid
//     over the box of the training points at or below the surface; these samples are added to the training
//     set (never to validation). A network trained on ~100 scattered points alone interpolates
//     between them quite differently from a thin-plate spline (training/README.md has the numbers);
//     the teacher pins it to the smooth interpolant in between;
//   * L-BFGS (optional, lbfgs_iterations > 0): after the Adam epochs, torch::optim::LBFGS (lr 1,
//     strong-Wolfe line search, lbfgs_history pairs, no tolerance stop) on the whole training set,
//     10 iterations per recorded epoch (one history row and one early-stopping check each);
//   * zero anchors (optional, zero_anchors): the training points whose wrench is exactly zero become
//     the anchors of mlp_function.hpp, radius R = the smallest normalized distance between two of
//     them (one anchor: to the nearest other training point), so the model is exactly zero there. The
//     loss is that of the anchored model (in the torch graph), except on the anchors' own rows, where
//     it is the network itself relative to the largest wrench S (a mild pull to N(ξ_a) ≈ 0 that keeps
//     the correction, and the wrench just above the surface, small);
//   * teacher_depth_power p ≥ 1: the teacher grid's rows at φ_lo + (φ_hi − φ_lo)(1 − (1 − t)^p)
//     (teacherDepthRows), denser towards the surface for p > 1;
//   * teacher_refinement (angle offsets, none by default): more teacher columns at each angle of the
//     training points at or below the surface ± each offset (inside the grid's angle range; columns
//     within 1e-9 rad of another are dropped), on every row. A thin-plate teacher bends sharply
//     (ρ² log ρ) next to its zero-wrench surface points, where the wrench is small and any error
//     is large relative to it;
//   * early stopping: after every epoch the loss on the validation points; the weights of the best
//     epoch are kept and restored at the end; training stops after `patience` epochs without a new
//     best (0: never early). Without validation points (validation_fraction 0) "best" is the lowest
//     training loss (evaluated after the epoch's step on the whole training set).
// Determinism: with the same data and settings the result is identical bit for bit (the tests write
// the model twice and compare the files) as long as libtorch runs on one thread (threads = 1, the
// default; more threads may change the summation order of the BLAS and so the last bits).
// fitMlp sets torch::set_num_threads(threads) and resets it to 1 on return, the convention of
// mlp_function.hpp. The library never prints: progress goes to an optional callback.
#pragma once
#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/mlp/mlp_function.hpp"
#include "training/mlp/mlp_points.hpp"
#include "training/mlp_fit_settings.hpp"
#include "training/augmentation.hpp"
#include "training/fit_warnings.hpp"

namespace nmdp {

// What the callback sees after every epoch (1-based epochs).
struct MlpEpochStatus {
  int epoch = 0, max_epochs = 0;
  double train_loss = 0.0;       // on the training points, after the epoch's steps
  double validation_loss = 0.0;  // NaN without validation points
  int best_epoch = 0;
  double best_loss = 0.0;  // the loss that picks the best epoch (validation, else training)
  double learning_rate = 0.0;
  double seconds = 0.0;  // since the start of training
};
using MlpProgress = std::function<void(const MlpEpochStatus&)>;

struct MlpFit {
  MlpParameters parameters;         // the best epoch's weights with the normalization
  std::vector<bool> validation;     // P: the point was held out
  int epochs = 0;                   // epochs run
  int total_epochs = 0;             // the limit: max_epochs + the L-BFGS epochs
  int best_epoch = 0;               // whose weights were kept (0: the initial network)
  bool stopped_early = false;       // patience ran out before max_epochs
  double train_loss = 0.0;          // of the kept weights
  double validation_loss = 0.0;     // of the kept weights; NaN without validation points
  Eigen::MatrixX2d history;         // epochs × 2: training and validation loss of every epoch
  Eigen::MatrixXd error;            // P×wK: W_fit − W_data at every point (training and validation)
  Eigen::MatrixXd relative;         // P×K: max over the vertex's w entries of |error| / point_scale
  Eigen::VectorXd point_scale;      // P: the largest |W_data| entry at the point (of all at zero points)
  int teacher_samples = 0;          // extra training samples (teacher grid)
};

// Trains a network on the points. Throws InputError "`where`: mlp.KEY ..." when the settings leave
// no training point (validation_fraction too large for the number of points) or fewer than 2 points
// are given, std::invalid_argument on settings parseFitConfig rejects (zero epochs, a width < 1...).
// `teacher_rbf`: the RBF settings of the teacher grid (settings.teacher_grid; default RbfFitSettings
// when null). The teacher RBF is fitted to the training points only, so validation stays unseen.
// Spatial points train a spatial network; settings.teacher_grid is then an InputError (planar only).
struct RbfFitSettings;
MlpFit fitMlp(const MlpPoints& points, const MlpFitSettings& settings, const std::string& where,
              const MlpProgress& progress = {}, const RbfFitSettings* teacher_rbf = nullptr);
MlpFit fitMlp(const PlanarPoints& points, const MlpFitSettings& settings, const std::string& where,
              const MlpProgress& progress = {}, const RbfFitSettings* teacher_rbf = nullptr);

// The depths φ of the teacher grid's n rows between lo and hi (the surface side): lo + (hi − lo)(1 − (1 − t)^power),
// t = 0, 1/(n − 1), ..., 1 (the last row exactly hi; n = 1: lo). power 1 spaces them evenly, more packs them
// towards hi, where the sand wrench changes fastest (mlp.teacher_depth_power).
std::vector<double> teacherDepthRows(double lo, double hi, int n, double power);

// What a fit records, as RbfFitRecord does for the RBF.
struct MlpFitRecord {
  nlohmann::ordered_json settings;  // every key with the value used (fitConfigJson(..., "mlp"))
  MlpPoints points;                 // planar (augmented) or spatial
  MlpFit fit;
  std::string data;
  double seconds = 0;  // wall time of augmentation and training
  std::vector<std::string> from_data;  // the settings decided from the data (resolveFitConfig)
  AboveSurfaceCheck above_surface;     // the model between the surface and the cut-off
  std::vector<FitWarning> warnings;    // above the surface, the epoch limit, the validation size
};

// The report printed after a fit and stored in the model file: the settings, the sizes (points by
// origin, training/validation, network, parameters), the epochs, the losses and the error per vertex
// relative to the largest wrench at each point: largest and RMS over the validation points, largest
// over the training points, the worst point; then the worst validation points, the model's largest
// wrench above the surface and the warnings (fit_warnings.hpp).
std::string formatMlpFitReport(const MlpFitRecord& record);

// Writes the model file of contact_models/mlp/mlp_function.hpp, which the "mlp" contact model loads as
// it is, plus a group /fit (ignored by loadMlpModel):
//   /fit                attributes: data, settings (JSON text), report (text), seconds, epochs,
//                       best_epoch, train_loss, validation_loss, from_data (text, one decided
//                       setting a line), warnings (text, as in the report), above_surface_share
//   /fit/points         P×F float64 (φ, β[, γ]), the (augmented) points
//   /fit/origin         P int64: 0 measured, 1 mirrored, 2 above the surface
//   /fit/validation     P int64: 1 held out for validation, 0 trained on
//   /fit/values         P×wK float64, the data fitted
//   /fit/error          P×wK float64, the fit minus the data
//   /fit/relative_error P×K float64, relative to the largest wrench at the point
//   /fit/history        epochs × 2 float64, training and validation loss per epoch
// Atomically (path + ".partial", renamed on success). A spatial fit is written as a spatial model
// (geometry.torque_centre unused).
void saveMlpFit(const std::string& path, const MlpFitRecord& record, const PlanarGeometry& geometry);

// The whole MLP pipeline on a dataset, as fitRbfToDataset (fit_config.hpp) for the RBF: group by
// point, decide what the configuration leaves to the data, augment, train with config.mlp, check
// (fit_warnings.hpp), with the settings and the timing recorded. Throws
// InputError for bad data (groupPlanarSamples), a missing torque centre, or settings that leave no
// training point. A 3-D dataset (isSpatialMlpDataset) is grouped by groupSpatialMlpSamples and fitted
// without augmentation; its cut-off is config.cutoff (default 0: zero at and above the surface) over
// config.cutoff_width (default 5 mm), the torque centre does not apply (an InputError when given),
// and the above-surface check is skipped (the cut-off zeroes the model there).
struct FitConfig;
struct MlpFitOutcome {
  MlpFitRecord record;
  PlanarGeometry geometry;  // a spatial fit's cut-off and band, torque_centre 0 (unused)
  bool spatial() const { return record.fit.parameters.wrench == MlpWrench::Spatial; }
  SpatialGeometry spatialGeometry() const { return SpatialGeometry{geometry.cutoff, geometry.cutoff_width}; }
};
MlpFitOutcome fitMlpToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name,
                              const MlpProgress& progress = {});

}  // namespace nmdp
