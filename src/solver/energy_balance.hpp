// The energy check that tells a diverged step from a physical one (integrator.hpp, advance()).
//
// The robot's mechanical energy with its PD springs at the target θ̄,
//   E(q, q̇; θ̄) = ½ q̇ᵀH(q)q̇ + U_g(q) + ½ (q − θ̄)ᵀK_p(q − θ̄),
// may not rise over a (sub-)step of size h, the target held at θ̄ = θ̄(t + h) (the one the step
// solved with), by more than what drives the robot can put in during it:
//   W = h/4 · θ̄̇ᵀK_dθ̄̇                      the dampers pulling toward the target velocity:
//                                          h(θ̇ᵀK_dθ̄̇ − θ̇ᵀK_dθ̇) ≤ h/4 · θ̄̇ᵀK_dθ̄̇ for every θ̇;
//     + (τ_ff + f_ext)ᵀ(q_{n+1} − q_n)      feed-forward torques and the constant external force.
// Why an NMDP step satisfies it: multiplying its residual G = 0 (backward Euler, DESIGN.md 2.1) by
// q_{n+1} − q_n = hθ̇ gives ΔE = W_d − ½ΔvᵀHΔv − ½ΔqᵀK_pΔq + (contact work) + O(h·|Ḣ|·|v|·|Δv|,
// |∂²U_g|·|Δq|²): backward Euler and the stable PD only dissipate, and maximal dissipation picks
// contact forces that do no positive work (the origin of every wrench space is feasible). The PBD
// form is the same in the limit. What remains is the discretization's second-order error, which
// the tolerance covers (IntegratorOptions::energy_tolerance).
// An explicit step (ne-mdp) has no such bound: past its stability limit its PD springs and the
// mass-matrix update inject energy, by orders of magnitude at once.
//
// Everything here allocates nothing (Data is preallocated); nothing prints.
#pragma once
#include <Eigen/Core>

#include "control/stable_pd.hpp"
#include "multibody/data.hpp"

namespace nmdp {

// ½ q̇ᵀH(q)q̇ and U_g(q) = −Σ m_k gᵀc_k(q) (zero at the world origin), J. Runs CRBA into `data`.
struct MechanicalEnergy {
  double kinetic = 0.0;
  double gravity = 0.0;
  double total() const { return kinetic + gravity; }
};
MechanicalEnergy mechanicalEnergy(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);

// ½ Σ_j K_p,j (q_j − θ̄_j)² over the coordinates with gains (others may have any target, even NaN).
double springEnergy(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& q);

// The balance of one (sub-)step from (q_n, q̇_n) to (q_{n+1}, q̇_{n+1}) with the target `target`.
struct EnergyBalance {
  double gain = 0.0;       // E_{n+1} − E_n, J
  double supplied = 0.0;   // W above, J
  double turnover = 0.0;   // the step's energy scale: T_n + T_{n+1} + |ΔU_g| + P_n + P_{n+1} + |W|, J
  double free_fall = 0.0;  // ½ m (‖g‖ h)², J
  double tolerance = 0.0;  // ρ · turnover + free_fall, J
  double excess() const { return gain - supplied; }
  bool diverged() const { return !(excess() <= tolerance); }  // NaN counts as diverged
};

// `relative_tolerance` is ρ above.
EnergyBalance energyBalance(const Model& model, const MechanicalEnergy& before, const MechanicalEnergy& after,
                            const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& external_force,
                            const Eigen::VectorXd& q_before, const Eigen::VectorXd& q_after, double h,
                            double relative_tolerance);

}  // namespace nmdp
