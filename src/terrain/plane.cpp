#include "terrain/plane.hpp"

#include <sstream>
#include <stdexcept>

namespace nmdp {

PlaneTerrain::PlaneTerrain(const Vec3& normal, double offset) : offset_(offset) {
  if (!(normal.norm() > 1e-12)) throw std::invalid_argument("plane terrain: the normal is zero");
  normal_ = normal.normalized();  // the offset is the signed distance of the plane from the origin along it
}

void PlaneTerrain::query(const Vec3& p, TerrainQuery& out, bool derivatives) const {
  out.distance = normal_.dot(p) - offset_;
  out.normal = normal_;
  if (derivatives) {
    out.gradient = normal_;
    out.normal_jacobian.setZero();
  }
}

std::string PlaneTerrain::describe() const {
  std::ostringstream s;
  s << "plane: normal (" << normal_.x() << ", " << normal_.y() << ", " << normal_.z() << "), offset " << offset_ << " m";
  return s.str();
}

}  // namespace nmdp
