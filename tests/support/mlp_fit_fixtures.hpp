// A small MLP fit for the tests: a synthetic wrench data set (K = 4 on a 5 × 5 feature grid) and
// quick settings (2 × 16 tanh, 300 epochs), and the scale of the relative loss.
#pragma once
#include <algorithm>
#include <vector>

#include "fit_fixtures.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace nmdp::test {

inline ForceDataset smallDataset() { return syntheticDataset(4, {-0.04, -0.03, -0.02, -0.01, 0.0}, {-0.6, -0.3, 0.0, 0.3, 0.6}); }

// The relative loss's scale (mlp_fit.hpp): the largest wrench entry over the training points.
inline double largestTrainingWrench(const PlanarPoints& pts, const std::vector<bool>& validation) {
  double largest = 0.0;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!validation[i]) largest = std::max(largest, pts.values.row(i).cwiseAbs().maxCoeff());
  return largest;
}

inline FitConfig quickConfig() {
  FitConfig c;
  c.augmentation.above_heights = {0.02, 0.05};
  c.mlp.hidden_layers = 2;
  c.mlp.width = 16;
  c.mlp.max_epochs = 300;
  c.mlp.learning_rate = 1e-2;
  c.mlp.final_learning_rate = 1e-3;
  c.mlp.validation_fraction = 0.2;
  c.mlp.patience = 0;
  return c;
}

}  // namespace nmdp::test
