// Analytic derivatives of RNEA (world-frame composite form, O(n·depth)):
// ∂τ/∂q into data.dtau_dq, ∂τ/∂q̇ into data.dtau_dv, and H = ∂τ/∂q̈ into data.H; τ into data.tau.
#pragma once
#include "multibody/data.hpp"

namespace nmdp {

void rneaDerivatives(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     const Eigen::VectorXd& qdd);

// The same after rnea(model, data, q, qd, qdd) has run with those arguments (data holds its results).
void rneaDerivativesAfterRnea(const Model& model, Data& data);

}  // namespace nmdp
