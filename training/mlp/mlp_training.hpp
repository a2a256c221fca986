// The steps of fitMlp (training/mlp/mlp_fit.hpp) that it composes: the teacher samples and the
// libtorch training loop (Adam epochs with a decaying learning rate, then optionally L-BFGS, early
// stopping on the validation loss).
#pragma once
#include <random>
#include <string>
#include <vector>

#include "training/mlp/mlp_fit.hpp"

namespace nmdp {

// The RBF of `rbf_settings` through the training points `train`, sampled on the grid s.teacher_grid
// over the box of the training points at or below the surface (measured and mirrored).
PlanarPoints mlpTeacherSamples(const PlanarPoints& points, const std::vector<int>& train, const MlpFitSettings& s,
                               const RbfFitSettings& rbf_settings, const std::string& where);

// Every row the loss sees (the points, then the teacher samples), in Eigen.
struct MlpTrainingRows {
  Eigen::MatrixXd inputs;    // normalized inputs
  Eigen::MatrixXd targets;   // normalized outputs, or the wrenches themselves with an envelope
  Eigen::MatrixXd weights;   // the loss weights
  Eigen::VectorXd envelope;  // the envelope's factor m(φ) of each row (1 without an envelope)
  Eigen::MatrixXd bumps;     // the zero anchors' bumps b_a(x) (zero on the anchors' own rows)
  std::vector<int> train, validation;  // row indices
  bool enveloped = false;
  bool anchored = false;
};

// Trains the network whose initial weights are params.layers and replaces them by the weights of
// the best epoch; fills fit's epochs, best_epoch, total_epochs, stopped_early, history and losses.
// `rng` shuffles the mini-batches (continuing the split's stream).
void trainMlp(const MlpTrainingRows& rows, const MlpFitSettings& s, std::mt19937& rng, const std::string& where,
              const MlpProgress& progress, MlpParameters& params, MlpFit& fit);

}  // namespace nmdp
