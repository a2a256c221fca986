// Composite-rigid-body algorithm: the joint-space mass matrix.
#pragma once
#include "multibody/data.hpp"

namespace nmdp {

// H(q) into data.H (full symmetric, armature on the diagonal). Runs forwardKinematics.
void crba(const Model& model, Data& data, const Eigen::VectorXd& q);

// H from the current kinematics; also leaves data.Ic (composite world inertias).
void crbaFromKinematics(const Model& model, Data& data);

}  // namespace nmdp
