#include "multibody/crba.hpp"

#include "multibody/kinematics.hpp"

namespace nmdp {

void crbaFromKinematics(const Model& model, Data& data) {
  const int n = model.nq;
  for (int i = 0; i < n; ++i) data.Ic[i] = data.Iw[i];
  for (int i = n - 1; i >= 0; --i) {
    const int parent = model.bodies[i].parent;
    if (parent >= 0) data.Ic[parent] += data.Ic[i];
  }
  for (int i = 0; i < n; ++i) {
    const Vec6 F = data.Ic[i] * data.S[i];
    data.H(i, i) = data.S[i].dot(F) + model.bodies[i].armature;
    for (int j = model.bodies[i].parent; j >= 0; j = model.bodies[j].parent) {
      data.H(i, j) = data.S[j].dot(F);
      data.H(j, i) = data.H(i, j);
    }
  }
  // Bodies on different branches do not couple (j past i's subtree is never its descendant).
  for (int i = 0; i < n; ++i)
    for (int j = model.subtree_end[i]; j < n; ++j) data.H(i, j) = data.H(j, i) = 0.0;
}

void crba(const Model& model, Data& data, const Eigen::VectorXd& q) {
  forwardKinematics(model, data, q);
  crbaFromKinematics(model, data);
}

}  // namespace nmdp
