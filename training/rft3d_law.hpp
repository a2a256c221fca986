// The resistive stress on one surface element in three dimensions: the law behind rft3dWrench
// (training/rft3d_foot.hpp). One function, so the law can be swapped without touching the feet.
//
// Which law. The target is the three-dimensional RFT of Agarwal, Goldman and Kamrin (PNAS 120,
// e2214017120, 2023; arXiv 2205.14920). Its formulation could not be taken from the paper's text,
// and the only available values of its reduced-order functions (an unverified third-party
// implementation) do not reduce to the planar generic form of training/rft.hpp (the rft3d note in
// docs/notes has the check). This file therefore implements a PROJECTION law in the spirit
// of Treers, Cao and Stuart (IEEE RA-L 6, 2021, "Granular resistive force theory implementation for
// three-dimensional trajectories"): the planar law of Li, Zhang and Goldman (Science 2013;
// training/rft.hpp) applied in the vertical plane of the element's velocity. Treers et al.'s
// empirical out-of-plane scaling factors are NOT included; the out-of-plane part of the normal is
// handled by the area weight below.
//
// The law. Element with unit normal n (either side for a thin plate, the outward normal of a closed
// body's leading element) moving with velocity v, at depth |z| below the surface (z up):
//   r̂ = v's horizontal direction (n's when v is vertical, x̂ when both are), θ̂ = ẑ × r̂;
//   the motion plane is span(r̂, ẑ); n_p = (n·r̂) r̂ + (n·ẑ) ẑ, the normal's part in it;
//   σ/|z| = |n_p| · S₂(n_p/|n_p|, v)   (force per unit area per metre of depth, N/m³),
// where S₂ is the planar stress rftStressPerDepth in the (r̂, ẑ) coordinates, mapped back to 3-D.
// |n_p| is the element's area projected onto the plane whose normal is n_p: the part of the element
// that the planar law sees. σ lies in the motion plane (no force along θ̂), and σ = 0 for an element
// whose normal is ±θ̂ (edge-on to the motion plane).
//
// Reduction to the planar RFT, exactly: when n and v lie in the x–z plane, r̂ = ±x̂ exactly, n_p = n,
// |n_p| = 1, and the result is rftStressPerDepth(n_x, n_z, v_x, v_z) with a zero y component, bit
// for bit (the planar law is mirror symmetric in x, and ±1 products are exact).
#pragma once
#include <Eigen/Dense>

#include "training/rft.hpp"

namespace nmdp {

// σ/|z| (N/m³) on an element of unit normal `n` moving with velocity `v`, both in the terrain frame
// (z up). Zero for v = 0. `n` need not lead; callers decide which elements are loaded.
Eigen::Vector3d rft3dStressPerDepth(const RftMedium& medium, const Eigen::Vector3d& n, const Eigen::Vector3d& v);

}  // namespace nmdp
