// Position-based dynamics terms (DESIGN.md 2.2), closed form from each body's homogeneous second
// moment M̄ = [[∫ρxxᵀ, m c], [m cᵀ, m]]: for constant 3×4 targets C_k,
//   E(θ) = 1/(2h²) Σ_k tr((T_k(θ) − C_k) M̄_k (T_k(θ) − C_k)ᵀ),
// which is I(θ) with C_k = (1+α) T_k(q_n) − α T_k(q_{n−1}) and K(θ) with C_k = T_k(q_n).
// Gradient and exact Hessian use ∂T_k/∂θ_j = Ŝ_j T_k and ∂²T_k/∂θ_j∂θ_l = Ŝ_j Ŝ_l T_k (j ⪯ l ⪯ k).
#pragma once
#include <vector>

#include "multibody/data.hpp"

namespace nmdp {

using BodyTransforms = std::vector<Mat34>;

// World transforms [R | p] of every body (after forwardKinematics).
void bodyTransforms(const Model& model, const Data& data, BodyTransforms& out);

// C_k = (1+α) T_k(q_n) − α T_k(q_{n−1}), the inertial target of the PBD step.
void inertialTargets(const BodyTransforms& current, const BodyTransforms& previous, double alpha, BodyTransforms& out);

// E(θ) above, on the current kinematics (forwardKinematics at θ). grad (nq) and hess (nq×nq) are
// optional outputs.
double transformEnergy(const Model& model, Data& data, const BodyTransforms& targets, double h, Eigen::VectorXd* grad,
                       Eigen::MatrixXd* hess);

// Gravity potential U(θ) = −Σ m_k gᵀ c_k(θ) with gradient (= RNEA at rest) and exact Hessian.
double gravityPotential(const Model& model, Data& data, Eigen::VectorXd* grad, Eigen::MatrixXd* hess);

}  // namespace nmdp
