// Preallocated workspace for one Model. Every algorithm writes its results into documented fields
// here; once constructed, stepping-sized calls allocate nothing.
#pragma once
#include <vector>

#include "multibody/model.hpp"

namespace nmdp {

struct Data {
  explicit Data(const Model& model);

  // Reference orientation of the floating base: R_base = base_chart · Rx(q3) Ry(q4) Rz(q5).
  // Re-centred by rebaseFloatingChart() so the angles stay far from gimbal lock.
  Mat3 base_chart = Mat3::Identity();

  // forwardKinematics: world pose of every body frame, world motion axis S_i (6).
  std::vector<Mat3> R;
  std::vector<Vec3> p;
  std::vector<Vec6> S;

  // rnea / rneaDerivatives: world spatial velocity, acceleration (gravity included as a base
  // acceleration), world spatial inertia about the origin, and f: after RNEA's backward pass, the
  // composite force of each body's subtree.
  std::vector<Vec6> v, a;
  std::vector<Mat6> Iw;
  std::vector<Vec6> f;
  Eigen::VectorXd tau;  // nq: RNEA output (gravity, armature included)

  // crba / rneaDerivatives
  std::vector<Mat6> Ic;  // composite world inertia of each subtree
  Eigen::MatrixXd H;     // nq×nq joint-space mass matrix (symmetric, full)

  // rneaDerivatives: ∂τ/∂q, ∂τ/∂q̇ (∂τ/∂q̈ = H).
  Eigen::MatrixXd dtau_dq, dtau_dv;
  std::vector<Vec6> hc;           // composite momentum Σ I_i v_i
  std::vector<Mat6> Bc;           // composite inertia rate Σ (crf(v_i) I_i − I_i crm(v_i))
  std::vector<Vec6> u_dq, x_dq;   // per-body seeds of the q-derivative

  // PBD terms
  std::vector<Mat43> P;       // composite T̃_k M̄_k A_kᵀ
  std::vector<Vec4> first;    // composite T̃_k M̄_k e4 = (m c, m) in world frame
  std::vector<Mat4> Q;        // composite T̃_k M̄_k T̃_kᵀ

  Eigen::VectorXd qd_work, qdd_work;  // nq scratch for residuals built on RNEA
};

}  // namespace nmdp
