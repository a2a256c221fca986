// Derivation (all quantities world frame, at the origin). Moving q_j rigidly moves the subtree of
// j by the motion S_j; relative to that rigid motion, body velocities and accelerations in the
// subtree change by δv = u_j and δa_i = a_λ(j) × S_j + u_j × (v_i − v_λ(j)), u_j = v_λ(j) × S_j.
// The rigid part cancels in τ_k = S_kᵀ F_k for k in the subtree, leaving
//   ∂τ_k/∂q_j = S_kᵀ [Ic_k x_j + Bc_k u_j + u_j ×* hc_k],  x_j = a_λ(j) × S_j − u_j × v_λ(j),
// with subtree sums Ic = Σ I_i, hc = Σ I_i v_i and Bc = Σ (crf(v_i) I_i − I_i crm(v_i)) (the rate
// of change of the world inertia, a symmetric matrix). For an ancestor k of j,
// ∂τ_k/∂q_j = S_kᵀ (S_j ×* F_j + the bracket at k = j). Likewise
//   ∂τ_k/∂q̇_j = S_kᵀ [2 Ic_k u_j + Bc_k S_j + S_j ×* hc_k]   (bracket at k = j above j).
// S_kᵀ (a ×* hc_k) = a · w_k with w_k = −S_k ×* hc_k, so every pair costs four 6-D dot products.
#include "multibody/rnea_derivatives.hpp"

#include "multibody/rnea.hpp"

namespace nmdp {

namespace {
// crf(v) I − I crm(v) for a world inertia I = [Ī, [h]×; [h]×ᵀ, m 1] (as spatialInertia builds it)
// and v = [ω; v_o]: the rate of I as the body moves with v. Since I is linear in (Ī, h, m), it is
//   [Ī', [h']×; [h']×ᵀ, 0],  h' = ω × h + m v_o,  Ī' = M + Mᵀ + 2 (h·v_o) 1,  M = [ω]× Ī − h v_oᵀ,
// which costs three cross products instead of six 3×3 matrix products.
inline void inertiaRate(const Mat6& I, const Vec6& v, Mat6& out) {
  const Vec3 w = v.head<3>(), vo = v.tail<3>();
  const Vec3 h(I(2, 4), I(0, 5), I(1, 3));
  Mat3 M;
  for (int c = 0; c < 3; ++c) M.col(c) = w.cross(I.block<3, 1>(0, c)) - h * vo[c];
  out.topLeftCorner<3, 3>() = M + M.transpose();
  out.topLeftCorner<3, 3>().diagonal().array() += 2.0 * h.dot(vo);
  const Vec3 hdot = w.cross(h) + I(3, 3) * vo;
  out.topRightCorner<3, 3>() = skew(hdot);
  out.bottomLeftCorner<3, 3>() = skew(-hdot);
  out.bottomRightCorner<3, 3>().setZero();
}
}  // namespace

void rneaDerivatives(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     const Eigen::VectorXd& qdd) {
  rnea(model, data, q, qd, qdd);  // kinematics, v, a, composite forces F (in data.f), τ
  rneaDerivativesAfterRnea(model, data);
}

void rneaDerivativesAfterRnea(const Model& model, Data& data) {
  const int n = model.nq;

  Vec6 a0;
  a0 << Vec3::Zero(), -model.gravity;
  for (int i = 0; i < n; ++i) {
    const int parent = model.bodies[i].parent;
    const Vec6 vp = parent >= 0 ? data.v[parent] : Vec6::Zero();
    const Vec6 ap = parent >= 0 ? data.a[parent] : a0;
    data.u_dq[i] = crossMotion(vp, data.S[i]);
    data.x_dq[i] = crossMotion(ap, data.S[i]) - crossMotion(data.u_dq[i], vp);
    data.Ic[i] = data.Iw[i];
    if (!model.bodies[i].hasInertia()) {  // Iw = 0: no momentum, no inertia rate
      data.hc[i].setZero();
      data.Bc[i].setZero();
      continue;
    }
    data.hc[i].noalias() = data.Iw[i] * data.v[i];
    inertiaRate(data.Iw[i], data.v[i], data.Bc[i]);
  }
  for (int i = n - 1; i >= 0; --i) {
    const int parent = model.bodies[i].parent;
    if (parent < 0) continue;
    data.Ic[parent] += data.Ic[i];
    data.hc[parent] += data.hc[i];
    data.Bc[parent] += data.Bc[i];
  }

  for (int k = 0; k < n; ++k) {
    const Vec6& Sk = data.S[k];
    const Vec6 sI = data.Ic[k] * Sk;  // = Ic_kᵀ S_k
    const Vec6 sB = data.Bc[k] * Sk;  // Bc is symmetric
    const Vec6 sBw = sB - crossForce(Sk, data.hc[k]);
    // Joints j on the path from the root to k (j ⪯ k).
    for (int j = k; j >= 0; j = model.bodies[j].parent) {
      const Vec6& u = data.u_dq[j];
      data.dtau_dq(k, j) = sI.dot(data.x_dq[j]) + sBw.dot(u);
      data.dtau_dv(k, j) = 2.0 * sI.dot(u) + sBw.dot(data.S[j]);
      data.H(k, j) = data.H(j, k) = sI.dot(data.S[j]);
    }
    data.H(k, k) += model.bodies[k].armature;
    // Strict ancestors i of k see the change of k's whole subtree force.
    const Vec6& u = data.u_dq[k];
    const Vec6 dF_dq = crossForce(Sk, data.f[k]) + data.Ic[k] * data.x_dq[k] + data.Bc[k] * u + crossForce(u, data.hc[k]);
    const Vec6 dF_dv = 2.0 * (data.Ic[k] * u) + sB + crossForce(Sk, data.hc[k]);
    for (int i = model.bodies[k].parent; i >= 0; i = model.bodies[i].parent) {
      data.dtau_dq(i, k) = data.S[i].dot(dF_dq);
      data.dtau_dv(i, k) = data.S[i].dot(dF_dv);
    }
    // Bodies on other branches do not couple.
    for (int j = model.subtree_end[k]; j < n; ++j)
      data.H(k, j) = data.H(j, k) = data.dtau_dq(k, j) = data.dtau_dq(j, k) = data.dtau_dv(k, j) = data.dtau_dv(j, k) = 0.0;
  }
}

}  // namespace nmdp
