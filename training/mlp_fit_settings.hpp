// The settings of an MLP fit (the "mlp" section of FIT.json), apart from the fitting itself
// (training/mlp/mlp_fit.hpp, which needs libtorch), so that configuration code can hold them.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "common/named_enum.hpp"
#include "contact_models/mlp/mlp_function.hpp"

namespace nmdp {

enum class MlpLoss { Relative, Mse };
inline constexpr EnumName<MlpLoss> kMlpLosses[] = {{MlpLoss::Relative, "relative"}, {MlpLoss::Mse, "mse"}};
inline const char* mlpLossName(MlpLoss loss) { return nameOf(kMlpLosses, loss); }

// The "mlp" section of FIT.json (its keys are declared in training/fit_config.cpp, mlpFitFields()).
struct MlpFitSettings {
  int hidden_layers = 2;
  int width = 64;
  MlpActivation activation = MlpActivation::Tanh;
  // A first fit of data like the sand samples (26 points carrying a wrench): 30 % held out gives 8
  // validation points with a wrench (kMinValidationPoints); early stopping ends it after ~2000 epochs
  // (2 s), the learning rate decaying over 10 000.
  int max_epochs = 10000;
  double learning_rate = 1e-2;
  double final_learning_rate = 1e-5;
  int batch_size = 0;  // 0 = full batch
  double validation_fraction = 0.3;
  int patience = 1000;  // epochs without a new best validation loss; 0 = no early stopping
  std::uint32_t seed = 1;
  double weight_decay = 0.0;
  MlpLoss loss = MlpLoss::Relative;
  double relative_floor = 0.05;
  int threads = 1;
  std::array<int, 2> teacher_grid{0, 0};  // n_φ × n_β RBF samples added to the training set; 0 = none
  MlpOutputEnvelope output_envelope = MlpOutputEnvelope::None;  // "depth": W = (−φ) ⊙ N (mlp_function.hpp)
  double envelope_width = 0.005;  // m: w of "soft_depth", W = w softplus(−φ/w) ⊙ N
  int lbfgs_iterations = 0;  // full-batch L-BFGS iterations after the Adam epochs; 0 = none
  int lbfgs_history = 50;    // L-BFGS memory (curvature pairs)
  std::vector<double> teacher_refinement;  // rad: extra teacher columns at each data angle ± these
  double teacher_depth_power = 1.0;  // ≥ 1: teacher rows at φ_lo + (φ_hi − φ_lo)(1 − (1 − t)^p), t uniform
  bool zero_anchors = false;  // anchor the model at the zero-wrench training points (mlp_function.hpp)
};

}  // namespace nmdp
