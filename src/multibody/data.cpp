#include "multibody/data.hpp"

namespace nmdp {

Data::Data(const Model& model) {
  const int n = model.nq;
  R.assign(n, Mat3::Identity());
  p.assign(n, Vec3::Zero());
  S.assign(n, Vec6::Zero());
  v.assign(n, Vec6::Zero());
  a.assign(n, Vec6::Zero());
  Iw.assign(n, Mat6::Zero());
  f.assign(n, Vec6::Zero());
  tau = Eigen::VectorXd::Zero(n);
  Ic.assign(n, Mat6::Zero());
  H = Eigen::MatrixXd::Zero(n, n);
  dtau_dq = Eigen::MatrixXd::Zero(n, n);
  dtau_dv = Eigen::MatrixXd::Zero(n, n);
  hc.assign(n, Vec6::Zero());
  Bc.assign(n, Mat6::Zero());
  u_dq.assign(n, Vec6::Zero());
  x_dq.assign(n, Vec6::Zero());
  P.assign(n, Mat43::Zero());
  first.assign(n, Vec4::Zero());
  Q.assign(n, Mat4::Zero());
  qd_work = Eigen::VectorXd::Zero(n);
  qdd_work = Eigen::VectorXd::Zero(n);
}

}  // namespace nmdp
