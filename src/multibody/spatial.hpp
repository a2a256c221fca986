// Spatial (6-D) algebra in world coordinates, Featherstone's conventions:
// motion vectors [angular; linear at the world origin], force vectors [moment about the origin; force].
#pragma once
#include <Eigen/Dense>

namespace nmdp {

using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat34 = Eigen::Matrix<double, 3, 4>;
using Mat43 = Eigen::Matrix<double, 4, 3>;
using Mat6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using Mat3X = Eigen::Matrix<double, 3, Eigen::Dynamic>;

inline Mat3 skew(const Vec3& w) {
  Mat3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// The two cross products are forced inline: GCC otherwise keeps them out of line in the larger
// dynamics loops, where a call costs as much as the product itself.

// m × u for motion vectors (Featherstone crm(m) u).
EIGEN_ALWAYS_INLINE Vec6 crossMotion(const Vec6& m, const Vec6& u) {
  Vec6 r;
  r.head<3>() = m.head<3>().cross(u.head<3>());
  r.tail<3>() = m.head<3>().cross(u.tail<3>()) + m.tail<3>().cross(u.head<3>());
  return r;
}

// m ×* f for a force vector f (Featherstone crf(m) f = -crm(m)^T f).
EIGEN_ALWAYS_INLINE Vec6 crossForce(const Vec6& m, const Vec6& f) {
  Vec6 r;
  r.head<3>() = m.head<3>().cross(f.head<3>()) + m.tail<3>().cross(f.tail<3>());
  r.tail<3>() = m.head<3>().cross(f.tail<3>());
  return r;
}

inline Mat6 crmMatrix(const Vec6& m) {
  Mat6 X = Mat6::Zero();
  X.topLeftCorner<3, 3>() = skew(m.head<3>());
  X.bottomRightCorner<3, 3>() = skew(m.head<3>());
  X.bottomLeftCorner<3, 3>() = skew(m.tail<3>());
  return X;
}

inline Mat6 crfMatrix(const Vec6& m) { return -crmMatrix(m).transpose(); }

// Spatial inertia about the world origin, written into I, of a body with mass m, world centre of
// mass c and rotational inertia R J Rᵀ about the centre of mass (J symmetric, in body axes):
//   [Ī, [h]×; [h]×ᵀ, m 1],  h = m c,  Ī = R J Rᵀ + m (|c|² 1 − c cᵀ).
// Entry by entry and in place: Ī has six distinct entries, each a row of R J dotted with a row of R.
inline void spatialInertia(double m, const Vec3& c, const Mat3& R, const Mat3& J, Mat6& I) {
  Mat3 A;
  A.noalias() = R * J;
  const Vec3 h = m * c;
  const double hc = h.dot(c);
  I(0, 0) = A.row(0).dot(R.row(0)) + hc - h.x() * c.x();
  I(1, 1) = A.row(1).dot(R.row(1)) + hc - h.y() * c.y();
  I(2, 2) = A.row(2).dot(R.row(2)) + hc - h.z() * c.z();
  I(0, 1) = I(1, 0) = A.row(0).dot(R.row(1)) - h.x() * c.y();
  I(0, 2) = I(2, 0) = A.row(0).dot(R.row(2)) - h.x() * c.z();
  I(1, 2) = I(2, 1) = A.row(1).dot(R.row(2)) - h.y() * c.z();
  I(0, 3) = I(3, 0) = I(1, 4) = I(4, 1) = I(2, 5) = I(5, 2) = 0.0;
  I(0, 4) = I(4, 0) = -h.z();
  I(0, 5) = I(5, 0) = h.y();
  I(1, 3) = I(3, 1) = h.z();
  I(1, 5) = I(5, 1) = -h.x();
  I(2, 3) = I(3, 2) = -h.y();
  I(2, 4) = I(4, 2) = h.x();
  I.bottomRightCorner<3, 3>() = m * Mat3::Identity();
}

// 4×4 homogeneous form of a motion vector: d/dt [R t; 0 1] = hat(v) [R t; 0 1].
inline Mat4 motionHat(const Vec6& m) {
  Mat4 X = Mat4::Zero();
  X.topLeftCorner<3, 3>() = skew(m.head<3>());
  X.topRightCorner<3, 1>() = m.tail<3>();
  return X;
}

inline Mat3 rotationAbout(const Vec3& unit_axis, double angle) {
  return Eigen::AngleAxisd(angle, unit_axis).toRotationMatrix();
}

}  // namespace nmdp
