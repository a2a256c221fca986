#include <torch/torch.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "common/input_error.hpp"
#include "training/mlp/mlp_training.hpp"

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

Network networkOf(const MlpParameters& params, MlpActivation activation) {
  Network net;
  net.activation = activation;
  for (const MlpLayer& l : params.layers) {
    net.weight.push_back(toTensor(l.weight).requires_grad_(true));
    net.bias.push_back(toTensor(l.bias).requires_grad_(true));
  }
  return net;
}

// Mean over rows and columns of (w ⊙ (y − t))².
torch::Tensor weightedLoss(const torch::Tensor& y, const torch::Tensor& target, const torch::Tensor& w) {
  return (w * (y - target)).square().mean();
}


torch::Tensor selectRows(const torch::Tensor& t, const std::vector<int>& rows) {
  std::vector<int64_t> r(rows.begin(), rows.end());
  return t.index_select(0, torch::tensor(r, torch::kInt64));
}

// One set of rows as tensors: inputs x, targets t, loss weights w, envelope factors d, bumps b.
struct Batch {
  torch::Tensor x, t, w, d, b;
  Batch select(const std::vector<int>& rows) const {
    return {selectRows(x, rows), selectRows(t, rows), selectRows(w, rows), selectRows(d, rows), selectRows(b, rows)};
  }
};

// The network and the loss of fitMlp, in libtorch.
class MlpTrainer {
 public:
  MlpTrainer(const MlpTrainingRows& rows, const MlpFitSettings& s, const MlpParameters& params);
  // One epoch (1-based): Adam over the training rows (full batch or shuffled mini-batches) while
  // epoch ≤ max_epochs, then L-BFGS chunks. Returns the learning rate used.
  double runEpoch(int epoch, std::mt19937& rng);
  torch::Tensor loss(const Batch& b);
  const Batch& train() const { return train_; }
  const Batch& validation() const { return validation_; }
  bool hasValidation() const { return has_validation_; }
  std::vector<torch::Tensor> parameters() const { return net_.parameters(); }

 private:
  const MlpFitSettings& s_;
  Network net_;
  bool enveloped_, anchored_, has_validation_;
  torch::Tensor out_scale_, out_offset_, X_anchor_, anchor_shift_;
  Batch train_, validation_;
  int n_train_, batch_;
  std::vector<int> order_;
  double decay_;
  torch::optim::Adam adam_;
  std::unique_ptr<torch::optim::LBFGS> lbfgs_;
};

// With an envelope the targets are the wrenches themselves and the network's output is mapped to
// W = m(φ) ⊙ (output_scale ⊙ y + output_offset) inside the graph. With zero anchors the normalized
// output is y(x) − Σ_a b_a(x) (y(x_a) + offset ⊘ scale), i.e. W = N − Σ_a b_a N(ξ_a) in normalized
// units; the bumps are zeroed on the anchors' own rows, so there the loss sees the network itself.
MlpTrainer::MlpTrainer(const MlpTrainingRows& rows, const MlpFitSettings& s, const MlpParameters& params)
    : s_(s),
      net_(networkOf(params, s.activation)),
      enveloped_(rows.enveloped),
      anchored_(rows.anchored),
      has_validation_(!rows.validation.empty()),
      adam_(net_.parameters(), torch::optim::AdamOptions(s.learning_rate).weight_decay(s.weight_decay)) {
  const Batch all{toTensor(rows.inputs), toTensor(rows.targets), toTensor(rows.weights),
                  toTensor(Eigen::MatrixXd(rows.envelope)), torch::Tensor()};
  out_scale_ = toTensor(params.output_scale).unsqueeze(0);
  out_offset_ = toTensor(params.output_offset).unsqueeze(0);
  if (anchored_) {
    X_anchor_ = toTensor(Eigen::MatrixXd((params.anchors.rowwise() - params.input_mean.transpose()).array().rowwise() /
                                         params.input_std.transpose().array()));
    anchor_shift_ = toTensor(Eigen::VectorXd(params.output_offset.cwiseQuotient(params.output_scale))).unsqueeze(0);
  }
  Batch with_bumps = all;
  with_bumps.b = toTensor(rows.bumps);
  train_ = with_bumps.select(rows.train);
  if (has_validation_) validation_ = with_bumps.select(rows.validation);
  n_train_ = static_cast<int>(rows.train.size());
  batch_ = s.batch_size == 0 ? n_train_ : std::min(s.batch_size, n_train_);
  order_.resize(n_train_);
  for (int i = 0; i < n_train_; ++i) order_[i] = i;
  decay_ = std::log(s.final_learning_rate / s.learning_rate);
}

torch::Tensor MlpTrainer::loss(const Batch& b) {
  torch::Tensor y = net_.forward(b.x);
  if (anchored_) y = y - torch::mm(b.b, net_.forward(X_anchor_) + anchor_shift_);
  if (!enveloped_) return weightedLoss(y, b.t, b.w);
  return weightedLoss(b.d * (y * out_scale_ + out_offset_), b.t, b.w);
}

