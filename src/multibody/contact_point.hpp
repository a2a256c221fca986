// A contact point: a sphere fixed to a link, the one description of a foot that foot detection
// (multibody/feet.hpp), the leg IK (control/leg_ik.hpp) and the solver's contact kinematics
// (solver/contact_kinematics.hpp) share.
#pragma once
#include <string>

#include "multibody/model.hpp"

namespace nmdp {

struct ContactPoint {
  std::string name;               // for output files and messages (a detected foot: its link's name)
  int link = -1;                  // Model::links index
  Vec3 offset = Vec3::Zero();     // sphere centre in the link frame
  double radius = 0.0;
  Vec3 leg_axis = Vec3::UnitZ();  // link frame, from the foot up the leg (planar granular models)
  Vec3 lateral = Vec3::UnitY();   // link frame; ignored on a planar base (the world y axis is used)
};

// The leg axis of a contact sphere (link frame, unit): from the sphere's centre toward the first
// link origin up the tree (the link's own, then its parent's, ...) that lies outside the sphere, in
// the model's zero configuration; UnitZ when there is none. A foot sphere at the end of a foot link
// (RoboSimian's link7, whose x axis runs along the foot) gets −x; one at the origin of a foot link
// fixed to the shank gets the direction to the knee. Planar granular models read their angle
// feature off this axis, so it must point up the leg, whatever the link's own axes.
Vec3 legAxisOf(const Model& model, int link, const Vec3& offset, double radius);

}  // namespace nmdp
