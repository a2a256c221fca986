// Contact model files written by the tests, each in a unique temporary folder: a small synthetic
// RBF in the published format (N = 3 centres, K = 4 vertices) and in the project's HDF5 layout, an
// MLP file written without validation (to store shapes that do not chain, NaNs), a valid small
// random MLP (K = 5), and the model configurations naming them.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>

#include "contact_models/mlp/mlp_function.hpp"
#include "io/hdf5_file.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {

// A small synthetic RBF in the published format: N = 3 centres, K = 4 vertices.
inline constexpr int kRbfCentres = 3;
inline constexpr int kRbfVertices = 4;

inline std::string publishedInputs() { return "# depth theta\n-0.04 0.0\n-0.02 0.3\n0.0 -0.3\n"; }

// K·N lines "fx fz wy" (vertex v, centre i on line v*N + i); `lines` < K·N truncates.
inline std::string publishedWeights(int lines = kRbfCentres * kRbfVertices) {
  std::ostringstream s;
  s.precision(17);
  for (int v = 0; v < kRbfVertices; ++v)
    for (int i = 0; i < kRbfCentres; ++i) {
      if (v * kRbfCentres + i >= lines) return s.str();
      const double base = 1.0 + v + 0.5 * i;
      s << (i % 2 ? -1.0 : 1.0) * 20.0 * base << " " << 40.0 * base * (v % 2 ? 0.5 : 1.0) << " " << 0.3 * (v - i) << "\n";
    }
  return s.str();
}

// Writes the published RBF folder `name` (inputs.txt, weights.txt) and returns its path.
inline std::string writePublishedRbf(const TempDir& dir, const std::string& name, const std::string& weights = publishedWeights()) {
  dir.write(name + "/inputs.txt", publishedInputs());
  dir.write(name + "/weights.txt", weights);
  return dir.file(name);
}

// An HDF5 RBF file in the project's layout with the given weights (not validated).
inline std::string writeRbfHdf5(const TempDir& dir, const std::string& name, const Eigen::MatrixXd& weights) {
  const std::string path = dir.file(name);
  Eigen::MatrixXd centres(kRbfCentres, 2);
  centres << -0.04, 0.0, -0.02, 0.3, 0.0, -0.3;
  h5::File file = h5::File::createAtomic(path);
  file.writeStringAttribute("/", "nmdp_model", "rbf");
  file.createGroup("/rbf");
  file.writeDoubleAttribute("/rbf", "format_version", 1.0);
  file.writeDoubleAttribute("/rbf", "epsilon", 1.0);
  file.writeDoubleAttribute("/rbf", "torque_centre", 0.1);
  file.writeDoubleAttribute("/rbf", "cutoff", 0.1);
  file.writeDoubleAttribute("/rbf", "cutoff_width", 0.02);
  file.writeMatrix("/rbf/centres", centres);
  file.writeMatrix("/rbf/weights", weights);
  file.writeStrings("/rbf/kernel", {"thin_plate"});
  file.writeVector("/rbf/scaling", Eigen::Vector2d(5.0, 1.0));
  file.writeStrings("/rbf/feature_names", {"phi", "beta"});
  file.commit();
  return path;
}

// An HDF5 MLP file in the layout of mlp_function.hpp, written without validation (so that shapes
// that do not chain and NaNs can be stored); `vertices` is the attribute, whatever the layers say.
inline std::string writeMlpHdf5Raw(const TempDir& dir, const std::string& name, const MlpParameters& p, int vertices) {
  const std::string path = dir.file(name);
  h5::File file = h5::File::createAtomic(path);
  file.writeStringAttribute("/", "nmdp_model", "mlp");
  file.createGroup("/mlp");
  file.writeDoubleAttribute("/mlp", "format_version", 1.0);
  file.writeStringAttribute("/mlp", "activation", "tanh");
  file.writeDoubleAttribute("/mlp", "layers", static_cast<double>(p.layers.size()));
  file.writeDoubleAttribute("/mlp", "vertices", vertices);
  file.writeStringAttribute("/mlp", "wrench", "planar");
  file.writeDoubleAttribute("/mlp", "torque_centre", 0.1);
  file.writeDoubleAttribute("/mlp", "cutoff", 0.1);
  file.writeDoubleAttribute("/mlp", "cutoff_width", 0.02);
  file.writeStrings("/mlp/feature_names", {"phi", "beta"});
  const std::pair<const char*, Eigen::VectorXd> vectors[] = {{"input_mean", p.input_mean}, {"input_std", p.input_std},
                                                              {"output_scale", p.output_scale},
                                                              {"output_offset", p.output_offset}};
  for (const auto& [key, vector] : vectors) file.writeVector(std::string("/mlp/") + key, vector);
  for (size_t i = 0; i < p.layers.size(); ++i) {
    const std::string layer = "/mlp/layer_" + std::to_string(i);
    file.createGroup(layer);
    file.writeMatrix(layer + "/weight", p.layers[i].weight);
    file.writeVector(layer + "/bias", p.layers[i].bias);
  }
  file.commit();
  return path;
}

inline constexpr int kMlpVertices = 5;

// A valid small random MLP (2-8-15 tanh, K = 5) saved with saveMlpModel.
inline std::string writeRandomMlp(const TempDir& dir, const std::string& name, std::uint32_t seed = 7) {
  const std::string path = dir.file(name);
  PlanarGeometry g;
  g.torque_centre = 0.1;
  g.cutoff = 0.1;
  g.cutoff_width = 0.02;
  MlpParameters p = randomMlpParameters(1, 8, kMlpVertices, MlpActivation::Tanh, seed);
  p.output_scale.setConstant(50.0);  // forces of tens of N, like the sand data
  saveMlpModel(path, p, g);
  return path;
}

inline nlohmann::json rbfConfig(const std::string& file) { return {{"type", "rbf"}, {"file", file}}; }
inline nlohmann::json mlpConfig(const std::string& file) { return {{"type", "mlp"}, {"file", file}}; }

}  // namespace nmdp::test
