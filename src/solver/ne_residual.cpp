#include "solver/ne_residual.hpp"

#include "multibody/rnea.hpp"
#include "multibody/rnea_derivatives.hpp"

namespace nmdp {

void neInertialResidual(const Model& model, Data& data, const Eigen::VectorXd& theta, const Eigen::VectorXd& q_n,
                        const Eigen::VectorXd& qd_n, double h, Eigen::VectorXd& G, Eigen::MatrixXd* dG_dtheta) {
  const double inv_h = 1.0 / h;
  data.qd_work = (theta - q_n) * inv_h;
  data.qdd_work = (data.qd_work - qd_n) * inv_h;
  rnea(model, data, theta, data.qd_work, data.qdd_work);
  if (dG_dtheta) neInertialJacobian(model, data, h, *dG_dtheta);
  G = data.tau;
}

void neInertialJacobian(const Model& model, Data& data, double h, Eigen::MatrixXd& dG_dtheta) {
  const double inv_h = 1.0 / h;
  rneaDerivativesAfterRnea(model, data);
  dG_dtheta.noalias() = data.dtau_dq + inv_h * data.dtau_dv + (inv_h * inv_h) * data.H;
}

}  // namespace nmdp
