#include "training/mlp/mlp_fit.hpp"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>

#include "io/hdf5_file.hpp"
#include "contact_models/rbf_function.hpp"
#include "common/input_error.hpp"
#include "training/fit_config.hpp"
#include "training/rbf_fit.hpp"

namespace nmdp {

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
constexpr double kSoftplusThreshold = 36.0;  // as mlp_function.cpp evaluates it
constexpr int kLbfgsChunk = 10;               // L-BFGS iterations per recorded epoch

torch::Tensor toTensor(const Eigen::MatrixXd& m) {
  RowMatrix r = m;
  return torch::from_blob(r.data(), {static_cast<int64_t>(r.rows()), static_cast<int64_t>(r.cols())},
                          torch::TensorOptions().dtype(torch::kFloat64))
      .clone();
}

torch::Tensor toTensor(const Eigen::VectorXd& v) {
  Eigen::VectorXd c = v;
  return torch::from_blob(c.data(), {static_cast<int64_t>(c.size())}, torch::TensorOptions().dtype(torch::kFloat64))
      .clone();
}

Eigen::MatrixXd toMatrix(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().contiguous();
  return Eigen::Map<const RowMatrix>(c.data_ptr<double>(), c.size(0), c.size(1));
}

Eigen::VectorXd toVector(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().contiguous();
  return Eigen::Map<const Eigen::VectorXd>(c.data_ptr<double>(), c.size(0));
}

// Resets libtorch to one thread (the convention of mlp_function.hpp) on every path out.
struct ThreadGuard {
  explicit ThreadGuard(int threads) { torch::set_num_threads(threads); }
  ~ThreadGuard() { torch::set_num_threads(1); }
};

struct Network {
  std::vector<torch::Tensor> weight, bias;  // out×in, out
  MlpActivation activation;

  torch::Tensor forward(const torch::Tensor& x) const {
    torch::Tensor h = x;
    for (size_t i = 0; i < weight.size(); ++i) {
      h = torch::addmm(bias[i], h, weight[i].t());
      if (i + 1 < weight.size()) {
        switch (activation) {
          case MlpActivation::Tanh: h = torch::tanh(h); break;
          case MlpActivation::Softplus: h = torch::softplus(h, 1.0, kSoftplusThreshold); break;
          case MlpActivation::Silu: h = torch::silu(h); break;
        }
      }
    }
    return h;
  }
  std::vector<torch::Tensor> parameters() const {
    std::vector<torch::Tensor> out;
    for (size_t i = 0; i < weight.size(); ++i) {
      out.push_back(weight[i]);
      out.push_back(bias[i]);
    }
    return out;
  }
};

// Mean over rows and columns of (w ⊙ (y − t))².
torch::Tensor weightedLoss(const torch::Tensor& y, const torch::Tensor& target, const torch::Tensor& w) {
  return (w * (y - target)).square().mean();
}


// The RBF of `rbf` through the training points, sampled on the grid s.teacher_grid over the box of
// the training points at or below the surface (measured and mirrored).
PlanarPoints teacherSamples(const PlanarPoints& points, const std::vector<int>& train, const MlpFitSettings& s,
                            const RbfFitSettings& rbf_settings, const std::string& where) {
  PlanarPoints fitted;
  fitted.features.resize(train.size(), 2);
  fitted.values.resize(train.size(), points.values.cols());
  for (size_t r = 0; r < train.size(); ++r) {
    fitted.features.row(r) = points.features.row(train[r]);
    fitted.values.row(r) = points.values.row(train[r]);
    fitted.origin.push_back(points.origin[train[r]]);
  }
  const RbfFunction rbf(fitRbf(fitted, rbf_settings, where + " (mlp.teacher_grid's RBF)").parameters);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int i = 0; i < fitted.pointCount(); ++i)
    if (fitted.origin[i] != PointOrigin::AboveSurface) {
      lo = lo.cwiseMin(fitted.features.row(i).transpose());
      hi = hi.cwiseMax(fitted.features.row(i).transpose());
    }
  PlanarPoints teacher;
  if (!(lo[0] <= hi[0])) return teacher;  // no point at or below the surface
  const int n0 = s.teacher_grid[0], n1 = s.teacher_grid[1];
  const std::vector<double> rows = teacherDepthRows(lo[0], hi[0], n0, s.teacher_depth_power);
  std::vector<double> columns;
  for (int b = 0; b < n1; ++b) columns.push_back(n1 > 1 ? lo[1] + (hi[1] - lo[1]) * b / (n1 - 1.0) : lo[1]);
  // Extra columns beside the data's angles, where the thin-plate teacher bends sharply (its
  // ρ² log ρ kernel at the zero-wrench surface points).
  if (!s.teacher_refinement.empty()) {
    std::vector<double> data_angles;
    for (int i = 0; i < fitted.pointCount(); ++i)
      if (fitted.origin[i] != PointOrigin::AboveSurface) data_angles.push_back(fitted.features(i, 1));
    std::sort(data_angles.begin(), data_angles.end());
    data_angles.erase(std::unique(data_angles.begin(), data_angles.end()), data_angles.end());
    for (double angle : data_angles)
      for (double offset : s.teacher_refinement)
        for (double c : {angle - offset, angle + offset})
          if (c >= lo[1] && c <= hi[1]) columns.push_back(c);
    std::sort(columns.begin(), columns.end());  // columns closer than 1e-9 rad are one (round-off)
    columns.erase(std::unique(columns.begin(), columns.end(), [](double a, double b) { return b - a <= 1e-9; }),
                  columns.end());
  }
  const int nc = static_cast<int>(columns.size());
  teacher.features.resize(n0 * nc, 2);
  for (int a = 0; a < n0; ++a)
    for (int b = 0; b < nc; ++b) teacher.features.row(a * nc + b) << rows[a], columns[b];
  rbf.evaluate(teacher.features, teacher.values, nullptr, nullptr);
  teacher.origin.assign(n0 * nc, PointOrigin::Measured);
  return teacher;
}
}  // namespace

