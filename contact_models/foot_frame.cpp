#include "contact_models/foot_frame.hpp"

#include <cmath>

namespace nmdp {

ContactFrame footFrameAt(const Terrain& terrain, double x, double y, double depth, double angle, double radius) {
  TerrainQuery q;
  terrain.query(Vec3(x, y, 0.0), q, false);
  ContactFrame frame;
  frame.radius = radius;
  frame.position = Vec3(x, y, 0.0) + (radius + depth - q.distance) * Vec3::UnitZ();
  terrain.query(frame.position, q, false);
  frame.position += (radius + depth - q.distance) * q.normal;  // exact on planes, close elsewhere
  const Vec3 lateral = Vec3::UnitY();
  const Vec3 forward = lateral.cross(q.normal).normalized();
  frame.leg_axis = std::cos(angle) * q.normal + std::sin(angle) * forward;
  frame.lateral = lateral;
  return frame;
}

}  // namespace nmdp
