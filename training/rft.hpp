// Resistive force theory (RFT) for granular media in the sagittal plane, after
//   C. Li, T. Zhang, D. I. Goldman, "A terradynamics of legged locomotion on granular media",
//   Science 339 (2013) 1408–1412, and its supplementary material.
// It is the project's own source of wrench samples for fitting granular contact models
// (DESIGN.md §9; `nmdp gen-rft`).
//
// ----- The stress on a surface element ------------------------------------------------------------
// An element of area dA at depth |z| below the free surface (z < 0; nothing above it) moving with
// velocity v feels the stress  σ = ζ |z| (α_z ẑ − α_x e)  (force on the element, per unit area),
// with the generic Fourier form of Li et al. (dimensionless; ζ in N/cm³ carries the medium):
//   α_z(β, γ) = A00 + A10 cos 2β + B11 sin(2β + γ) + B01 sin γ + Bm11 sin(−2β + γ)
//   α_x(β, γ) = C11 cos(2β + γ) + C01 cos γ + Cm11 cos(−2β + γ) + D10 sin 2β
// The angles follow the widely used convention of the 3-D extension of Treers et al. (IEEE RA-L 6,
// 2021, DOI 10.1109/LRA.2021.3057052), which applies this form without case distinctions:
//   n  the unit normal of the element's leading side (n·v ≥ 0),
//   e  the horizontal unit vector toward n's horizontal part (± x̂; toward v's when n is vertical),
//   β  = atan2(n_z, n·e) + π/2 ∈ [0, π]: the tilt of n away from straight down (0: a horizontal plate
//        facing down, π/2: a vertical plate),
//   γ  = −atan2(v_z, v·e) ∈ (−π, π]: the direction of motion, positive downward (π/2: straight down).
// The generic coefficients are normalized so that α_z(0, π/2) = 1: ζ is the vertical stress per unit
// depth on a horizontal plate pushed straight down. A horizontal plate of area A at depth d pushed
// down is resisted by F_z = ζ α_z(0, π/2) A d, a vertical plate of width w reaching depth d dragged
// sideways by F_x = ∓ζ α_x(π/2, 0) w d²/2 and lifted by ζ α_z(π/2, 0) w d²/2.
//
// The form is invariant under the mirror (β, γ, α_x, e) → (−β, −π − γ, −α_x, −e), so a thin plate
// (both sides exposed) has the same stress whichever side is taken as n; for a closed body only the
// elements whose outward normal leads (n·v > 0) are loaded. RFT is rate independent: only the
// direction of each element's velocity matters.
//
// ----- Feet, features and wrenches (the conventions of contact_models/planar_wrench_model.hpp) ----
// The foot point P is at depth `depth` (signed, m, negative below the surface) under the origin;
// the leg axis a = (sin θ, cos θ) leans toward +x for θ > 0 (`angle`, rad); t = (cos θ, −sin θ) is
// the foot's forward axis. The torque centre is Q = P + L a (L = `torque_centre`, m up the leg).
// Shapes (out-of-plane extent `width`):
//   plate  a thin plate across the leg, centred on P, from P − (ℓ/2) t to P + (ℓ/2) t;
//   blade  a thin plate along the leg, from P up to P + ℓ a (a shank or fin entering the sand);
//   disc   the sagittal section of a foot sphere of radius r: the circle of centre P + r ẑ whose
//          lowest point is P (as for the sphere feet of the planar wrench model); a closed body.
// A motion is a planar twist (v_x, v_z, ω_y) of the foot: the velocity of a point r is
// (v_x, v_z) + ω ŷ × (r − Q), so ω > 0 turns +x toward −z (a right-handed rotation about +y).
// The wrench (F_x, F_z, τ_y) is the medium's force on the foot, in N, and its moment about Q about
// +y, in N·m: τ_y = Σ (r_z − Q_z) f_x − (r_x − Q_x) f_z.
//
// ----- Integration --------------------------------------------------------------------------------
// Each shape's submerged part is found exactly (a segment is clipped at z = 0; a circle's submerged
// arc is the one centred on its lowest point), the disc's arc is further split where its leading
// side begins and ends (for a circle n·v = n·v_centre, so these are two points), and each piece is
// integrated with the midpoint rule on `elements` equal parts (shared among the pieces by length).
// For a flat shape in translation the integrand is linear in arc length and the result is exact.
#pragma once
#include <string>
#include <vector>

