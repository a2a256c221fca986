// Position-based dynamics terms (DESIGN.md 2.2), closed form from each body's homogeneous second
// moment M̄ = [[∫ρxxᵀ, m c], [m cᵀ, m]]: for constant 3×4 targets C_k,
//   E(θ) = 1/(2h²) Σ_k tr((T_k(θ) − C_k) M̄_k (T_k(θ) − C_k)ᵀ),
// which is I(θ) with C_k = (1+α) T_k(q_n) − α T_k(q_{n−1}) and K(θ) with C_k = T_k(q_n) (first order),
// or, at second order, I(θ) with C_k = T̂_k + ĥ V̂_k and K(θ) with C_k = T̂_k over ĥ (BDF2 in each
// body's transform: T̈_k ≈ (T_k(θ) − T̂_k − ĥ V̂_k)/ĥ², see secondOrderTargets).
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

// Ṫ_k = v̂_k T_k, the rates of the world transforms at velocity q̇ (after forwardKinematics at q),
// with v_k = Σ_{j ⪯ k} S_j q̇_j the body's world spatial velocity (left in data.v).
void bodyTransformRates(const Model& model, Data& data, const Eigen::VectorXd& qd, BodyTransforms& out);

// The second-order (BDF2) targets: T̂_k = T_k,n + c (T_k,n − T_k,n−1), V̂_k = Ṫ_k,n + c (Ṫ_k,n − Ṫ_k,n−1),
// and the inertial target T̂_k + ĥ V̂_k (solver/bdf2.hpp gives c and ĥ). `kinetic` is T̂.
void secondOrderTargets(const BodyTransforms& current, const BodyTransforms& current_rates,
                        const BodyTransforms& previous, const BodyTransforms& previous_rates, double extrapolation,
                        double h_hat, BodyTransforms& kinetic, BodyTransforms& inertial);

// E(θ) above, on the current kinematics (forwardKinematics at θ). grad (nq) and hess (nq×nq) are
// optional outputs.
double transformEnergy(const Model& model, Data& data, const BodyTransforms& targets, double h, Eigen::VectorXd* grad,
                       Eigen::MatrixXd* hess);

// Gravity potential U(θ) = −Σ m_k gᵀ c_k(θ) with gradient (= RNEA at rest) and exact Hessian.
double gravityPotential(const Model& model, Data& data, Eigen::VectorXd* grad, Eigen::MatrixXd* hess);

}  // namespace nmdp
