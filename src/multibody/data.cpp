#include "multibody/data.hpp"

namespace nmdp {

Data::Data(const Model& model) {
  const int n = model.nq;
  R.assign(n, Mat3::Identity());
  p.assign(n, Vec3::Zero());
  for (std::vector<Vec6>* x : {&S, &v, &a, &f, &hc, &u_dq, &x_dq}) x->assign(n, Vec6::Zero());
  for (std::vector<Mat6>* x : {&Iw, &Ic, &Bc}) x->assign(n, Mat6::Zero());
  for (Eigen::MatrixXd* x : {&H, &dtau_dq, &dtau_dv}) x->setZero(n, n);
  for (Eigen::VectorXd* x : {&tau, &qd_work, &qdd_work}) x->setZero(n);
  P.assign(n, Mat43::Zero());
  first.assign(n, Vec4::Zero());
  Q.assign(n, Mat4::Zero());
}

}  // namespace nmdp
