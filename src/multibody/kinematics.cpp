#include "multibody/kinematics.hpp"

#include "multibody/base_chart.hpp"

namespace nmdp {

namespace {
// The index of a coordinate axis ±e_a, or −1 for a general axis. URDF joints mostly turn about
// ±x, ±y or ±z; then turning a frame mixes two of its columns and the world axis is a column.
int coordinateAxis(const Vec3& axis) {
  for (int a = 0; a < 3; ++a)
    if (std::abs(axis[a]) == 1.0 && axis[(a + 1) % 3] == 0.0 && axis[(a + 2) % 3] == 0.0) return a;
  return -1;
}
}  // namespace

void forwardKinematics(const Model& model, Data& data, const Eigen::VectorXd& q) {
  for (int i = 0; i < model.nq; ++i) {
    const Body& b = model.bodies[i];
    const Mat3& Rplace = b.uses_base_chart ? data.base_chart : b.placement_rotation;
    // R and p first hold the joint frame at q_i = 0.
    Mat3& R = data.R[i];
    Vec3& p = data.p[i];
    if (b.parent < 0) {
      R = Rplace;
      p = b.placement_translation;
    } else {
      const Mat3& Rp = data.R[b.parent];
      p.noalias() = Rp * b.placement_translation;
      p += data.p[b.parent];
      if (Rplace == Mat3::Identity())
        R = Rp;
      else
        R.noalias() = Rp * Rplace;
    }
    const int a = coordinateAxis(b.axis);
    const Vec3 axis = a >= 0 ? Vec3(b.axis[a] * R.col(a)) : Vec3(R * b.axis);
    if (b.kind == JointKind::Revolute) {
      if (a >= 0) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        const double c = std::cos(q[i]), s = b.axis[a] * std::sin(q[i]);
        const Vec3 ru = R.col(u), rv = R.col(v);
        R.col(u) = c * ru + s * rv;
        R.col(v) = c * rv - s * ru;
      } else {
        R = (R * rotationAbout(b.axis, q[i])).eval();
      }
      data.S[i].head<3>() = axis;  // (not a comma initializer: GCC 12 warns on its 4-wide loads of a Vec3)
      data.S[i].tail<3>() = p.cross(axis);
    } else {
      p += axis * q[i];
      data.S[i].head<3>().setZero();
      data.S[i].tail<3>() = axis;
    }
    // Virtual base bodies keep Iw = 0.
    if (b.hasInertia()) spatialInertia(b.mass, p + R * b.com, R, b.inertia_com, data.Iw[i]);
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

// With Jacobian columns at the point, J_j = [ω_j; v_j], the derivative of column j along joint l
// is J_l × J_j plus the point's own motion, which simplifies to
//   [ω_l × ω_j; ω_l × v_j]  when l is j or an ancestor of j (l moves j's axis and the point),
//   [0;         ω_j × v_l]  when l lies beyond j (only the point moves).
void spatialJacobianDerivative(const Model& model, const Data& data, int body, const Vec3& point, int l,
                               Eigen::Ref<Mat6X> dJ) {
  dJ.setZero();
  if (body < 0 || !model.isAncestor(l, body)) return;
  const Vec3 wl = data.S[l].head<3>();
  const Vec3 vl = data.S[l].tail<3>() + wl.cross(point);
  for (int j = body; j >= 0; j = model.bodies[j].parent) {
    const Vec3 wj = data.S[j].head<3>();
    if (j >= l) {
      dJ.col(j).head<3>() = wl.cross(wj);
      dJ.col(j).tail<3>() = wl.cross(data.S[j].tail<3>() + wj.cross(point));
    } else {
      dJ.col(j).tail<3>() = wj.cross(vl);
    }
  }
}

// With f = [τ; F]: for l ⪯ j the entry is ω_l · (ω_j × τ + v_j × F); for l beyond j it is
// ω_j · (v_l × F). Per contact: two cross products per joint and one dot product per pair.
void addJacobianTransposeWrenchDerivative(const Model& model, const Data& data, int body, const Vec3& point,
                                          const Vec6& wrench, Eigen::Ref<Eigen::MatrixXd> out) {
  const Vec3 torque = wrench.head<3>(), force = wrench.tail<3>();
  for (int j = body; j >= 0; j = model.bodies[j].parent) {
    const Vec3 wj = data.S[j].head<3>();
    const Vec3 vj = data.S[j].tail<3>() + wj.cross(point);
    const Vec3 aj = wj.cross(torque) + vj.cross(force);  // paired with ancestors l ⪯ j
    const Vec3 bj = vj.cross(force);                      // paired with joints j' before j
    out(j, j) += wj.dot(aj);
    for (int l = model.bodies[j].parent; l >= 0; l = model.bodies[l].parent) {
      // ω_l = 0 for a prismatic l (the base translations, ancestors of every contact): both
      // entries vanish.
      if (model.bodies[l].kind == JointKind::Prismatic) continue;
      out(j, l) += data.S[l].head<3>().dot(aj);
      out(l, j) += data.S[l].head<3>().dot(bj);
    }
  }
}

void basePose(const Model& model, const Data& data, Vec3& position, Vec3& rpy) {
  Mat3 R;
  linkPose(model, data, model.root_link, R, position);
  rpy = rpyOf(R);
}

}  // namespace nmdp