std::vector<double> teacherDepthRows(double lo, double hi, int n, double power) {
  std::vector<double> rows(std::max(n, 0));
  for (int a = 0; a < n; ++a)
    rows[a] = n < 2 ? lo
              : power == 1.0 ? lo + (hi - lo) * a / (n - 1.0)  // the even grid, as before the option existed
              : a + 1 == n ? hi
                           : lo + (hi - lo) * (1.0 - std::pow(1.0 - a / (n - 1.0), power));
  return rows;
}

MlpFit fitMlp(const PlanarPoints& points, const MlpFitSettings& s, const std::string& where,
              const MlpProgress& progress, const RbfFitSettings* teacher_rbf) {
  if (s.hidden_layers < 0 || s.width < 1 || s.max_epochs < 1 || !(s.learning_rate > 0.0) ||
      !(s.final_learning_rate > 0.0) || s.batch_size < 0 || !(s.validation_fraction >= 0.0 && s.validation_fraction < 1.0) ||
      s.patience < 0 || !(s.weight_decay >= 0.0) || !(s.relative_floor > 0.0) || s.threads < 1 ||
      s.lbfgs_iterations < 0 || s.lbfgs_history < 1 || !(s.teacher_depth_power >= 1.0) ||
      (s.zero_anchors && s.output_envelope == MlpOutputEnvelope::Depth) || !(s.envelope_width > 0.0))
    throw std::invalid_argument("fitMlp: invalid settings (parseFitConfig rejects them)");
  const int P = points.pointCount(), K = points.vertexCount(), O = 3 * K;
  if (P < 2)
    throw InputError(where + ": " + std::to_string(P) +
                     " feature point(s) after augmentation: an MLP fit needs at least 2 (more data, or augmentation)");
  if (K < 1) throw InputError(where + ": no vertices to fit");

  // ---- split by point, stratified by origin and by whether the point carries a wrench -------------
  // (so the validation points that carry one, those that say something about the fit, are a fixed share)
  std::mt19937 rng(s.seed);
  MlpFit fit;
  fit.validation.assign(P, false);
  for (int stratum = 0; stratum < 6; ++stratum) {
    std::vector<int> idx;
    for (int i = 0; i < P; ++i)
      if (2 * static_cast<int>(points.origin[i]) + (points.values.row(i).isZero(0.0) ? 0 : 1) == stratum)
        idx.push_back(i);
    const int n_val = static_cast<int>(std::lround(s.validation_fraction * static_cast<double>(idx.size())));
    for (int i = static_cast<int>(idx.size()) - 1; i > 0; --i) std::swap(idx[i], idx[rng() % static_cast<unsigned>(i + 1)]);
    for (int n = 0; n < n_val; ++n) fit.validation[idx[n]] = true;
  }
  std::vector<int> train, val;
  for (int i = 0; i < P; ++i) (fit.validation[i] ? val : train).push_back(i);
  PlanarPoints teacher_points;
  if (s.teacher_grid[0] > 0) {
    const RbfFitSettings defaults;
    teacher_points = teacherSamples(points, train, s, teacher_rbf ? *teacher_rbf : defaults, where);
  }
  const PlanarPoints* teacher = &teacher_points;
  const int T = teacher_points.pointCount();
  if (train.empty()) {
    std::ostringstream m;
    m << where << ": mlp.validation_fraction " << s.validation_fraction << " holds out all " << P
      << " points (rounded per origin): no point is left to train on; lower it (e.g. 0.1) or set it to 0";
    throw InputError(m.str());
  }

  // ---- normalization over the training points ----------------------------------------------------
  MlpParameters params = randomMlpParameters(s.hidden_layers, s.width, K, s.activation, s.seed);
  const auto rowsOf = [&](const Eigen::MatrixXd& m, const std::vector<int>& rows) {
    Eigen::MatrixXd out(rows.size(), m.cols());
    for (size_t r = 0; r < rows.size(); ++r) out.row(r) = m.row(rows[r]);
    return out;
  };
  // The points, then the teacher samples (always trained on).
  Eigen::MatrixXd F(P + T, 2), Y(P + T, O);
  F.topRows(P) = points.features;
  Y.topRows(P) = points.values;
  if (T > 0) {
    F.bottomRows(T) = teacher->features;
    Y.bottomRows(T) = teacher->values;
    for (int i = 0; i < T; ++i) train.push_back(P + i);
  }
  const Eigen::MatrixXd Ft = rowsOf(F, train), Yt = rowsOf(Y, train);
  const auto stdOf = [](const Eigen::MatrixXd& m, const Eigen::RowVectorXd& mu) {
    Eigen::RowVectorXd sd = ((m.rowwise() - mu).array().square().colwise().sum() / static_cast<double>(m.rows())).sqrt();
    for (Eigen::Index c = 0; c < sd.size(); ++c)
      if (!(sd[c] > 0.0)) sd[c] = 1.0;
    return sd;
  };
  // The inputs are normalized over the training points that carry a wrench: the zero-wrench points
  // above the surface (up to 1 m for the published augmentation, against a few cm of depth) would
  // otherwise squeeze the whole depth range into a sliver of the normalized input.
  std::vector<int> loaded;
  for (int i : train)
    if (Y.row(i).cwiseAbs().maxCoeff() > 0.0) loaded.push_back(i);
  const Eigen::MatrixXd Fl = loaded.size() >= 2 ? rowsOf(F, loaded) : Ft;
  const Eigen::RowVectorXd fmu = Fl.colwise().mean(), ymu = Yt.colwise().mean();
  params.input_mean = fmu.transpose();
  params.input_std = stdOf(Fl, fmu).transpose();
  params.output_offset = ymu.transpose();
  params.output_scale = stdOf(Yt, ymu).transpose();
  params.output_envelope = s.output_envelope;
  if (s.output_envelope == MlpOutputEnvelope::SoftDepth) params.envelope_width = s.envelope_width;
  const bool enveloped = s.output_envelope != MlpOutputEnvelope::None;
  // The envelope's factor m(φ) of every row (fixed: it depends on the inputs only).
  Eigen::VectorXd envelope_col = Eigen::VectorXd::Ones(P + T);
  for (int i = 0; i < P + T; ++i) {
    double dm;
    mlpEnvelopeFactor(s.output_envelope, params.envelope_width, F(i, 0), &envelope_col[i], &dm);
  }
  const Eigen::RowVectorXd w_scale = params.output_scale.transpose();  // the spread of W (the "mse" loss's unit)
  if (enveloped) {
    // The network fits N = W / m(φ): normalized by its mean and spread over the training points
    // below the surface (at φ = 0 the "depth" wrench is (−φ) N = 0 whatever N is).
    std::vector<int> below;
    for (int i : train)
      if (F(i, 0) < 0.0) below.push_back(i);
    if (!below.empty()) {
      Eigen::MatrixXd Nt(below.size(), O);
      for (size_t r = 0; r < below.size(); ++r) Nt.row(r) = Y.row(below[r]) / envelope_col[below[r]];
      const Eigen::RowVectorXd nmu = Nt.colwise().mean();
      params.output_offset = nmu.transpose();
      params.output_scale = stdOf(Nt, nmu).transpose();
    }
  }

  // Zero anchors: the training points whose wrench is exactly zero (mlp_function.hpp). The bumps'
  // radius is the smallest normalized distance between two of them (with a single anchor, to the
  // nearest other training point), so each bump vanishes at the other anchors.
  std::vector<int> anchor_rows;
  if (s.zero_anchors) {
    for (int i : train)
      if (i < P && (Y.row(i).array() == 0.0).all()) anchor_rows.push_back(i);
    const Eigen::Array2d inv_std = params.input_std.cwiseInverse().array();
    const auto distance = [&](int a, int b) {
      return ((F.row(a) - F.row(b)).transpose().array() * inv_std).matrix().norm();
    };
    double radius = std::numeric_limits<double>::infinity();
    for (size_t a = 0; a < anchor_rows.size(); ++a)
      for (size_t b = a + 1; b < anchor_rows.size(); ++b)
        if (const double d = distance(anchor_rows[a], anchor_rows[b]); d > 0.0) radius = std::min(radius, d);
    if (anchor_rows.size() == 1)
      for (int i : train)
        if (const double d = distance(anchor_rows[0], i); d > 0.0) radius = std::min(radius, d);
    if (!anchor_rows.empty() && std::isfinite(radius)) {
      params.anchors = rowsOf(F, anchor_rows);
      params.anchor_radius = radius;
    } else {
      anchor_rows.clear();
    }
  }
  const bool anchored = !anchor_rows.empty();

  // Normalized inputs and targets, the loss weights.
  const Eigen::MatrixXd Xn = (F.rowwise() - params.input_mean.transpose()).array().rowwise() /
                             params.input_std.transpose().array();
  const Eigen::MatrixXd Yn = (Y.rowwise() - params.output_offset.transpose()).array().rowwise() /
                             params.output_scale.transpose().array();
  fit.point_scale = pointScales(points);
  // The loss weights. Without an envelope they multiply the normalized outputs y − ŷ, so they carry
  // output_scale; with an envelope they multiply W − W_data itself.
  const Eigen::RowVectorXd unit =
      enveloped ? Eigen::RowVectorXd(Eigen::RowVectorXd::Ones(O)) : Eigen::RowVectorXd(params.output_scale.transpose());
  Eigen::MatrixXd Wl = enveloped ? Eigen::MatrixXd(w_scale.cwiseInverse().replicate(P + T, 1))
                                      : Eigen::MatrixXd::Ones(P + T, O);
  if (s.loss == MlpLoss::Relative) {
    // Over the training points (the validation points stay unseen): the largest wrench entry and
    // the envelope's factor at its point.
    double largest = 0.0, largest_m = 1.0;
    for (int i : train)
      if (i < P && Y.row(i).cwiseAbs().maxCoeff() > largest) {
        largest = Y.row(i).cwiseAbs().maxCoeff();
        largest_m = envelope_col[i];
      }
    const double floor = s.relative_floor * (largest > 0.0 ? largest : 1.0);
    // With the soft depth envelope the floor follows it: floor · m(min(φ, 0)) / m at the largest
    // wrench's depth, so that near the surface, where the wrench is small, the loss stays relative.
    const bool soft = s.output_envelope == MlpOutputEnvelope::SoftDepth;
    for (int i = 0; i < P + T; ++i) {
      double floor_i = floor;
      if (soft) {
        double m0, dm;
        mlpEnvelopeFactor(s.output_envelope, params.envelope_width, std::min(F(i, 0), 0.0), &m0, &dm);
        floor_i = floor * m0 / largest_m;
      }
      const double si = std::max(Y.row(i).cwiseAbs().maxCoeff(), floor_i);
      Wl.row(i) = unit / si;
    }
    // At the anchors the loss sees the network itself (below): a mild pull towards N(ξ_a) ≈ 0, on
    // the scale of the largest wrench, so a small floor does not let these rows dominate.
    for (int i : anchor_rows) Wl.row(i) = unit / std::max(floor, largest > 0.0 ? largest : 1.0);
  }

  // ---- training ---------------------------------------------------------------------------------
  const ThreadGuard threads(s.threads);
  torch::manual_seed(s.seed);
  torch::AutoGradMode grad_mode(true);
  Network net;
  net.activation = s.activation;
  for (const MlpLayer& l : params.layers) {
    net.weight.push_back(toTensor(l.weight).requires_grad_(true));
    net.bias.push_back(toTensor(l.bias).requires_grad_(true));
  }
  // With an envelope the targets are the wrenches themselves and the network's output is mapped to
  // W = m(φ) ⊙ (output_scale ⊙ y + output_offset) inside the graph.
  const torch::Tensor X_all = toTensor(Xn), Y_all = toTensor(enveloped ? Y : Yn), W_all = toTensor(Wl),
                      D_all = toTensor(Eigen::MatrixXd(envelope_col));  // (P + T) × 1
  const torch::Tensor out_scale = toTensor(params.output_scale).unsqueeze(0),
                      out_offset = toTensor(params.output_offset).unsqueeze(0);
  // With zero anchors the normalized output is y(x) − Σ_a b_a(x) (y(x_a) + offset ⊘ scale), i.e.
  // W = N − Σ_a b_a N(ξ_a) in normalized units. The bumps are zeroed on the anchors' own rows, so there
  // the loss sees the network itself (N(ξ_a) ≈ 0 keeps the correction small and the model smooth),
  // while the anchored model is exactly zero there anyway.
  Eigen::MatrixXd bumps = Eigen::MatrixXd::Zero(P + T, std::max<Eigen::Index>(params.anchors.rows(), 1));
  torch::Tensor X_anchor, anchor_shift;
  if (anchored) {
    mlpAnchorBumps(params, F, bumps);
    for (int i : anchor_rows) bumps.row(i).setZero();
    X_anchor = toTensor(Eigen::MatrixXd((params.anchors.rowwise() - params.input_mean.transpose()).array().rowwise() /
                                        params.input_std.transpose().array()));
    anchor_shift = toTensor(Eigen::VectorXd(params.output_offset.cwiseQuotient(params.output_scale))).unsqueeze(0);
  }
  const torch::Tensor B_all = toTensor(bumps);
  // The loss on rows x (normalized inputs), targets t, weights w, envelope factors m(φ) (column d),
  // bumps b.
  const auto loss = [&](const torch::Tensor& x, const torch::Tensor& t, const torch::Tensor& w, const torch::Tensor& d,
                        const torch::Tensor& b) {
    torch::Tensor y = net.forward(x);
    if (anchored) y = y - torch::mm(b, net.forward(X_anchor) + anchor_shift);
    if (!enveloped) return weightedLoss(y, t, w);
    return weightedLoss(d * (y * out_scale + out_offset), t, w);
  };
  const auto select = [](const torch::Tensor& t, const std::vector<int>& rows) {
    std::vector<int64_t> r(rows.begin(), rows.end());
    return t.index_select(0, torch::tensor(r, torch::kInt64));
  };
  const torch::Tensor Xt = select(X_all, train), Ytn = select(Y_all, train), Wt = select(W_all, train),
                      Dt = select(D_all, train), Bt = select(B_all, train);
  torch::Tensor Xv, Yvn, Wv, Dv, Bv;
  if (!val.empty()) {
    Xv = select(X_all, val);
    Yvn = select(Y_all, val);
    Wv = select(W_all, val);
    Dv = select(D_all, val);
    Bv = select(B_all, val);
  }
  const int n_train = static_cast<int>(train.size());
  const int batch = s.batch_size == 0 ? n_train : std::min(s.batch_size, n_train);

  torch::optim::Adam adam(net.parameters(), torch::optim::AdamOptions(s.learning_rate).weight_decay(s.weight_decay));
  std::vector<torch::Tensor> best;
  for (const torch::Tensor& p : net.parameters()) best.push_back(p.detach().clone());
  double best_loss = std::numeric_limits<double>::infinity();
  std::vector<double> train_hist, val_hist;
  std::vector<int> order(n_train);
  for (int i = 0; i < n_train; ++i) order[i] = i;
  const double decay = std::log(s.final_learning_rate / s.learning_rate);
  const auto start = std::chrono::steady_clock::now();

  // After the Adam epochs, optionally full-batch L-BFGS (strong-Wolfe line search) on the training
  // set, kLbfgsChunk iterations per "epoch" (one history row, one early-stopping check each).
  const int lbfgs_epochs = (s.lbfgs_iterations + kLbfgsChunk - 1) / kLbfgsChunk;
  const int total_epochs = s.max_epochs + lbfgs_epochs;
  fit.total_epochs = total_epochs;
  std::unique_ptr<torch::optim::LBFGS> lbfgs;
  for (int epoch = 1; epoch <= total_epochs; ++epoch) {
    const bool adam_epoch = epoch <= s.max_epochs;
    const double lr = adam_epoch ? s.learning_rate * std::exp(decay * (s.max_epochs > 1 ? (epoch - 1.0) / (s.max_epochs - 1.0) : 0.0))
                                 : 1.0;
    if (adam_epoch)
      for (auto& group : adam.param_groups()) static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
    if (!adam_epoch) {
      const int iterations = std::min(kLbfgsChunk, s.lbfgs_iterations - (epoch - s.max_epochs - 1) * kLbfgsChunk);
      if (!lbfgs)
        lbfgs = std::make_unique<torch::optim::LBFGS>(
            net.parameters(), torch::optim::LBFGSOptions(1.0)
                                  .max_iter(iterations)
                                  .history_size(s.lbfgs_history)
                                  .tolerance_grad(0.0)
                                  .tolerance_change(0.0)
                                  .line_search_fn("strong_wolfe"));
      static_cast<torch::optim::LBFGSOptions&>(lbfgs->param_groups()[0].options()).max_iter(iterations);
      lbfgs->step([&]() {
        lbfgs->zero_grad();
        torch::Tensor l = loss(Xt, Ytn, Wt, Dt, Bt);
        l.backward();
        return l;
      });
    } else if (batch == n_train) {
      adam.zero_grad();
      loss(Xt, Ytn, Wt, Dt, Bt).backward();
      adam.step();
    } else {
      for (int i = n_train - 1; i > 0; --i) std::swap(order[i], order[rng() % static_cast<unsigned>(i + 1)]);
      for (int b = 0; b < n_train; b += batch) {
        const std::vector<int> rows(order.begin() + b, order.begin() + std::min(b + batch, n_train));
        const torch::Tensor xb = select(Xt, rows), yb = select(Ytn, rows), wb = select(Wt, rows),
                            db = select(Dt, rows), bb = select(Bt, rows);
        adam.zero_grad();
        loss(xb, yb, wb, db, bb).backward();
        adam.step();
      }
    }
    double train_loss, val_loss = std::numeric_limits<double>::quiet_NaN();
    {
      torch::NoGradGuard no_grad;
      train_loss = loss(Xt, Ytn, Wt, Dt, Bt).item<double>();
      if (!val.empty()) val_loss = loss(Xv, Yvn, Wv, Dv, Bv).item<double>();
    }
    if (!std::isfinite(train_loss) || (!val.empty() && !std::isfinite(val_loss))) {
      std::ostringstream m;
      m << where << ": MLP training diverged (non-finite loss at epoch " << epoch
        << "): lower mlp.learning_rate (now " << s.learning_rate << ")";
      throw InputError(m.str());
    }
    train_hist.push_back(train_loss);
    val_hist.push_back(val_loss);
    const double picked = val.empty() ? train_loss : val_loss;
    if (picked < best_loss) {
      best_loss = picked;
      fit.best_epoch = epoch;
      const std::vector<torch::Tensor> now = net.parameters();
      for (size_t i = 0; i < now.size(); ++i) best[i].copy_(now[i].detach());
    }
    fit.epochs = epoch;
    if (progress) {
      MlpEpochStatus st;
      st.epoch = epoch;
      st.max_epochs = total_epochs;
      st.train_loss = train_loss;
      st.validation_loss = val_loss;
      st.best_epoch = fit.best_epoch;
      st.best_loss = best_loss;
      st.learning_rate = lr;
      st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      progress(st);
    }
    if (s.patience > 0 && epoch - fit.best_epoch >= s.patience && epoch < total_epochs) {
      fit.stopped_early = true;
      break;
    }
  }

  // ---- the kept weights -------------------------------------------------------------------------
  for (size_t i = 0; i < params.layers.size(); ++i) {
    params.layers[i].weight = toMatrix(best[2 * i]);
    params.layers[i].bias = toVector(best[2 * i + 1]);
  }
  fit.history.resize(fit.epochs, 2);
  for (int e = 0; e < fit.epochs; ++e) fit.history.row(e) << train_hist[e], val_hist[e];
  fit.train_loss = fit.best_epoch > 0 ? train_hist[fit.best_epoch - 1] : 0.0;
  fit.validation_loss = fit.best_epoch > 0 ? val_hist[fit.best_epoch - 1] : std::numeric_limits<double>::quiet_NaN();

  // The error of the model as the contact model will evaluate it.
  const MlpFunction function(params);
  Eigen::MatrixXd W;
  function.evaluate(points.features, W, nullptr, nullptr);
  fit.error = W - points.values;
  fit.teacher_samples = T;
  fit.relative = relativeVertexErrors(fit.error, fit.point_scale);
  fit.parameters = std::move(params);
  return fit;
}

