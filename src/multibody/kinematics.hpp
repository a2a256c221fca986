// Forward kinematics, Jacobians of points fixed on bodies, and their θ-derivatives.
#pragma once
#include <Eigen/Dense>

#include "multibody/data.hpp"

namespace nmdp {

// World pose R[i], p[i] and world motion axis S[i] of every body; world spatial inertia Iw[i].
void forwardKinematics(const Model& model, Data& data, const Eigen::VectorXd& q);

// After forwardKinematics: world pose of a URDF link frame.
void linkPose(const Model& model, const Data& data, int link, Mat3& R, Vec3& p);
// World position of a point given in a link's frame.
Vec3 linkPoint(const Model& model, const Data& data, int link, const Vec3& local);

// Spatial Jacobian (6×nq, rows [angular; linear], world frame) of the point `point_world` moving
// with body `body` (-1: the world, all zero). J.col(j) is nonzero only for ancestors j of body.
void spatialJacobian(const Model& model, const Data& data, int body, const Vec3& point_world, Eigen::Ref<Mat6X> J);
// The linear rows only (3×nq).
void pointJacobian(const Model& model, const Data& data, int body, const Vec3& point_world, Eigen::Ref<Mat3X> J);

// ∂J/∂θ_l of the spatial Jacobian above (the point moves with the body).
void spatialJacobianDerivative(const Model& model, const Data& data, int body, const Vec3& point_world, int l,
                               Eigen::Ref<Mat6X> dJ);

// out(j, l) += ∂(J_jᵀ f)/∂θ_l for a fixed wrench f = [torque about the point; force] (world).
// This is the ∂Jᵀ/∂θ · f term of the NE residual's θ-Jacobian.
void addJacobianTransposeWrenchDerivative(const Model& model, const Data& data, int body, const Vec3& point_world,
                                          const Vec6& wrench, Eigen::Ref<Eigen::MatrixXd> out);


// World pose of the robot's root link as position and roll-pitch-yaw (ZYX) angles.
void basePose(const Model& model, const Data& data, Vec3& position, Vec3& rpy);

}  // namespace nmdp
