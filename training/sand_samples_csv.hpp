// Writing a planar force dataset in the CSV layout of granular/sand_samples (granular/README.md),
// the layout importSandSamplesCsv (force_dataset.hpp) reads:
//   features.csv        "depth,theta", one row per feature point, in order of first appearance
//   wrench_samples.csv  "depth,theta,vel_index,fx,fz,wy", the samples of each point in vertex order
//   scalars.txt         "Ntheta P", "Nvel K" and, when the dataset has one, "cT L" (torque centre)
// Numbers are written in the shortest form that reads back to the same double, so the points of the
// two CSV files match exactly.
#pragma once
#include <string>

#include "training/force_dataset.hpp"

namespace nmdp {

// Writes the three files into `folder` (created if missing; existing files of these names are
// replaced). The dataset must be planar (features phi, beta; wrench F_x, F_z, tau_y) with, at every
// point, one sample of each vertex 0..K−1 and the same K everywhere. Throws InputError naming the
// folder or file otherwise.
void writeSandSamplesCsv(const std::string& folder, const ForceDataset& data);

}  // namespace nmdp
