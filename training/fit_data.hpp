// The data `nmdp fit --data` (and the Python nmdp.fit) accepts: a force dataset file (HDF5,
// force_dataset.hpp), a folder in the CSV layout of granular/sand_samples (features.csv,
// wrench_samples.csv, scalars.txt), imported on the fly, or a .csv file in such a folder.
#pragma once
#include <string>

#include "training/force_dataset.hpp"

namespace nmdp {

// Anything else is one InputError "--data PATH: ..." saying what the path is and what is accepted;
// a dataset's own errors are those of readForceDataset and importSandSamplesCsv.
ForceDataset loadFitData(const std::string& path);

}  // namespace nmdp
