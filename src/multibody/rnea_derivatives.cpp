// Derivation (all quantities world frame, at the origin). Moving q_j rigidly moves the subtree of
// j by the motion S_j; relative to that rigid motion, body velocities and accelerations in the
// subtree change by δv = u_j and δa_i = a_λ(j) × S_j + u_j × (v_i − v_λ(j)), u_j = v_λ(j) × S_j.
// The rigid part cancels in τ_k = S_kᵀ F_k for k in the subtree, leaving
//   ∂τ_k/∂q_j = S_kᵀ [Ic_k x_j + (Nc_k − Mc_k) u_j + u_j ×* hc_k],  x_j = a_λ(j) × S_j − u_j × v_λ(j),
// with subtree sums Ic = Σ I_i, hc = Σ I_i v_i, Mc = Σ I_i crm(v_i), Nc = Σ crf(v_i) I_i.
// For an ancestor k of j, ∂τ_k/∂q_j = S_kᵀ (S_j ×* F_j + the bracket at k = j).
// Likewise ∂τ_k/∂q̇_j = S_kᵀ [2 Ic_k u_j + (Nc_k − Mc_k) S_j + S_j ×* hc_k] (bracket at k = j above j).
#include "multibody/rnea_derivatives.hpp"

#include "multibody/rnea.hpp"

namespace nmdp {

void rneaDerivatives(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     const Eigen::VectorXd& qdd) {
  const int n = model.nq;
  rnea(model, data, q, qd, qdd);  // kinematics, v, a, composite forces F (in data.f), τ

  Vec6 a0;
  a0 << Vec3::Zero(), -model.gravity;
  for (int i = 0; i < n; ++i) {
    data.Ic[i] = data.Iw[i];
    data.hc[i].noalias() = data.Iw[i] * data.v[i];
    data.Mc[i].noalias() = data.Iw[i] * crmMatrix(data.v[i]);
    data.Nc[i].noalias() = crfMatrix(data.v[i]) * data.Iw[i];
    const int parent = model.bodies[i].parent;
    const Vec6 vp = parent >= 0 ? data.v[parent] : Vec6::Zero();
    const Vec6 ap = parent >= 0 ? data.a[parent] : a0;
    data.u_dq[i] = crossMotion(vp, data.S[i]);
    data.x_dq[i] = crossMotion(ap, data.S[i]) - crossMotion(data.u_dq[i], vp);
  }
  for (int i = n - 1; i >= 0; --i) {
    const int parent = model.bodies[i].parent;
    if (parent < 0) continue;
    data.Ic[parent] += data.Ic[i];
    data.hc[parent] += data.hc[i];
    data.Mc[parent] += data.Mc[i];
    data.Nc[parent] += data.Nc[i];
  }

  data.dtau_dq.setZero();
  data.dtau_dv.setZero();
  for (int k = 0; k < n; ++k) {
    const Vec6& Sk = data.S[k];
    const Vec6 sI = data.Ic[k] * Sk;  // = (S_kᵀ Ic_k)ᵀ
    const Vec6 sNM = (data.Nc[k] - data.Mc[k]).transpose() * Sk;
    // Joints j on the path from the root to k (j ⪯ k).
    for (int j = k; j >= 0; j = model.bodies[j].parent) {
      const Vec6& u = data.u_dq[j];
      data.dtau_dq(k, j) = sI.dot(data.x_dq[j]) + sNM.dot(u) + Sk.dot(crossForce(u, data.hc[k]));
      data.dtau_dv(k, j) = 2.0 * sI.dot(u) + sNM.dot(data.S[j]) + Sk.dot(crossForce(data.S[j], data.hc[k]));
      data.H(k, j) = data.H(j, k) = sI.dot(data.S[j]);
    }
    data.H(k, k) += model.bodies[k].armature;
    // Strict ancestors i of k see the change of k's whole subtree force.
    const Mat6 NM = data.Nc[k] - data.Mc[k];
    const Vec6& u = data.u_dq[k];
    const Vec6 dF_dq = crossForce(Sk, data.f[k]) + data.Ic[k] * data.x_dq[k] + NM * u + crossForce(u, data.hc[k]);
    const Vec6 dF_dv = 2.0 * (data.Ic[k] * u) + NM * Sk + crossForce(Sk, data.hc[k]);
    for (int i = model.bodies[k].parent; i >= 0; i = model.bodies[i].parent) {
      data.dtau_dq(i, k) = data.S[i].dot(dF_dq);
      data.dtau_dv(i, k) = data.S[i].dot(dF_dv);
    }
  }
  for (int i = 0; i < n; ++i)
    for (int j = model.subtree_end[i]; j < n; ++j) data.H(i, j) = data.H(j, i) = 0.0;
}

}  // namespace nmdp
