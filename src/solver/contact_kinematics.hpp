// From the robot to its contacts: where each contact sphere is (ContactFrame, the input of every
// contact model) and how its wrench vertices change with the configuration:
//   ∂V/∂θ_j = Σ_i dV/dξ_i · J_c(i, j),
// J_c the spatial Jacobian of the sphere centre (rows [angular; linear], world), ξ the model's
// perturbation [rotation about the centre; translation] (contact_models/contact_model.hpp).
#pragma once
#include <vector>

#include "contact_models/contact_model.hpp"
#include "multibody/contact_point.hpp"
#include "multibody/data.hpp"
#include "multibody/feet.hpp"

namespace nmdp {

// ContactPoint is multibody/contact_point.hpp; footContactPoints, multibody/feet.hpp.

// After forwardKinematics: the contact's world frame.
void contactFrame(const Model& model, const Data& data, const ContactPoint& contact, ContactFrame& out);

// After forwardKinematics: the 6×nq spatial Jacobian of the contact's sphere centre.
void contactJacobian(const Model& model, const Data& data, const ContactPoint& contact, Eigen::Ref<Mat6X> J);

// ∂V/∂θ_j from the model's dV/dξ and the contact Jacobian (6×K).
void vertexDerivative(const ContactWrenches& wrenches, const Mat6X& J, int j, Mat6X& dV_dtheta_j);

}  // namespace nmdp
