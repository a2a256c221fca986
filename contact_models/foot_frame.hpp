// The contact frame of one foot placed for probing a contact model (nmdp wrench, the Python
// ContactModel.vertices): the sphere's lowest point `depth` from the terrain below (x, y), the leg in
// the terrain's sagittal plane through the world y axis, tilted by `angle` from the normal.
// On a plane these are exactly the planar models' features (planar_wrench_model.hpp): φ = depth and
// β = angle for |angle| < π; the Coulomb cone's penetration is max(0, −depth).
#pragma once
#include "contact_models/contact_model.hpp"

namespace nmdp {

// `depth`: m, signed distance of the foot's lowest point to the terrain (negative below);
// `angle`: rad, leg axis = cos(angle) n + sin(angle) x_s, x_s = y × n (forward); `radius`: m ≥ 0.
// Exact on planes; on curved terrain the sphere is placed along the normal once (close, not exact).
ContactFrame footFrameAt(const Terrain& terrain, double x, double y, double depth, double angle, double radius);
// The same with the leg also leaning `lateral_angle` (rad) toward the lateral axis y_s: leg axis =
// cos γ sin β x_s + sin γ y_s + cos γ cos β n (β = angle, γ = lateral_angle), so that on a plane the
// 3-D models' features (spatial_wrench_model.hpp) are φ = depth, β = angle and γ = lateral_angle for
// |angle| < π, |lateral_angle| < π/2. lateral_angle = 0 gives the frame above exactly.
ContactFrame footFrameAt(const Terrain& terrain, double x, double y, double depth, double angle, double lateral_angle,
                         double radius);

}  // namespace nmdp
