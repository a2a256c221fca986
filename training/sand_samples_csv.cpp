#include "training/sand_samples_csv.hpp"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>
#include <system_error>
#include <vector>

#include "common/input_error.hpp"
#include "io/output_path.hpp"

namespace nmdp {

namespace {
// Shortest round-trip text of a double.
std::string text(double x) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, r.ptr);
}

// Under a unique temporary name, renamed into place (io/output_path.hpp).
void writeFile(const std::filesystem::path& path, const std::string& content) { writeFileAtomically(path.string(), content); }
}  // namespace

void writeSandSamplesCsv(const std::string& folder, const ForceDataset& data) {
  namespace fs = std::filesystem;
  validateForceDataset(data, folder);
  if (data.features.cols() != 2 || data.wrench.cols() != 3)
    throw InputError(folder + ": the sand-samples layout holds planar data (2 features depth, theta and 3 wrench "
                     "columns fx, fz, wy), this dataset has " + std::to_string(data.features.cols()) + " and " +
                     std::to_string(data.wrench.cols()));
  // Points in order of first appearance, and each point's samples by vertex.
  std::map<std::pair<double, double>, size_t> index;
  std::vector<std::pair<double, double>> points;
  std::vector<std::vector<Eigen::Index>> rows;  // rows[p][v] = sample row, −1 if none
  const int K = data.vertex.maxCoeff() + 1;
  for (Eigen::Index i = 0; i < data.features.rows(); ++i) {
    const auto key = std::make_pair(data.features(i, 0), data.features(i, 1));
    auto [it, added] = index.emplace(key, points.size());
    if (added) {
      points.push_back(key);
      rows.emplace_back(K, -1);
    }
    Eigen::Index& slot = rows[it->second][data.vertex[i]];
    if (slot >= 0)
      throw InputError(folder + ": row " + std::to_string(i) + " repeats vertex " + std::to_string(data.vertex[i]) +
                       " of the point (" + text(key.first) + ", " + text(key.second) + ")");
    slot = i;
  }
  for (size_t p = 0; p < points.size(); ++p)
    for (int v = 0; v < K; ++v)
      if (rows[p][v] < 0)
        throw InputError(folder + ": the point (" + text(points[p].first) + ", " + text(points[p].second) +
                         ") has no sample of vertex " + std::to_string(v) + " (the layout needs all " +
                         std::to_string(K) + " at every point)");

  std::error_code ec;
  fs::create_directories(folder, ec);
  if (!fs::is_directory(folder, ec)) throw InputError(folder + ": cannot create the folder");
  std::string features = "depth,theta\n", samples = "depth,theta,vel_index,fx,fz,wy\n";
  for (size_t p = 0; p < points.size(); ++p) {
    const std::string point = text(points[p].first) + "," + text(points[p].second);
    features += point + "\n";
    for (int v = 0; v < K; ++v) {
      const Eigen::Index i = rows[p][v];
      samples += point + "," + std::to_string(v) + "," + text(data.wrench(i, 0)) + "," + text(data.wrench(i, 1)) +
                 "," + text(data.wrench(i, 2)) + "\n";
    }
  }
  std::string scalars = "Ntheta " + std::to_string(points.size()) + "\nNvel " + std::to_string(K) + "\n";
  if (data.torque_centre) scalars += "cT " + text(*data.torque_centre) + "\n";
  writeFile(fs::path(folder) / "features.csv", features);
  writeFile(fs::path(folder) / "wrench_samples.csv", samples);
  writeFile(fs::path(folder) / "scalars.txt", scalars);
}

}  // namespace nmdp
