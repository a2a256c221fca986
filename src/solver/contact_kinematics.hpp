// From the robot to its contacts: where each contact sphere is (ContactFrame, the input of every
// contact model) and how its wrench vertices change with the configuration:
//   ∂V/∂θ_j = Σ_i dV/dξ_i · J_c(i, j),
// J_c the spatial Jacobian of the sphere centre (rows [angular; linear], world), ξ the model's
// perturbation [rotation about the centre; translation] (contact_models/contact_model.hpp).
#pragma once
#include <string>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "multibody/data.hpp"

namespace nmdp {

struct ContactPoint {
  std::string name;               // for output files and messages
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

// One contact sphere per foot found by detectFeet (multibody/feet.hpp), named after its link, with
// its leg axis from legAxisOf.
std::vector<ContactPoint> footContactPoints(const Model& model);

// After forwardKinematics: the contact's world frame.
void contactFrame(const Model& model, const Data& data, const ContactPoint& contact, ContactFrame& out);

// After forwardKinematics: the 6×nq spatial Jacobian of the contact's sphere centre.
void contactJacobian(const Model& model, const Data& data, const ContactPoint& contact, Eigen::Ref<Mat6X> J);

// ∂V/∂θ_j from the model's dV/dξ and the contact Jacobian (6×K).
void vertexDerivative(const ContactWrenches& wrenches, const Mat6X& J, int j, Mat6X& dV_dtheta_j);

}  // namespace nmdp
