// The floating base's orientation coordinates, in one place. q[3..5] = (a, b, c) are angles about x,
// y and z of R = C · Rx(a) Ry(b) Rz(c), where C is the chart (Data::base_chart, a rotation the
// integrator re-centres so that the middle angle b stays far from gimbal lock at ±π/2). The output's
// /base/rpy are the usual roll-pitch-yaw (ZYX) of the whole rotation instead.
#pragma once
#include <Eigen/Core>

#include "multibody/data.hpp"
#include "multibody/model.hpp"
#include "multibody/spatial.hpp"

namespace nmdp {

// Rx(a) Ry(b) Rz(c) of the angles (a, b, c).
Mat3 baseAnglesRotation(const Vec3& angles);

// The angles (a, b, c) of R = Rx(a) Ry(b) Rz(c), with b in [−π/2, π/2].
Vec3 baseAnglesOf(const Mat3& R);

// The chart angles (identity chart) of a roll-pitch-yaw triple, R = Rz(yaw) Ry(pitch) Rx(roll).
Vec3 baseAnglesFromRpy(const Vec3& rpy);

// Roll, pitch and yaw (ZYX) of a rotation: /base/rpy of the output.
Vec3 rpyOf(const Mat3& R);

// Moves the chart to the base's current orientation: q's base angles become 0 and q̇'s base angle
// rates the body-frame angular velocity (the rates at zero angles). No-op for other bases.
void rebaseFloatingChart(const Model& model, Data& data, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd);

}  // namespace nmdp