std::string formatMlpFitReport(const MlpFitRecord& r) {
  const PlanarPoints& pts = r.points;
  const MlpFit& fit = r.fit;
  const Eigen::Index P = pts.features.rows(), K = pts.vertexCount();
  std::ostringstream s;
  s << "MLP fit of " << r.data << "\n";
  s << "settings: " << r.settings.dump() << "\n";
  for (const std::string& d : r.from_data) s << "decided from the data: " << d << "\n";
  int counts[3] = {0, 0, 0}, val_counts[3] = {0, 0, 0};
  for (Eigen::Index i = 0; i < P; ++i) {
    ++counts[static_cast<int>(pts.origin[i])];
    if (fit.validation[i]) ++val_counts[static_cast<int>(pts.origin[i])];
  }
  const int n_val = val_counts[0] + val_counts[1] + val_counts[2];
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
    s << std::setw(12) << 100 * max_train << std::defaultfloat << std::setprecision(4) << "   " << worst << " ("
      << pts.features(worst, 0) << ", " << pts.features(worst, 1) << ", " << pointOriginName(pts.origin[worst])
      << (fit.validation[worst] ? ", validation" : ", training") << ")\n";
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
    s << (n ? "," : "") << " " << i << " (" << pts.features(i, 0) << ", " << pts.features(i, 1) << ") " << std::fixed
      << std::setprecision(2) << 100 * per_point[i] << std::defaultfloat << std::setprecision(6);
  }
  s << "\n" << formatAboveSurface(r.above_surface) << formatFitWarnings(r.warnings);
  return s.str();
}

