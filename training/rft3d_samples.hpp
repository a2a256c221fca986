// Wrench samples of 3-D resistive force theory (training/rft3d_foot.hpp) on a grid of foot states
// and a set of motion directions: the data `nmdp fit` turns into a spatial (3-D) granular model,
// or, from the same medium and foot, into a planar one.
//
// Spatial dataset (training/force_dataset.hpp, the 3-D layout of contact_models/spatial_wrench_model.hpp):
//   features (phi, beta, gamma) in (m, rad, rad) = (depth of P, sagittal lean, lateral lean);
//   vertex j = direction j; wrench (tau_x, tau_y, tau_z, F_x, F_y, F_z) in (N m, N m, N m, N, N, N),
//   the medium's resistance to a translation along direction j, torque about the foot point P, in
//   the terrain frame. Rows: depths outer, then betas, then gammas, then directions.
// Planar dataset (the layout of the planar `nmdp gen-rft`, training/rft.hpp): the same foot at
//   γ = 0 translated along directions in the sagittal x–z plane; features (phi, beta), wrench
//   (F_x, F_z, tau_y) with tau_y about the torque centre Q = P + L a (L m up the leg):
//   tau_y = tau_y(P) + ((P − Q) × F)_y.
#pragma once
#include <Eigen/Dense>
#include <vector>

#include "training/force_dataset.hpp"
#include "training/rft3d_foot.hpp"

namespace nmdp {

// The 26 directions (i, j, k) ∈ {−1, 0, 1}³ \ {0}, normalized, lexicographic (i slowest).
std::vector<Eigen::Vector3d> rft3dCubeDirections();
// `count` unit vectors spread over the sphere on a Fibonacci (golden-angle) spiral, from near +z
// to near −z: z_k = 1 − (2k + 1)/count, azimuth k·π(3 − √5).
std::vector<Eigen::Vector3d> rft3dFibonacciDirections(int count);
// `count` directions in the x–z plane, ψ_j = 2πj/count from straight down toward +x:
// (sin ψ_j, 0, −cos ψ_j) (the translations of the planar rftCircleDirections).
std::vector<Eigen::Vector3d> rft3dCircleDirections(int count);

struct Rft3dGrid {
  std::vector<double> depths;  // m, ≤ 0
  std::vector<double> betas;   // rad
  std::vector<double> gammas;  // rad (the planar dataset uses γ = 0 only)
  std::vector<Eigen::Vector3d> directions;
};

ForceDataset rft3dSamples(const RftMedium& medium, const Rft3dFoot& foot, const Rft3dGrid& grid);

// The planar dataset: every direction must have y = 0. Throws std::invalid_argument otherwise.
ForceDataset rft3dPlanarSamples(const RftMedium& medium, const Rft3dFoot& foot, const Rft3dGrid& grid,
                                double torque_centre);

}  // namespace nmdp
