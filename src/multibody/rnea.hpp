// Recursive Newton–Euler inverse dynamics in world coordinates.
#pragma once
#include "multibody/data.hpp"

namespace nmdp {

// τ = H(q) q̈ + C(q, q̇) q̇ + g(q) (armature included) into data.tau. Runs forwardKinematics.
// Leaves data.v, data.a (gravity as base acceleration) and data.f (composite force of each
// subtree) for the derivative pass.
void rnea(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd);

// RNEA on the current kinematics (forwardKinematics already run at q).
void rneaFromKinematics(const Model& model, Data& data, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd);

// ½ q̇ᵀ H q̇ computed from body velocities (forwardKinematics already run at q).
double kineticEnergy(const Model& model, Data& data, const Eigen::VectorXd& qd);

}  // namespace nmdp
