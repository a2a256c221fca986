// The inertial part of the NE-form residual (DESIGN.md 2.1), backward Euler with the actual
// sub-step h:  θ̇ = (θ − q_n)/h,  θ̈ = (θ̇ − q̇_n)/h,  G(θ) = RNEA(θ, θ̇, θ̈)  (gravity included),
//   ∂G/∂θ = ∂RNEA/∂q + (1/h) ∂RNEA/∂q̇ + (1/h²) H(θ).
// Contact and PD terms are added on top by the step solver.
#pragma once
#include "multibody/data.hpp"

namespace nmdp {

void neInertialResidual(const Model& model, Data& data, const Eigen::VectorXd& theta, const Eigen::VectorXd& q_n,
                        const Eigen::VectorXd& qd_n, double h, Eigen::VectorXd& G, Eigen::MatrixXd* dG_dtheta);

// ∂G/∂θ alone, after neInertialResidual() at the same θ (data holds its RNEA).
void neInertialJacobian(const Model& model, Data& data, double h, Eigen::MatrixXd& dG_dtheta);

}  // namespace nmdp