void saveMlpFit(const std::string& path, const MlpFitRecord& r, const PlanarGeometry& geometry) {
  h5::File file = h5::File::createAtomic(path);
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

MlpFitOutcome fitMlpToDataset(const ForceDataset& data, const FitConfig& config, const std::string& data_name,
                              const MlpProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const PlanarPoints grouped = groupPlanarSamples(data, data_name);
  const ResolvedFitConfig resolved = resolveFitConfig(config, data, grouped, data_name);
  const FitConfig& c = resolved.config;
  MlpFitOutcome out;
  out.geometry = fitGeometry(c);
  MlpFitRecord& r = out.record;
  r.points = augment(grouped, c.augmentation);
  r.fit = fitMlp(r.points, c.mlp, data_name, progress, &c.rbf);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.settings = fitConfigJson(c, out.geometry.torque_centre, "mlp");
  r.from_data = resolved.from_data;
  r.data = data_name;
  r.above_surface = checkAboveSurface(MlpFunction(r.fit.parameters), out.geometry, r.points);
  if (auto w = aboveSurfaceWarning(r.above_surface, out.geometry)) r.warnings.push_back(*w);
  if (auto w = epochLimitWarning(r.fit.stopped_early, r.fit.epochs, r.fit.total_epochs, r.fit.best_epoch,
                                 c.mlp.patience))
    r.warnings.push_back(*w);
  if (auto w = validationSizeWarning(r.fit.validation, r.points, c.mlp.validation_fraction)) r.warnings.push_back(*w);
  return out;
}

}  // namespace nmdp
