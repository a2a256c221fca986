#pragma once
#include <map>
#include <string>

#include "multibody/model.hpp"

namespace nmdp {

struct UrdfOptions {
  BaseType base = BaseType::Floating;
  std::map<std::string, double> locked_joints;  // joint name -> value (rad or m), merged like fixed
  std::map<std::string, double> armature;       // joint name -> rotor inertia added to H_ii
  double default_armature = 0.0;                // for every actuated joint not in `armature`
  Vec3 gravity = Vec3(0, 0, -9.81);
};

// Loads a URDF file. Throws InputError naming the file and element for a missing file, malformed
// XML, an unsupported joint type, a non-finite or negative inertia, a locked joint that does not
// exist, or a movable joint that moves no mass or inertia.
Model loadUrdf(const std::string& path, const UrdfOptions& options = {});

BaseType parseBaseType(const std::string& name);

// A <mesh filename="..."> resolved as loadUrdf resolves it (package://, file:// and relative paths
// against `urdf_dir` and its parents): the absolute path of the file, "" when none is found.
std::string resolveMeshFile(const std::string& filename, const std::string& urdf_dir);

}  // namespace nmdp
