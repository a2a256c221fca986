// What a URDF says a robot looks like: each link's <visual> and <collision> shapes (with their
// origins, mesh files and material colours) and its inertia, read from URDF text with urdfdom, for
// drawing the robot (nmdp view). The dynamics read the same file through urdf_loader.hpp.
#pragma once
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "multibody/spatial.hpp"

namespace nmdp {

struct ShapeOfLink {
  enum class Type { Box, Sphere, Cylinder, Mesh };
  Type type = Type::Box;
  Vec3 size = Vec3::Zero();       // box, m
  double radius = 0.0;            // sphere, cylinder, m
  double length = 0.0;            // cylinder (along local z), m
  std::string mesh_file;          // mesh: the filename as the URDF writes it
  std::string mesh_path;          // mesh: resolved as the loader resolves it, "" when not found
  Vec3 mesh_scale = Vec3::Ones();
  Vec3 position = Vec3::Zero();   // origin in the link frame
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  std::optional<Eigen::Vector4d> color;  // RGBA in [0, 1], when the URDF gives a material colour
};

struct LinkAppearance {
  std::string name;
  std::vector<ShapeOfLink> visuals, collisions;
  // The box of the link's mass and inertia (a uniform box with the same principal moments), placed
  // at the centre of mass along the principal axes; absent for a link without <inertial> or mass.
  std::optional<ShapeOfLink> inertia_box;
};

struct RobotAppearance {
  std::string root_link;            // the URDF's root link (the trunk of a floating robot)
  std::vector<LinkAppearance> links;  // in the URDF's order
};

// Parses URDF text. `urdf_path` (may be "") is where it came from: mesh paths are resolved against
// its folder, and messages name it. Throws InputError naming the URDF when urdfdom rejects it or a
// number is not finite.
RobotAppearance readRobotAppearance(const std::string& urdf_text, const std::string& urdf_path);

}  // namespace nmdp
