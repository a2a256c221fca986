#include "solver/contact_kinematics.hpp"

#include "multibody/kinematics.hpp"

namespace nmdp {

void contactFrame(const Model& model, const Data& data, const ContactPoint& contact, ContactFrame& out) {
  Mat3 R;
  Vec3 p;
  linkPose(model, data, contact.link, R, p);
  out.position = p + R * contact.offset;
  out.radius = contact.radius;
  out.leg_axis = (R * contact.leg_axis).normalized();
  // On a planar base the sagittal plane is the plane of motion, fixed in the world.
  out.lateral_rotates = model.base != BaseType::Planar;
  out.lateral = out.lateral_rotates ? Vec3((R * contact.lateral).normalized()) : Vec3::UnitY();
}

void contactJacobian(const Model& model, const Data& data, const ContactPoint& contact, Eigen::Ref<Mat6X> J) {
  spatialJacobian(model, data, model.links[contact.link].body, linkPoint(model, data, contact.link, contact.offset), J);
}

void vertexDerivative(const ContactWrenches& wrenches, const Mat6X& J, int j, Mat6X& dV_dtheta_j) {
  dV_dtheta_j.noalias() = wrenches.dV[0] * J(0, j);
  for (int i = 1; i < 6; ++i) dV_dtheta_j.noalias() += wrenches.dV[i] * J(i, j);
}

}  // namespace nmdp
