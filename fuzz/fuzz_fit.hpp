// What `nmdp fit --model rbf` does with a dataset, for the fuzz targets of the data formats: group,
// augment and fit, when the augmented points are few enough for an input to take milliseconds.
#pragma once
#include <string>

#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"

namespace nmdp::fuzz {

inline void fitIfSmall(const ForceDataset& data, const FitConfig& config, const std::string& name) {
  constexpr Eigen::Index kMostSamples = 2000;  // ~80 points of 26 vertices: a fit of a few ms
  if (data.features.rows() > kMostSamples) return;
  fitRbfToDataset(data, config, name);
}

}  // namespace nmdp::fuzz
