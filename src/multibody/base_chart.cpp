#include "multibody/base_chart.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace nmdp {

Mat3 baseAnglesRotation(const Vec3& angles) {
  return rotationAbout(Vec3::UnitX(), angles[0]) * rotationAbout(Vec3::UnitY(), angles[1]) *
         rotationAbout(Vec3::UnitZ(), angles[2]);
}

Vec3 baseAnglesOf(const Mat3& R) {
  return Vec3(std::atan2(-R(1, 2), R(2, 2)), std::asin(std::clamp(R(0, 2), -1.0, 1.0)), std::atan2(-R(0, 1), R(0, 0)));
}

Vec3 baseAnglesFromRpy(const Vec3& rpy) {
  using Eigen::AngleAxisd;
  const Mat3 R = (AngleAxisd(rpy.z(), Vec3::UnitZ()) * AngleAxisd(rpy.y(), Vec3::UnitY()) *
                  AngleAxisd(rpy.x(), Vec3::UnitX())).toRotationMatrix();
  return baseAnglesOf(R);
}

Vec3 rpyOf(const Mat3& R) {
  Vec3 rpy;
  rpy.y() = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  rpy.x() = std::atan2(R(2, 1), R(2, 2));
  rpy.z() = std::atan2(R(1, 0), R(0, 0));
  return rpy;
}

void rebaseFloatingChart(const Model& model, Data& data, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd) {
  if (model.base != BaseType::Floating) return;
  const Mat3 Rx = rotationAbout(Vec3::UnitX(), q[3]);
  const Mat3 Ry = rotationAbout(Vec3::UnitY(), q[4]);
  const Mat3 Rz = rotationAbout(Vec3::UnitZ(), q[5]);
  // Angular velocity of the base in its own frame; at zero angles it equals the new angle rates.
  const Vec3 omega = (Ry * Rz).transpose() * Vec3::UnitX() * qd[3] + Rz.transpose() * Vec3::UnitY() * qd[4] + Vec3::UnitZ() * qd[5];
  data.base_chart = data.base_chart * Rx * Ry * Rz;
  // Keep the chart a rotation despite round-off accumulated over many steps.
  const Eigen::Quaterniond qn(data.base_chart);
  data.base_chart = qn.normalized().toRotationMatrix();
  q.segment<3>(3).setZero();
  qd.segment<3>(3) = omega;
}

}  // namespace nmdp
