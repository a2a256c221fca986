// Shared by the fitting tests (test_fit, test_mlp_fit, test_fit_cli): FIT.json files of the
// repository, a synthetic planar force dataset, a check on error messages, and the comparison
// with the published sand model that the RBF and MLP acceptances share.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/rbf_function.hpp"
#include "test_support.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"

namespace nmdp::test {

// Every one of `parts` occurs in `message` (an error message names the file, the key, the value...).
inline void expectAll(const std::string& message, const std::vector<std::string>& parts) {
  for (const std::string& p : parts)
    EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

// A FIT.json of the repository (path relative to its root), parsed as `nmdp fit --config` would.
inline FitConfig fitConfigFile(const std::string& rel) {
  const std::string path = sourcePath(rel);
  std::ifstream in(path);
  return parseFitConfig(nlohmann::json::parse(in), {path, ""});
}

// A configuration that adds nothing to the data (left out, mirror and the zero-wrench heights are
// decided from the data).
inline FitConfig noAugmentation() {
  FitConfig c;
  c.augmentation.mirror = false;
  c.augmentation.above_heights = std::vector<double>{};
  return c;
}

// A planar dataset: the points phis × betas, K vertices each, smooth made-up wrenches that vanish
// above the surface.
inline ForceDataset syntheticDataset(int K, const std::vector<double>& phis, const std::vector<double>& betas) {
  ForceDataset d;
  const int P = static_cast<int>(phis.size() * betas.size());
  d.features.resize(P * K, 2);
  d.vertex.resize(P * K);
  d.wrench.resize(P * K, 3);
  int row = 0;
  for (double phi : phis)
    for (double beta : betas)
      for (int v = 0; v < K; ++v, ++row) {
        d.features.row(row) << phi, beta;
        d.vertex[row] = v;
        const double depth = std::max(0.0, -phi);
        d.wrench.row(row) << depth * 100 * std::sin(v + beta), depth * 1000 * (1.5 + std::cos(v - beta)),
            depth * std::cos(3 * v + beta);
      }
  d.feature_names = {"phi", "beta"};
  d.feature_units = {"m", "rad"};
  d.wrench_names = {"F_x", "F_z", "tau_y"};
  d.wrench_units = {"N", "N", "N m"};
  d.source = "synthetic";
  d.torque_centre = 0.05;
  return d;
}

// The published sand model, ../shared/granular/robosimian_sand_rbf (the caller checks it is there).
inline RbfFunction publishedSandModel() {
  const std::string dir = sharedPath("granular/robosimian_sand_rbf");
  return RbfFunction(readPublishedRbf(dir + "/inputs.txt", dir + "/weights.txt"));
}

// The acceptance points: 2000 random (depth, angle) of the valid range, depth −0.07..0, angle
// −0.9..0.9, the same every run.
inline Eigen::MatrixX2d acceptancePoints() {
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> depth(-0.07, 0.0), angle(-0.9, 0.9);
  Eigen::MatrixX2d f(2000, 2);
  for (Eigen::Index i = 0; i < f.rows(); ++i) f.row(i) << depth(rng), angle(rng);
  return f;
}

// Per point, the largest |W − W_pub| entry divided by the largest |W_pub| entry there ("within x %
// of the largest wrench at the point"); infinity, and a failure, where W_pub is zero.
inline std::vector<double> errorRelativeToPublished(const Eigen::MatrixX2d& f, const Eigen::MatrixXd& W,
                                                     const Eigen::MatrixXd& W_pub) {
  std::vector<double> e(f.rows());
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const double largest = W_pub.row(i).cwiseAbs().maxCoeff();
    EXPECT_GT(largest, 0.0) << "at " << f.row(i);
    e[i] = largest > 0.0 ? (W.row(i) - W_pub.row(i)).cwiseAbs().maxCoeff() / largest
                         : std::numeric_limits<double>::infinity();
  }
  return e;
}

}  // namespace nmdp::test
