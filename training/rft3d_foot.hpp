// Feet in three dimensions for resistive force theory: their surfaces cut into elements, the
// submerged part integrated with the element law of training/rft3d_law.hpp, giving the wrench that
// resists a translation of the foot (`nmdp gen-rft` with "dimension": 3).
//
// ----- Frames and features (contact_models/spatial_wrench_model.hpp) -----------------------------
// The terrain frame R = [x_s y_s n]: x the heading, z the terrain normal (up), the surface z = 0.
// The foot point P = (0, 0, depth) (m, negative below the surface). The foot's frame is
// R_f = Rot_y(β)·Rot_x(−γ): columns t = (cos β, 0, −sin β) forward, l = (−sin γ sin β, cos γ,
// −sin γ cos β) lateral, a = (cos γ sin β, sin γ, cos γ cos β) the leg axis (β the sagittal lean,
// γ the lateral lean toward +y).
// The wrench (τ, F) is the medium's force on the foot, N, and its moment about P, N m, both in the
// terrain frame, for a translation of the foot along `velocity` (only its direction matters).
//
// ----- Shapes --------------------------------------------------------------------------------------
//   sphere  radius r, centre P + r ẑ (lowest point P), a closed body: only the elements whose
//           outward normal leads (n·v > 0) are loaded;
//   plate   a thin rectangle length × width in the t–l plane centred on P (a sole across the leg),
//           normal a, both sides exposed;
//   blade   a thin rectangle from P up to P + length·a, width along l (a fin along the leg),
//           normal t, both sides exposed.
//
// ----- Integration ---------------------------------------------------------------------------------
// The stress is ζ|z| times a function of directions, so it vanishes continuously at the surface:
// elements above z = 0 carry nothing and the clip needs no exact cut. The sphere is cut into
// `elements` rings of equal polar angle over its submerged cap (pole at P), and each ring's
// leading arc (n·v > 0, found exactly: the one jump of the integrand) into equal parts,
// 2·`elements` per full ring; the rectangles into `elements` × `elements` midpoint cells.
#pragma once
#include <Eigen/Dense>

#include "training/rft.hpp"

namespace nmdp {

enum class Rft3dShape { Sphere, Plate, Blade };

struct Rft3dFoot {
  Rft3dShape shape = Rft3dShape::Sphere;
  double radius = 0.02;  // m, sphere
  double length = 0.0;   // m, plate (along t) and blade (along a)
  double width = 0.0;    // m, plate and blade (along l)
  int elements = 64;     // cuts per direction (see above)
};

struct Wrench6 {
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // N m, about the foot point P
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N
};

// The foot's frame R_f = Rot_y(β)·Rot_x(−γ) in the terrain frame (columns t, l, a).
Eigen::Matrix3d rft3dFootFrame(double beta, double gamma);

// The medium's resistance to the foot at (depth, β, γ) translating along `velocity` (terrain
// frame). Zero for a zero velocity and for a foot wholly above the surface. Throws
// std::invalid_argument on non-finite input, a non-positive size, or an element count outside
// [1, 100000].
Wrench6 rft3dWrench(const RftMedium& medium, const Rft3dFoot& foot, double depth, double beta, double gamma,
                    const Eigen::Vector3d& velocity);

// The same for a foot whose frame (columns t, l, a) is `foot_frame`, any rotation: the terrain
// frame's own integration, which rft3dWrench calls with rft3dFootFrame(β, γ).
Wrench6 rft3dWrenchInFrame(const RftMedium& medium, const Rft3dFoot& foot, double depth,
                           const Eigen::Matrix3d& foot_frame, const Eigen::Vector3d& velocity);

const char* rft3dShapeName(Rft3dShape shape);

}  // namespace nmdp
