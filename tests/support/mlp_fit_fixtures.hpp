// A small MLP fit for the tests: a synthetic wrench data set (K = 4 on a 5 × 5 feature grid) and
// quick settings (2 × 16 tanh, 300 epochs), the scale of the relative loss, and the comparison of
// two fits' model files.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "contact_models/mlp/mlp_function.hpp"
#include "fit_fixtures.hpp"
#include "io/hdf5_file.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace nmdp::test {

inline ForceDataset smallDataset() { return syntheticDataset(4, {-0.04, -0.03, -0.02, -0.01, 0.0}, {-0.6, -0.3, 0.0, 0.3, 0.6}); }

// The relative loss's scale (mlp_fit.hpp): the largest wrench entry over the training points.
template <class Points>
inline double largestTrainingWrench(const Points& pts, const std::vector<bool>& validation) {
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

// The model files of two fits hold the same network and /fit report (`same`) or different ones.
inline void expectSameModelFiles(const std::string& a, const std::string& b, bool same) {
  const MlpModelFile ma = loadMlpModel(a), mb = loadMlpModel(b);
  bool equal = ma.parameters.input_mean == mb.parameters.input_mean &&
               ma.parameters.input_std == mb.parameters.input_std &&
               ma.parameters.output_scale == mb.parameters.output_scale &&
               ma.parameters.output_offset == mb.parameters.output_offset &&
               ma.parameters.layers.size() == mb.parameters.layers.size();
  for (size_t i = 0; equal && i < ma.parameters.layers.size(); ++i)
    equal = ma.parameters.layers[i].weight == mb.parameters.layers[i].weight &&
            ma.parameters.layers[i].bias == mb.parameters.layers[i].bias;
  EXPECT_EQ(equal, same) << a << " vs " << b;
  const h5::File fa = h5::File::openRead(a), fb = h5::File::openRead(b);
  for (const char* d : {"/fit/history", "/fit/error", "/fit/validation"})
    EXPECT_EQ(fa.readMatrix(d) == fb.readMatrix(d), same) << d;
}

}  // namespace nmdp::test
