#include "multibody/pbd_terms.hpp"

namespace nmdp {

namespace {
inline Mat4 homogeneousOf(const Data& data, int k) {
  Mat4 T = Mat4::Identity();
  T.topLeftCorner<3, 3>() = data.R[k];
  T.topRightCorner<3, 1>() = data.p[k];
  return T;
}
// tr(X Y) for X 3×4, Y 4×3.
inline double traceProduct(const Mat34& X, const Mat43& Y) { return (X.array() * Y.transpose().array()).sum(); }
}  // namespace

void bodyTransforms(const Model& model, const Data& data, BodyTransforms& out) {
  out.resize(model.nq);
  for (int k = 0; k < model.nq; ++k) {
    out[k].leftCols<3>() = data.R[k];
    out[k].col(3) = data.p[k];
  }
}

void inertialTargets(const BodyTransforms& current, const BodyTransforms& previous, double alpha, BodyTransforms& out) {
  out.resize(current.size());
  for (size_t k = 0; k < current.size(); ++k) out[k] = (1.0 + alpha) * current[k] - alpha * previous[k];
}

void bodyTransformRates(const Model& model, Data& data, const Eigen::VectorXd& qd, BodyTransforms& out) {
  out.resize(model.nq);
  for (int k = 0; k < model.nq; ++k) {
    const int parent = model.bodies[k].parent;
    data.v[k] = data.S[k] * qd[k];
    if (parent >= 0) data.v[k] += data.v[parent];
    const Vec3 omega = data.v[k].head<3>();
    out[k].leftCols<3>().noalias() = skew(omega) * data.R[k];
    out[k].col(3) = data.v[k].tail<3>() + omega.cross(data.p[k]);
  }
}

void secondOrderTargets(const BodyTransforms& current, const BodyTransforms& current_rates,
                        const BodyTransforms& previous, const BodyTransforms& previous_rates, double extrapolation,
                        double h_hat, BodyTransforms& kinetic, BodyTransforms& inertial) {
  kinetic.resize(current.size());
  inertial.resize(current.size());
  for (size_t k = 0; k < current.size(); ++k) {
    kinetic[k] = current[k] + extrapolation * (current[k] - previous[k]);
    inertial[k] = kinetic[k] + h_hat * (current_rates[k] + extrapolation * (current_rates[k] - previous_rates[k]));
  }
}

double transformEnergy(const Model& model, Data& data, const BodyTransforms& targets, double h, Eigen::VectorXd* grad,
                       Eigen::MatrixXd* hess) {
  const int n = model.nq;
  const double inv_h2 = 1.0 / (h * h);
  double energy = 0.0;
  for (int k = 0; k < n; ++k) {
    const Mat4& M = model.bodies[k].second_moment;
    Mat34 A;
    A.leftCols<3>() = data.R[k];
    A.col(3) = data.p[k];
    A -= targets[k];
    const Eigen::Matrix<double, 4, 3> MA = M * A.transpose();
    energy += 0.5 * inv_h2 * traceProduct(A, MA);
    if (grad || hess) data.P[k].noalias() = homogeneousOf(data, k) * MA;
    if (hess) {
      const Mat4 T = homogeneousOf(data, k);
      data.Q[k].noalias() = T * M * T.transpose();
    }
  }
  if (!grad && !hess) return energy;
  for (int k = n - 1; k >= 0; --k) {
    const int parent = model.bodies[k].parent;
    if (parent < 0) continue;
    data.P[parent] += data.P[k];
    if (hess) data.Q[parent] += data.Q[k];
  }
  if (grad)
    for (int j = 0; j < n; ++j) (*grad)[j] = inv_h2 * traceProduct(motionHat(data.S[j]).topRows<3>(), data.P[j]);
  if (hess) {
    for (int l = 0; l < n; ++l) {
      const Mat4 Sl = motionHat(data.S[l]);
      const Mat43 Y = data.Q[l] * Sl.topRows<3>().transpose();
      for (int j = l; j >= 0; j = model.bodies[j].parent) {
        const Mat4 Sj = motionHat(data.S[j]);
        const Mat34 SjSl = (Sj * Sl).topRows<3>();
        const double value = inv_h2 * (traceProduct(SjSl, data.P[l]) + traceProduct(Sj.topRows<3>(), Y));
        (*hess)(j, l) = (*hess)(l, j) = value;
      }
      for (int j = model.subtree_end[l]; j < n; ++j) (*hess)(l, j) = (*hess)(j, l) = 0.0;
    }
  }
  return energy;
}

double gravityPotential(const Model& model, Data& data, Eigen::VectorXd* grad, Eigen::MatrixXd* hess) {
  const int n = model.nq;
  double U = 0.0;
  for (int k = 0; k < n; ++k) {
    const Mat4& M = model.bodies[k].second_moment;
    data.first[k].noalias() = homogeneousOf(data, k) * M.col(3);  // (m c_world, m)
    U -= model.gravity.dot(data.first[k].head<3>());
  }
  if (!grad && !hess) return U;
  for (int k = n - 1; k >= 0; --k) {
    const int parent = model.bodies[k].parent;
    if (parent >= 0) data.first[parent] += data.first[k];
  }
  for (int l = 0; l < n; ++l) {
    const Mat4 Sl = motionHat(data.S[l]);
    if (grad) (*grad)[l] = -model.gravity.dot((Sl * data.first[l]).head<3>());
    if (hess) {
      const Vec4 Slf = Sl * data.first[l];
      for (int j = l; j >= 0; j = model.bodies[j].parent) {
        const double value = -model.gravity.dot((motionHat(data.S[j]) * Slf).head<3>());
        (*hess)(j, l) = (*hess)(l, j) = value;
      }
      for (int j = model.subtree_end[l]; j < n; ++j) (*hess)(l, j) = (*hess)(j, l) = 0.0;
    }
  }
  return U;
}

}  // namespace nmdp
