#include "multibody/kinematics.hpp"

namespace nmdp {

void forwardKinematics(const Model& model, Data& data, const Eigen::VectorXd& q) {
  for (int i = 0; i < model.nq; ++i) {
    const Body& b = model.bodies[i];
    const Mat3& Rplace = b.uses_base_chart ? data.base_chart : b.placement_rotation;
    Mat3 Rj;
    Vec3 pj;
    if (b.parent < 0) {
      Rj = Rplace;
      pj = b.placement_translation;
    } else {
      Rj.noalias() = data.R[b.parent] * Rplace;
      pj.noalias() = data.R[b.parent] * b.placement_translation;
      pj += data.p[b.parent];
    }
    const Vec3 axis = Rj * b.axis;
    if (b.kind == JointKind::Revolute) {
      data.R[i].noalias() = Rj * rotationAbout(b.axis, q[i]);
      data.p[i] = pj;
      data.S[i] << axis, pj.cross(axis);
    } else {
      data.R[i] = Rj;
      data.p[i] = pj + axis * q[i];
      data.S[i] << Vec3::Zero(), axis;
    }
    const Vec3 c = data.p[i] + data.R[i] * b.com;
    data.Iw[i] = spatialInertia(b.mass, c, data.R[i] * b.inertia_com * data.R[i].transpose());
  }
}

void linkPose(const Model& model, const Data& data, int link, Mat3& R, Vec3& p) {
  const Link& l = model.links[link];
  if (l.body < 0) {
    R = l.rotation;
    p = l.translation;
  } else {
    R.noalias() = data.R[l.body] * l.rotation;
    p.noalias() = data.R[l.body] * l.translation;
    p += data.p[l.body];
  }
}

Vec3 linkPoint(const Model& model, const Data& data, int link, const Vec3& local) {
  Mat3 R;
  Vec3 p;
  linkPose(model, data, link, R, p);
  return p + R * local;
}

void spatialJacobian(const Model& model, const Data& data, int body, const Vec3& point, Eigen::Ref<Mat6X> J) {
  J.setZero();
  for (int j = body; j >= 0; j = model.bodies[j].parent) {
    const Vec6& s = data.S[j];
    J.col(j).head<3>() = s.head<3>();
    J.col(j).tail<3>() = s.tail<3>() + s.head<3>().cross(point);
  }
}

void pointJacobian(const Model& model, const Data& data, int body, const Vec3& point, Eigen::Ref<Mat3X> J) {
  J.setZero();
  for (int j = body; j >= 0; j = model.bodies[j].parent) {
    const Vec6& s = data.S[j];
    J.col(j) = s.tail<3>() + s.head<3>().cross(point);
  }
}

namespace {
// Velocity of the point under the unit motion of joint l.
inline Vec3 pointMotion(const Vec6& s, const Vec3& point) { return s.tail<3>() + s.head<3>().cross(point); }

// d(J_j)/dθ_l for j, l both ancestors of the body carrying the point.
inline Vec6 columnDerivative(const Model& model, const Data& data, int j, int l, const Vec3& point) {
  const Vec6& Sj = data.S[j];
  const Vec3 dp = pointMotion(data.S[l], point);
  Vec6 d;
  if (model.isAncestor(l, j)) {  // joint l moves joint j's axis and the point rigidly
    const Vec6 dS = crossMotion(data.S[l], Sj);
    d.head<3>() = dS.head<3>();
    d.tail<3>() = dS.tail<3>() + dS.head<3>().cross(point) + Sj.head<3>().cross(dp);
  } else {  // joint l lies beyond j: only the point moves
    d.head<3>().setZero();
    d.tail<3>() = Sj.head<3>().cross(dp);
  }
  return d;
}
}  // namespace

void spatialJacobianDerivative(const Model& model, const Data& data, int body, const Vec3& point, int l,
                               Eigen::Ref<Mat6X> dJ) {
  dJ.setZero();
  if (body < 0 || !model.isAncestor(l, body)) return;
  for (int j = body; j >= 0; j = model.bodies[j].parent) dJ.col(j) = columnDerivative(model, data, j, l, point);
}

void addJacobianTransposeWrenchDerivative(const Model& model, const Data& data, int body, const Vec3& point,
                                          const Vec6& wrench, Eigen::Ref<Eigen::MatrixXd> out) {
  for (int j = body; j >= 0; j = model.bodies[j].parent)
    for (int l = body; l >= 0; l = model.bodies[l].parent) out(j, l) += columnDerivative(model, data, j, l, point).dot(wrench);
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

void basePose(const Model& model, const Data& data, Vec3& position, Vec3& rpy) {
  Mat3 R;
  linkPose(model, data, model.root_link, R, position);
  rpy.y() = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  rpy.x() = std::atan2(R(2, 1), R(2, 2));
  rpy.z() = std::atan2(R(1, 0), R(0, 0));
}

}  // namespace nmdp
