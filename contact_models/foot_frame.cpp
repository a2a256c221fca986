#include "contact_models/foot_frame.hpp"

#include <cmath>

namespace nmdp {

ContactFrame footFrameAt(const Terrain& terrain, double x, double y, double depth, double angle, double radius) {
  return footFrameAt(terrain, x, y, depth, angle, 0.0, radius);
}

ContactFrame footFrameAt(const Terrain& terrain, double x, double y, double depth, double angle, double lateral_angle,
                         double radius) {
  TerrainQuery q;
  terrain.query(Vec3(x, y, 0.0), q, false);
  ContactFrame frame;
  frame.radius = radius;
  frame.position = Vec3(x, y, 0.0) + (radius + depth - q.distance) * Vec3::UnitZ();
  terrain.query(frame.position, q, false);
  frame.position += (radius + depth - q.distance) * q.normal;  // exact on planes, close elsewhere
  const Vec3 lateral = Vec3::UnitY();
  const Vec3 forward = lateral.cross(q.normal).normalized();
  const Vec3 sideways = q.normal.cross(forward);  // y_s, unit
  frame.leg_axis = std::cos(lateral_angle) * (std::cos(angle) * q.normal + std::sin(angle) * forward);
  if (lateral_angle != 0.0) frame.leg_axis += std::sin(lateral_angle) * sideways;
  frame.lateral = lateral;
  return frame;
}

}  // namespace nmdp