#include "training/force_dataset.hpp"

namespace nmdp {

// The nine coefficients of the generic form; defaults: the published generic values (Li, Zhang,
// Goldman 2013, supplementary material), dimensionless.
struct RftCoefficients {
  double A00 = 0.206, A10 = 0.169, B11 = 0.212, B01 = 0.358, Bm11 = 0.055;
  double C11 = -0.124, C01 = 0.253, Cm11 = 0.007, D10 = 0.088;
};

struct RftMedium {
  RftCoefficients coefficients;
  double zeta = 1.0;  // the medium's scale factor ζ, N/cm³ (the unit Li et al. publish it in)
};

struct RftAlpha {
  double x = 0, z = 0;
};

// α_x(β, γ), α_z(β, γ) of the generic form (dimensionless; multiply by ζ).
RftAlpha rftAlpha(const RftCoefficients& c, double beta, double gamma);

// The stress per unit depth on a plate element with unit normal `n` (either side for a thin plate;
// the outward normal of a closed body's leading element) moving with velocity `v`, in N/m³ (force
// per unit area per metre of depth), world (x, z). Zero when v = 0. `n` need not lead: the result
// is the same for n and −n (see above), so callers decide which elements are loaded.
void rftStressPerDepth(const RftMedium& medium, double nx, double nz, double vx, double vz, double* sx, double* sz);

enum class RftShape { Plate, Blade, Disc };

struct RftFoot {
  RftShape shape = RftShape::Disc;
  double length = 0.0;         // m, plate and blade
  double radius = 0.02;        // m, disc
  double width = 0.04;         // m, out-of-plane extent over which the planar stress acts
  double torque_centre = 0.0;  // m up the leg from the foot point
  int elements = 400;          // midpoint-rule elements over the submerged part
};

struct RftTwist {
  double vx = 0, vz = 0, omega = 0;  // m/s, m/s, rad/s (about +y through the torque centre)
};

struct PlanarWrench {
  double fx = 0, fz = 0, wy = 0;  // N, N, N·m about the torque centre
};

// The medium's resistance to the foot at (depth, angle) moving along `twist`. Zero at and above
// the surface and for a zero twist. Throws std::invalid_argument on a non-positive size, width or
// element count, or non-finite input.
PlanarWrench rftWrench(const RftMedium& medium, const RftFoot& foot, double depth, double angle,
                       const RftTwist& twist);

// `count` translations, ψ_j = 2πj/count from straight down toward +x: (sin ψ_j, −cos ψ_j, 0).
// Under the mirror x → −x direction j becomes count − j (mod count).
std::vector<RftTwist> rftCircleDirections(int count);
// The 26 twists (i, k, l) ∈ {−1, 0, 1}³ \ {0}, in lexicographic order: v = (i, k), ω = l / rotation_radius
// (a point rotation_radius from the torque centre moves at unit speed).
std::vector<RftTwist> rftCubeDirections(double rotation_radius);

struct RftGrid {
  std::vector<double> depths;  // m, ≤ 0
  std::vector<double> angles;  // rad
  std::vector<RftTwist> directions;
};

// Wrench samples at every (depth, angle) of the grid (depths outer, angles inner, in the given
// order): one sample per direction, vertex index = the direction's index, the wrench resisting it.
// Features (phi, beta) = (depth, angle) in (m, rad); wrench (F_x, F_z, tau_y) in (N, N, N m); the
// torque centre is the foot's; `source` describes the medium, foot and grid.
ForceDataset rftSamples(const RftMedium& medium, const RftFoot& foot, const RftGrid& grid);

const char* rftShapeName(RftShape shape);

}  // namespace nmdp
