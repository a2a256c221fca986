// 3-D RBF feature functions built in code for tests and benchmarks: a smooth "sphere pressed into
// sand" formula interpolated on the planned grid (9 depths × 5 tilt nodes, the 26 default motion
// directions), and random functions of any size for the derivative checks.
#pragma once
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "contact_models/rbf_basis.hpp"
#include "contact_models/spatial_rbf_function.hpp"

namespace nmdp::test {

// The 26 unit directions (i, j, k) ∈ {−1, 0, 1}³ \ {0}, normalized, i slowest (the default set).
inline std::vector<Vec3> defaultSpatialDirections() {
  std::vector<Vec3> out;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        if (i || j || k) out.push_back(Vec3(i, j, k).normalized());
  return out;
}

// The wrench (τ about the foot point; F), frame R, resisting motion along `d` at features f: a force
// opposing d, stiffer downward than upward, k h(φ) with h a smooth positive part of −φ (≈ −φ below
// 1 cm, k = 2e4 N/m: a 12 kg robot on four feet sinks about 1.5 mm), modulated by the leans, and a
// moment arm of 2 cm that leans with the leg. Smooth in (φ, β, γ).
inline Eigen::Matrix<double, 6, 1> sandWrench(const Eigen::Vector3d& f, const Vec3& d) {
  const double phi = f[0], beta = f[1], gamma = f[2];
  const double h = 0.5 * (-phi + std::sqrt(phi * phi + 1e-4));
  const double k = 2e4;
  const double gain = 1.0 + 0.3 * std::sin(beta) * d.x() + 0.2 * std::sin(gamma) * d.y();
  const Vec3 F = -k * h * gain * (0.4 * d + 0.6 * std::min(d.z(), 0.0) * Vec3::UnitZ());
  const Vec3 arm = 0.02 * Vec3(std::sin(beta) * std::cos(gamma), std::sin(gamma), 0.0);
  const Vec3 tau = arm.cross(F);
  Eigen::Matrix<double, 6, 1> w;
  w << tau[0], tau[1], tau[2], F[0], F[1], F[2];
  return w;
}

// Interpolates `target` (f, vertex → wrench) at the centres with a thin-plate RBF and a linear
// tail (the tail orthogonal to the weights), scaling (20, 1, 1).
template <class Target>
SpatialRbfParameters interpolateSpatial(const Eigen::MatrixX3d& centres, int K, const Target& target) {
  SpatialRbfParameters p;
  p.kernel = RbfKernel::ThinPlate;
  p.scaling = Eigen::Vector3d(20.0, 1.0, 1.0);
  p.centres = centres;
  const Eigen::Index N = centres.rows();
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(N + 4, N + 4), rhs = Eigen::MatrixXd::Zero(N + 4, 6 * K);
  for (Eigen::Index i = 0; i < N; ++i) {
    for (Eigen::Index j = 0; j < N; ++j) {
      const Eigen::Vector3d d = p.scaling.cwiseProduct(centres.row(i).transpose() - centres.row(j).transpose());
      double kappa = 0.0, g = 0.0;
      rbfKernel(p.kernel, p.epsilon, d.squaredNorm(), &kappa, &g);
      system(i, j) = kappa;
    }
    system(i, N) = system(N, i) = 1.0;
    for (int c = 0; c < 3; ++c) system(i, N + 1 + c) = system(N + 1 + c, i) = centres(i, c);
    for (int v = 0; v < K; ++v) rhs.block(i, 6 * v, 1, 6) = target(centres.row(i).transpose(), v).transpose();
  }
  const Eigen::MatrixXd solution = system.fullPivLu().solve(rhs);
  p.weights = solution.topRows(N);
  p.polynomial = solution.bottomRows(4);
  return p;
}

// The planned grid: 9 depths in [−0.07, 0.01] m × the tilt nodes (0, 0), (±0.4, 0), (0, ±0.4) rad.
inline Eigen::MatrixX3d sandCentres() {
  const double tilts[5][2] = {{0, 0}, {0.4, 0}, {-0.4, 0}, {0, 0.4}, {0, -0.4}};
  Eigen::MatrixX3d c(45, 3);
  for (int i = 0; i < 9; ++i)
    for (int t = 0; t < 5; ++t) c.row(5 * i + t) << -0.07 + 0.01 * i, tilts[t][0], tilts[t][1];
  return c;
}

// The sand formula interpolated on the planned grid with the 26 default directions.
inline SpatialRbfParameters sandSpatialRbf() {
  const std::vector<Vec3> directions = defaultSpatialDirections();
  return interpolateSpatial(sandCentres(), static_cast<int>(directions.size()),
                            [&](const Eigen::Vector3d& f, int v) { return sandWrench(f, directions[v]); });
}

// A random spatial RBF: N centres in φ ∈ [−0.08, 0.02] m, β, γ ∈ [−0.8, 0.8] rad, weights of
// order 10 N (optionally a tail), K vertices.
inline SpatialRbfParameters randomSpatialRbf(RbfKernel kernel, bool tail, std::mt19937& rng, int N = 12, int K = 5) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SpatialRbfParameters p;
  p.kernel = kernel;
  p.epsilon = 0.7;
  p.scaling = Eigen::Vector3d(15.0, 1.2, 0.9);
  p.centres.resize(N, 3);
  for (int i = 0; i < N; ++i) p.centres.row(i) << -0.03 + 0.05 * u(rng), 0.8 * u(rng), 0.8 * u(rng);
  p.weights = Eigen::MatrixXd::NullaryExpr(N, 6 * K, [&]() { return 10.0 * u(rng); });
  if (tail) p.polynomial = Eigen::MatrixXd::NullaryExpr(4, 6 * K, [&]() { return 10.0 * u(rng); });
  return p;
}

}  // namespace nmdp::test
