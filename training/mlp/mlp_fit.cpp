#include "training/mlp/mlp_fit.hpp"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "io/hdf5_file.hpp"
#include "training/fit_config.hpp"
#include "training/mlp/mlp_training.hpp"
#include "training/rbf_fit.hpp"

namespace nmdp {

namespace {

// Resets libtorch to one thread (the convention of mlp_function.hpp) on every path out.
struct ThreadGuard {
  explicit ThreadGuard(int threads) { torch::set_num_threads(threads); }
  ~ThreadGuard() { torch::set_num_threads(1); }
};

void requireValidSettings(const MlpFitSettings& s) {
  if (s.hidden_layers < 0 || s.width < 1 || s.max_epochs < 1 || !(s.learning_rate > 0.0) ||
      !(s.final_learning_rate > 0.0) || s.batch_size < 0 || !(s.validation_fraction >= 0.0 && s.validation_fraction < 1.0) ||
      s.patience < 0 || !(s.weight_decay >= 0.0) || !(s.relative_floor > 0.0) || s.threads < 1 ||
      s.lbfgs_iterations < 0 || s.lbfgs_history < 1 || !(s.teacher_depth_power >= 1.0) ||
      (s.zero_anchors && s.output_envelope == MlpOutputEnvelope::Depth) || !(s.envelope_width > 0.0))
    throw std::invalid_argument("fitMlp: invalid settings (parseFitConfig rejects them)");
}

// Split by point, stratified by origin and by whether the point carries a wrench (so the validation
// points that carry one, those that say something about the fit, are a fixed share).
void splitForValidation(const MlpPoints& points, double fraction, std::mt19937& rng, std::vector<bool>& validation,
                        std::vector<int>& train, std::vector<int>& val) {
  const int P = points.pointCount();
  validation.assign(P, false);
  for (int stratum = 0; stratum < 6; ++stratum) {
    std::vector<int> idx;
    for (int i = 0; i < P; ++i)
      if (2 * static_cast<int>(points.origin[i]) + (points.values.row(i).isZero(0.0) ? 0 : 1) == stratum)
        idx.push_back(i);
    const int n_val = static_cast<int>(std::lround(fraction * static_cast<double>(idx.size())));
    for (int i = static_cast<int>(idx.size()) - 1; i > 0; --i) std::swap(idx[i], idx[rng() % static_cast<unsigned>(i + 1)]);
    for (int n = 0; n < n_val; ++n) validation[idx[n]] = true;
  }
  for (int i = 0; i < P; ++i) (validation[i] ? val : train).push_back(i);
}

Eigen::MatrixXd rowsOf(const Eigen::MatrixXd& m, const std::vector<int>& rows) {
  Eigen::MatrixXd out(rows.size(), m.cols());
  for (size_t r = 0; r < rows.size(); ++r) out.row(r) = m.row(rows[r]);
  return out;
}

Eigen::RowVectorXd stdOf(const Eigen::MatrixXd& m, const Eigen::RowVectorXd& mu) {
  Eigen::RowVectorXd sd = ((m.rowwise() - mu).array().square().colwise().sum() / static_cast<double>(m.rows())).sqrt();
  for (Eigen::Index c = 0; c < sd.size(); ++c)
    if (!(sd[c] > 0.0)) sd[c] = 1.0;
  return sd;
}

// All rows before normalization: the points, then the teacher samples (always trained on).
struct RawRows {
  int P = 0, T = 0;
  Eigen::MatrixXd F, Y;      // features (φ, β[, γ]) and wrenches
  Eigen::VectorXd envelope;  // m(φ) of every row
  std::vector<int> train;    // the training points and the teacher rows
};

RawRows stackRows(const MlpPoints& points, const PlanarPoints& teacher, std::vector<int> train) {
  RawRows raw;
  raw.P = points.pointCount();
  raw.T = teacher.pointCount();
  const int P = raw.P, T = raw.T;
  raw.F.resize(P + T, points.features.cols());
  raw.Y.resize(P + T, points.values.cols());
  raw.F.topRows(P) = points.features;
  raw.Y.topRows(P) = points.values;
  if (T > 0) {
    raw.F.bottomRows(T) = teacher.features;
    raw.Y.bottomRows(T) = teacher.values;
    for (int i = 0; i < T; ++i) train.push_back(P + i);
  }
  raw.train = std::move(train);
  return raw;
}

// Input and output normalization over the training rows, into params; the envelope's factor of
// every row into raw.envelope. Returns the spread of W over the training rows (the "mse" loss's unit).
Eigen::RowVectorXd normalize(RawRows& raw, const MlpFitSettings& s, MlpParameters& params) {
  const Eigen::MatrixXd& F = raw.F;
  const Eigen::MatrixXd& Y = raw.Y;
  const Eigen::MatrixXd Ft = rowsOf(F, raw.train), Yt = rowsOf(Y, raw.train);
  // The inputs are normalized over the training points that carry a wrench: the zero-wrench points
  // above the surface (up to 1 m for the published augmentation, against a few cm of depth) would
  // otherwise squeeze the whole depth range into a sliver of the normalized input.
  std::vector<int> loaded;
  for (int i : raw.train)
    if (Y.row(i).cwiseAbs().maxCoeff() > 0.0) loaded.push_back(i);
  const Eigen::MatrixXd Fl = loaded.size() >= 2 ? rowsOf(F, loaded) : Ft;
  const Eigen::RowVectorXd fmu = Fl.colwise().mean(), ymu = Yt.colwise().mean();
  params.input_mean = fmu.transpose();
  params.input_std = stdOf(Fl, fmu).transpose();
  params.output_offset = ymu.transpose();
  params.output_scale = stdOf(Yt, ymu).transpose();
  params.output_envelope = s.output_envelope;
  if (s.output_envelope == MlpOutputEnvelope::SoftDepth) params.envelope_width = s.envelope_width;
  const int rows = static_cast<int>(F.rows());
  raw.envelope = Eigen::VectorXd::Ones(rows);
  for (int i = 0; i < rows; ++i) {
    double dm;
    mlpEnvelopeFactor(s.output_envelope, params.envelope_width, F(i, 0), &raw.envelope[i], &dm);
  }
  const Eigen::RowVectorXd w_scale = params.output_scale.transpose();
  if (s.output_envelope != MlpOutputEnvelope::None) {
    // The network fits N = W / m(φ): normalized by its mean and spread over the training points
    // below the surface (at φ = 0 the "depth" wrench is (−φ) N = 0 whatever N is).
    std::vector<int> below;
    for (int i : raw.train)
      if (F(i, 0) < 0.0) below.push_back(i);
    if (!below.empty()) {
      Eigen::MatrixXd Nt(below.size(), Y.cols());
      for (size_t r = 0; r < below.size(); ++r) Nt.row(r) = Y.row(below[r]) / raw.envelope[below[r]];
      const Eigen::RowVectorXd nmu = Nt.colwise().mean();
      params.output_offset = nmu.transpose();
      params.output_scale = stdOf(Nt, nmu).transpose();
    }
  }
  return w_scale;
}

// Zero anchors: the training points whose wrench is exactly zero (mlp_function.hpp). The bumps'
// radius is the smallest normalized distance between two of them (with a single anchor, to the
// nearest other training point), so each bump vanishes at the other anchors. Returns their rows
// (none when there is no usable radius).
template <int F>
std::vector<int> chooseAnchors(const RawRows& raw, MlpParameters& params) {
  std::vector<int> anchor_rows;
  for (int i : raw.train)
    if (i < raw.P && (raw.Y.row(i).array() == 0.0).all()) anchor_rows.push_back(i);
  const Eigen::Array<double, F, 1> inv_std = params.input_std.head<F>().cwiseInverse().array();
  const auto distance = [&](int a, int b) {
    return ((raw.F.row(a) - raw.F.row(b)).transpose().array() * inv_std).matrix().norm();
  };
  double radius = std::numeric_limits<double>::infinity();
  for (size_t a = 0; a < anchor_rows.size(); ++a)
    for (size_t b = a + 1; b < anchor_rows.size(); ++b)
      if (const double d = distance(anchor_rows[a], anchor_rows[b]); d > 0.0) radius = std::min(radius, d);
  if (anchor_rows.size() == 1)
    for (int i : raw.train)
      if (const double d = distance(anchor_rows[0], i); d > 0.0) radius = std::min(radius, d);
  if (anchor_rows.empty() || !std::isfinite(radius)) return {};
  params.anchors = rowsOf(raw.F, anchor_rows);
  params.anchor_radius = radius;
  return anchor_rows;
}

// The loss weights. Without an envelope they multiply the normalized outputs y − ŷ, so they carry
// output_scale; with an envelope they multiply W − W_data itself.
Eigen::MatrixXd lossWeights(const RawRows& raw, const MlpFitSettings& s, const MlpParameters& params,
                            const Eigen::RowVectorXd& w_scale, const std::vector<int>& anchor_rows) {
  const bool enveloped = s.output_envelope != MlpOutputEnvelope::None;
  const Eigen::Index rows = raw.F.rows(), O = raw.Y.cols();
  const Eigen::RowVectorXd unit =
      enveloped ? Eigen::RowVectorXd(Eigen::RowVectorXd::Ones(O)) : Eigen::RowVectorXd(params.output_scale.transpose());
  Eigen::MatrixXd Wl = enveloped ? Eigen::MatrixXd(w_scale.cwiseInverse().replicate(rows, 1))
                                 : Eigen::MatrixXd::Ones(rows, O);
  if (s.loss != MlpLoss::Relative) return Wl;
  // Over the training points (the validation points stay unseen): the largest wrench entry and
  // the envelope's factor at its point.
  double largest = 0.0, largest_m = 1.0;
  for (int i : raw.train)
    if (i < raw.P && raw.Y.row(i).cwiseAbs().maxCoeff() > largest) {
      largest = raw.Y.row(i).cwiseAbs().maxCoeff();
      largest_m = raw.envelope[i];
    }
  const double floor = s.relative_floor * (largest > 0.0 ? largest : 1.0);
  // With the soft depth envelope the floor follows it: floor · m(min(φ, 0)) / m at the largest
  // wrench's depth, so that near the surface, where the wrench is small, the loss stays relative.
  const bool soft = s.output_envelope == MlpOutputEnvelope::SoftDepth;
  for (Eigen::Index i = 0; i < rows; ++i) {
    double floor_i = floor;
    if (soft) {
      double m0, dm;
      mlpEnvelopeFactor(s.output_envelope, params.envelope_width, std::min(raw.F(i, 0), 0.0), &m0, &dm);
      floor_i = floor * m0 / largest_m;
    }
    const double si = std::max(raw.Y.row(i).cwiseAbs().maxCoeff(), floor_i);
    Wl.row(i) = unit / si;
  }
  // At the anchors the loss sees the network itself: a mild pull towards N(ξ_a) ≈ 0, on the scale
  // of the largest wrench, so a small floor does not let these rows dominate.
  for (int i : anchor_rows) Wl.row(i) = unit / std::max(floor, largest > 0.0 ? largest : 1.0);
  return Wl;
}

// The values of the model as the contact model evaluates them, either kind.
Eigen::MatrixXd modelValues(const MlpFunction& function, const Eigen::MatrixXd& features) {
  Eigen::MatrixXd W;
  if (function.wrench() == MlpWrench::Spatial)
    function.evaluate(Eigen::MatrixX3d(features), W, nullptr);
  else
    function.evaluate(Eigen::MatrixX2d(features), W, nullptr, nullptr);
  return W;
}

}  // namespace

MlpFit fitMlp(const PlanarPoints& points, const MlpFitSettings& s, const std::string& where,
              const MlpProgress& progress, const RbfFitSettings* teacher_rbf) {
  return fitMlp(mlpPoints(points), s, where, progress, teacher_rbf);
}

MlpFit fitMlp(const MlpPoints& points, const MlpFitSettings& s, const std::string& where,
              const MlpProgress& progress, const RbfFitSettings* teacher_rbf) {
  requireValidSettings(s);
  if (points.features.cols() != points.featureCount() || points.values.cols() % points.wrenchWidth() != 0)
    throw std::invalid_argument("fitMlp: the points' features or values do not match their kind");
  const int P = points.pointCount(), K = points.vertexCount();
  if (P < 2)
    throw InputError(where + ": " + std::to_string(P) +
                     " feature point(s) after augmentation: an MLP fit needs at least 2 (more data, or augmentation)");
  if (K < 1) throw InputError(where + ": no vertices to fit");
  std::mt19937 rng(s.seed);
  MlpFit fit;
  std::vector<int> train, val;
  splitForValidation(points, s.validation_fraction, rng, fit.validation, train, val);
  PlanarPoints teacher;
  if (s.teacher_grid[0] > 0) {
    if (points.wrench != MlpWrench::Planar)
      throw InputError(where + ": mlp.teacher_grid is for planar data (an RBF of (phi, beta)); leave it out for 3-D data");
    const RbfFitSettings defaults;
    teacher = mlpTeacherSamples(planarPoints(points), train, s, teacher_rbf ? *teacher_rbf : defaults, where);
  }
  if (train.empty()) {
    std::ostringstream m;
    m << where << ": mlp.validation_fraction " << s.validation_fraction << " holds out all " << P
      << " points (rounded per origin): no point is left to train on; lower it (e.g. 0.1) or set it to 0";
    throw InputError(m.str());
  }
  MlpParameters params = randomMlpParameters(s.hidden_layers, s.width, K, s.activation, s.seed, points.wrench);
  RawRows raw = stackRows(points, teacher, train);
  const Eigen::RowVectorXd w_scale = normalize(raw, s, params);
  const std::vector<int> anchor_rows = !s.zero_anchors                      ? std::vector<int>{}
                                       : points.wrench == MlpWrench::Spatial ? chooseAnchors<3>(raw, params)
                                                                             : chooseAnchors<2>(raw, params);

  MlpTrainingRows rows;
  rows.enveloped = s.output_envelope != MlpOutputEnvelope::None;
  rows.anchored = !anchor_rows.empty();
  rows.inputs = (raw.F.rowwise() - params.input_mean.transpose()).array().rowwise() / params.input_std.transpose().array();
  rows.targets = rows.enveloped ? raw.Y
                                : Eigen::MatrixXd((raw.Y.rowwise() - params.output_offset.transpose()).array().rowwise() /
                                                  params.output_scale.transpose().array());
  fit.point_scale = mlpPointScales(points);
  rows.weights = lossWeights(raw, s, params, w_scale, anchor_rows);
  rows.envelope = raw.envelope;
  rows.train = raw.train;
  rows.validation = val;

  const ThreadGuard threads(s.threads);
  torch::manual_seed(s.seed);
  torch::AutoGradMode grad_mode(true);
  rows.bumps = Eigen::MatrixXd::Zero(raw.P + raw.T, std::max<Eigen::Index>(params.anchors.rows(), 1));
  if (rows.anchored) {
    mlpAnchorBumps(params, raw.F, rows.bumps);
    for (int i : anchor_rows) rows.bumps.row(i).setZero();
  }
  trainMlp(rows, s, rng, where, progress, params, fit);

  // The error of the model as the contact model will evaluate it.
  fit.error = modelValues(MlpFunction(params), points.features) - points.values;
  fit.teacher_samples = raw.T;
  fit.relative = mlpRelativeVertexErrors(fit.error, fit.point_scale, points.wrenchWidth());
  fit.parameters = std::move(params);
  return fit;
}

void saveMlpFit(const std::string& path, const MlpFitRecord& r, const PlanarGeometry& geometry) {
  h5::File file = h5::File::createAtomic(path);
  if (r.fit.parameters.wrench == MlpWrench::Spatial)
    writeMlpModel(file, r.fit.parameters, SpatialGeometry{geometry.cutoff, geometry.cutoff_width});
  else
    writeMlpModel(file, r.fit.parameters, geometry);
  file.createGroup("/fit");
  file.writeStringAttribute("/fit", "data", r.data);
  file.writeStringAttribute("/fit", "settings", r.settings.dump());
  file.writeStringAttribute("/fit", "report", formatMlpFitReport(r));
  file.writeDoubleAttribute("/fit", "seconds", r.seconds);
  file.writeDoubleAttribute("/fit", "epochs", r.fit.epochs);
  file.writeDoubleAttribute("/fit", "best_epoch", r.fit.best_epoch);
  file.writeDoubleAttribute("/fit", "train_loss", r.fit.train_loss);
  file.writeDoubleAttribute("/fit", "validation_loss", r.fit.validation_loss);
  std::string from_data;
  for (const std::string& d : r.from_data) from_data += d + "\n";
  file.writeStringAttribute("/fit", "from_data", from_data);
  file.writeStringAttribute("/fit", "warnings", r.warnings.empty() ? "" : formatFitWarnings(r.warnings));
  file.writeDoubleAttribute("/fit", "above_surface_share", r.above_surface.share());
  file.writeMatrix("/fit/points", r.points.features);
  const Eigen::Index P = r.points.pointCount();
  Eigen::VectorXi origin(P), validation(P);
  for (Eigen::Index i = 0; i < P; ++i) {
    origin[i] = static_cast<int>(r.points.origin[i]);
    validation[i] = r.fit.validation[i] ? 1 : 0;
  }
  file.writeIntegerVector("/fit/origin", origin);
  file.writeIntegerVector("/fit/validation", validation);
  file.writeMatrix("/fit/values", r.points.values);
  file.writeMatrix("/fit/error", r.fit.error);
  file.writeMatrix("/fit/relative_error", r.fit.relative);
  file.writeMatrix("/fit/history", r.fit.history);
  file.commit();
}

namespace {

// fitMlpToDataset for a 3-D dataset (mlp_fit.hpp).
MlpFitOutcome fitSpatialMlpToDataset(const ForceDataset& data, const FitConfig& c, const std::string& data_name,
                                     const MlpProgress& progress, std::chrono::steady_clock::time_point start) {
  if (c.torque_centre)
    throw InputError(data_name + ": torque_centre is for planar models; a spatial MLP's torque is about the foot point "
                     "(leave it out for 3-D data)");
  MlpFitOutcome out;
  out.geometry = PlanarGeometry{0.0, c.cutoff.value_or(0.0), c.cutoff_width.value_or(SpatialGeometry{}.cutoff_width)};
  if (!(out.geometry.cutoff_width > 0.0))
    throw InputError(data_name + ": cutoff_width must be positive (m), got " + std::to_string(out.geometry.cutoff_width));
  MlpFitRecord& r = out.record;
  r.points = groupSpatialMlpSamples(data, data_name);
  r.fit = fitMlp(r.points, c.mlp, data_name, progress, &c.rbf);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  FitConfig recorded = c;
  recorded.cutoff = out.geometry.cutoff;
  recorded.cutoff_width = out.geometry.cutoff_width;
  r.settings = fitConfigJson(recorded, 0.0, "mlp");
  r.settings.erase("torque_centre");
  r.settings.erase("augmentation");  // 3-D points are fitted as they are
  r.data = data_name;
  if (auto w = epochLimitWarning(r.fit.stopped_early, r.fit.epochs, r.fit.total_epochs, r.fit.best_epoch,
                                 c.mlp.patience))
    r.warnings.push_back(*w);
  return out;
}

}  // namespace

MlpFitOutcome fitMlpToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name,
                              const MlpProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (isSpatialMlpDataset(data)) return fitSpatialMlpToDataset(data, config, data_name, progress, start);
  const PlanarPoints grouped = groupPlanarSamples(data, data_name);
  const ResolvedFitConfig resolved = resolveFitConfig(config, data, grouped, data_name);
  const FitConfig& c = resolved.config;
  MlpFitOutcome out;
  out.geometry = fitGeometry(c);
  MlpFitRecord& r = out.record;
  const PlanarPoints augmented = augment(grouped, c.augmentation);
  r.points = mlpPoints(augmented);
  r.fit = fitMlp(augmented, c.mlp, data_name, progress, &c.rbf);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.settings = fitConfigJson(c, out.geometry.torque_centre, "mlp");
  r.from_data = resolved.from_data;
  r.data = data_name;
  r.above_surface = checkAboveSurface(MlpFunction(r.fit.parameters), out.geometry, augmented);
  if (auto w = aboveSurfaceWarning(r.above_surface, out.geometry)) r.warnings.push_back(*w);
  if (auto w = epochLimitWarning(r.fit.stopped_early, r.fit.epochs, r.fit.total_epochs, r.fit.best_epoch,
                                 c.mlp.patience))
    r.warnings.push_back(*w);
  if (auto w = validationSizeWarning(r.fit.validation, augmented, c.mlp.validation_fraction)) r.warnings.push_back(*w);
  return out;
}

}  // namespace nmdp
