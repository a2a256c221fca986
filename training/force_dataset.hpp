// Force datasets (DESIGN.md §9): samples (features, vertex index, wrench), one row per sample. At
// each feature point the samples of vertices 0..K−1 are the wrench-space vertices there (for the
// sand data: the wrench resisting each of 26 probing directions).
//
// ----- HDF5 layout, format_version 1 (readable by h5py) ------------------------------------------
//   /                  attributes:
//       nmdp_dataset     "force_samples" (string)
//       format_version   1 (float64)
//       source           string, free text: where the samples came from (informational)
//       torque_centre    float64, m up the leg from the foot point about which τ_y is taken
//                        (optional; `nmdp fit` stores it in the model file)
//   /features          N×F float64; attributes "names" and "units": comma-separated strings with F
//                      entries, e.g. "phi, beta" and "m, rad"
//   /vertex            N int64 (any numeric type is accepted), ≥ 0: the vertex of each sample
//   /wrench            N×W float64, W = 3 for planar models (F_x, F_z, τ_y in the sagittal plane) or 6
//                      (τ_x, τ_y, τ_z, F_x, F_y, F_z); attributes "names" and "units" as for /features,
//                      e.g. "F_x, F_z, tau_y" and "N, N, N m"
// The RBF and MLP contact models take the features (phi, beta): phi the signed distance of the foot
// point to the terrain (m, negative below), beta the sagittal leg angle (rad).
//
// Validation (readForceDataset, validateForceDataset): every value finite, N ≥ 1 and the same N in
// all three datasets, F ≥ 1, W ∈ {3, 6}, integer vertex indices ≥ 0, as many names and units as
// columns. The first violation is an InputError "FILE: dataset '/x' ..." naming the row.
#pragma once
#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

namespace nmdp {

struct ForceDataset {
  Eigen::MatrixXd features;                               // N×F
  Eigen::VectorXi vertex;                                 // N, the vertex index of each sample
  Eigen::MatrixXd wrench;                                 // N×W
  std::vector<std::string> feature_names, feature_units;  // F each
  std::vector<std::string> wrench_names, wrench_units;    // W each
  std::string source;                                     // free text
  std::optional<double> torque_centre;                    // m, when the data says
};

// The names and units of the two layouts the contact models take: planar, features (phi, beta) in
// (m, rad) and wrench (F_x, F_z, tau_y) in (N, N, N m); spatial, features (phi, beta, gamma) in
// (m, rad, rad) and wrench (tau_x, tau_y, tau_z, F_x, F_y, F_z) in (N m, N m, N m, N, N, N).
struct SampleLayout {
  std::vector<std::string> feature_names, feature_units, wrench_names, wrench_units;
};
const SampleLayout& planarSampleLayout();
const SampleLayout& spatialSampleLayout();
// Sets the dataset's names and units to the layout's.
void applySampleLayout(ForceDataset& data, const SampleLayout& layout);

// Throws InputError "`where`: dataset '/x' ..." on the first inconsistency (see above).
void validateForceDataset(const ForceDataset& data, const std::string& where);

// Reads and validates a dataset file. Throws InputError naming the file and the dataset.
ForceDataset readForceDataset(const std::string& path);

// Validates (naming `path`) and writes the file atomically (path + ".partial", renamed on success).
void writeForceDataset(const std::string& path, const ForceDataset& data);

// Imports the CSV layout of granular/sand_samples (granular/README.md): a folder with
//   features.csv        header "depth,theta", one row per feature point
//   wrench_samples.csv  header "depth,theta,vel_index,fx,fz,wy", one row per sample
//   scalars.txt         lines "name value": Nvel (vertices per point) and Ntheta (points) are
//                       checked; cT, when present, becomes the torque centre
// depth → phi (m), theta → beta (rad), vel_index → vertex, (fx, fz, wy) → (F_x, F_z, tau_y) in
// (N, N, N m). Every sample's point must be listed in features.csv and every point must have
// samples of vertices 0..Nvel−1, once each. Throws InputError naming the file and line.
ForceDataset importSandSamplesCsv(const std::string& folder);

// "a, b, c" ↔ {"a", "b", "c"} (the names/units attributes).
std::string joinNames(const std::vector<std::string>& names);
std::vector<std::string> splitNames(const std::string& text);

}  // namespace nmdp
