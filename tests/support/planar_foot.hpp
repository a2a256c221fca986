// A foot sphere placed as `nmdp wrench` places it, for the tests of planar wrench models.
#pragma once
#include <cmath>

#include "contact_models/contact_model.hpp"

namespace nmdp::test {

// The sphere's lowest point is `depth` from the plane z = 0 (negative below) at x, its leg tilted by
// `angle` from the normal toward +x, the sagittal plane x–z.
inline ContactFrame planarFoot(double radius, double depth, double angle, double x = 0.0) {
  ContactFrame f;
  f.radius = radius;
  f.position = Vec3(x, 0.0, radius + depth);
  f.leg_axis = Vec3(std::sin(angle), 0.0, std::cos(angle));
  f.lateral = Vec3::UnitY();
  return f;
}

}  // namespace nmdp::test