double MlpTrainer::runEpoch(int epoch, std::mt19937& rng) {
  const bool adam_epoch = epoch <= s_.max_epochs;
  const double lr = adam_epoch ? s_.learning_rate * std::exp(decay_ * (s_.max_epochs > 1 ? (epoch - 1.0) / (s_.max_epochs - 1.0) : 0.0))
                               : 1.0;
  if (adam_epoch)
    for (auto& group : adam_.param_groups()) static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
  if (!adam_epoch) {
    const int iterations = std::min(kLbfgsChunk, s_.lbfgs_iterations - (epoch - s_.max_epochs - 1) * kLbfgsChunk);
    if (!lbfgs_)
      lbfgs_ = std::make_unique<torch::optim::LBFGS>(net_.parameters(), torch::optim::LBFGSOptions(1.0)
                                                                            .max_iter(iterations)
                                                                            .history_size(s_.lbfgs_history)
                                                                            .tolerance_grad(0.0)
                                                                            .tolerance_change(0.0)
                                                                            .line_search_fn("strong_wolfe"));
    static_cast<torch::optim::LBFGSOptions&>(lbfgs_->param_groups()[0].options()).max_iter(iterations);
    lbfgs_->step([&]() {
      lbfgs_->zero_grad();
      torch::Tensor l = loss(train_);
      l.backward();
      return l;
    });
  } else if (batch_ == n_train_) {
    adam_.zero_grad();
    loss(train_).backward();
    adam_.step();
  } else {
    for (int i = n_train_ - 1; i > 0; --i) std::swap(order_[i], order_[rng() % static_cast<unsigned>(i + 1)]);
    for (int b = 0; b < n_train_; b += batch_) {
      const std::vector<int> rows(order_.begin() + b, order_.begin() + std::min(b + batch_, n_train_));
      adam_.zero_grad();
      loss(train_.select(rows)).backward();
      adam_.step();
    }
  }
  return lr;
}

}  // namespace

void trainMlp(const MlpTrainingRows& rows, const MlpFitSettings& s, std::mt19937& rng, const std::string& where,
              const MlpProgress& progress, MlpParameters& params, MlpFit& fit) {
  MlpTrainer trainer(rows, s, params);
  std::vector<torch::Tensor> best;
  for (const torch::Tensor& p : trainer.parameters()) best.push_back(p.detach().clone());
  double best_loss = std::numeric_limits<double>::infinity();
  std::vector<double> train_hist, val_hist;
  const auto start = std::chrono::steady_clock::now();
  // After the Adam epochs, optionally full-batch L-BFGS (strong-Wolfe line search) on the training
  // set, kLbfgsChunk iterations per "epoch" (one history row, one early-stopping check each).
  const int lbfgs_epochs = (s.lbfgs_iterations + kLbfgsChunk - 1) / kLbfgsChunk;
  const int total_epochs = s.max_epochs + lbfgs_epochs;
  fit.total_epochs = total_epochs;
  for (int epoch = 1; epoch <= total_epochs; ++epoch) {
    const double lr = trainer.runEpoch(epoch, rng);
    double train_loss, val_loss = std::numeric_limits<double>::quiet_NaN();
    {
      torch::NoGradGuard no_grad;
      train_loss = trainer.loss(trainer.train()).item<double>();
      if (trainer.hasValidation()) val_loss = trainer.loss(trainer.validation()).item<double>();
    }
    if (!std::isfinite(train_loss) || (trainer.hasValidation() && !std::isfinite(val_loss))) {
      std::ostringstream m;
      m << where << ": MLP training diverged (non-finite loss at epoch " << epoch
        << "): lower mlp.learning_rate (now " << s.learning_rate << ")";
      throw InputError(m.str());
    }
    train_hist.push_back(train_loss);
    val_hist.push_back(val_loss);
    const double picked = trainer.hasValidation() ? val_loss : train_loss;
    if (picked < best_loss) {
      best_loss = picked;
      fit.best_epoch = epoch;
      const std::vector<torch::Tensor> now = trainer.parameters();
      for (size_t i = 0; i < now.size(); ++i) best[i].copy_(now[i].detach());
    }
    fit.epochs = epoch;
    if (progress) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      progress({epoch, total_epochs, train_loss, val_loss, fit.best_epoch, best_loss, lr, seconds});
    }
    if (s.patience > 0 && epoch - fit.best_epoch >= s.patience && epoch < total_epochs) {
      fit.stopped_early = true;
      break;
    }
  }
  for (size_t i = 0; i < params.layers.size(); ++i) {
    params.layers[i].weight = toMatrix(best[2 * i]);
    params.layers[i].bias = toVector(best[2 * i + 1]);
  }
  fit.history.resize(fit.epochs, 2);
  for (int e = 0; e < fit.epochs; ++e) fit.history.row(e) << train_hist[e], val_hist[e];
  fit.train_loss = fit.best_epoch > 0 ? train_hist[fit.best_epoch - 1] : 0.0;
  fit.validation_loss = fit.best_epoch > 0 ? val_hist[fit.best_epoch - 1] : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace nmdp
