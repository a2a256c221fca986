#include "multibody/rnea.hpp"

#include "multibody/kinematics.hpp"

namespace nmdp {

void rneaFromKinematics(const Model& model, Data& data, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
  Vec6 a0;
  a0 << Vec3::Zero(), -model.gravity;
  for (int i = 0; i < model.nq; ++i) {
    const int parent = model.bodies[i].parent;
    const Vec6& S = data.S[i];
    if (parent < 0) {
      data.v[i] = S * qd[i];
      data.a[i] = a0 + S * qdd[i];
    } else {
      data.v[i] = data.v[parent] + S * qd[i];
      data.a[i] = data.a[parent] + S * qdd[i] + crossMotion(data.v[parent], S) * qd[i];
    }
    if (!model.bodies[i].hasInertia()) {  // Iw = 0: no force of its own
      data.f[i].setZero();
      continue;
    }
    const Vec6 h = data.Iw[i] * data.v[i];
    data.f[i].noalias() = data.Iw[i] * data.a[i];
    data.f[i] += crossForce(data.v[i], h);
  }
  for (int i = model.nq - 1; i >= 0; --i) {
    data.tau[i] = data.S[i].dot(data.f[i]) + model.bodies[i].armature * qdd[i];
    const int parent = model.bodies[i].parent;
    if (parent >= 0) data.f[parent] += data.f[i];
  }
}

void rnea(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
  forwardKinematics(model, data, q);
  rneaFromKinematics(model, data, qd, qdd);
}

double kineticEnergy(const Model& model, Data& data, const Eigen::VectorXd& qd) {
  double T = 0.0;
  for (int i = 0; i < model.nq; ++i) {
    const int parent = model.bodies[i].parent;
    data.v[i] = data.S[i] * qd[i];
    if (parent >= 0) data.v[i] += data.v[parent];
    T += 0.5 * data.v[i].dot(data.Iw[i] * data.v[i]) + 0.5 * model.bodies[i].armature * qd[i] * qd[i];
  }
  return T;
}

}  // namespace nmdp
