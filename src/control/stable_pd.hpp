// Stable PD control evaluated at the new state (DESIGN.md 2.1, 2.2, 5): the building block both
// integrator forms use for the actuator torque.
//
// Within one step of size h from (q_n, q̇_n) the unknown is θ = q_{n+1}, and the velocity at the new
// state is the backward-Euler one θ̇ = (θ − q_n)/h. With the target (θ̄, θ̄̇) taken at t + h,
//
//   NE form   τ(θ) = −K_p (θ − θ̄) − K_d (θ̇ − θ̄̇) + τ_ff,          ∂τ/∂θ = −(K_p + K_d/h)   (diagonal)
//
// The NE residual is G = RNEA − Σ Jᵀf − τ, so ∂G/∂θ gets +(K_p + K_d/h) on its diagonal.
//
//   PBD form  P(θ) = ½‖θ − θ̄‖²_{K_p} + (h/2)‖(θ − q_n)/h − θ̄̇‖²_{K_d} − τ_ffᵀθ
//             ∇P(θ)  = K_p (θ − θ̄) + (h/2)·2·(1/h)·K_d ((θ − q_n)/h − θ̄̇) − τ_ff
//                    = K_p (θ − θ̄) + K_d (θ̇ − θ̄̇) − τ_ff  =  −τ(θ)
//             ∇²P    = K_p + K_d/h = −∂τ/∂θ                                    (diagonal)
//
// so adding P to the PBD energy E applies exactly the NE-form torque (G = ∇E − ΣJᵀf contains −τ).
// The implementation computes ∇P once and pdTorque negates it (negation is exact in IEEE
// arithmetic), so ∇P == −τ holds bit for bit, not only up to rounding.
//
// The stiffness is "stable" because it is evaluated at the new state: the 1-DOF backward-Euler
// recursion I(θ − q_n)/h² − I q̇_n/h = τ(θ) is unconditionally stable for K_p, K_d ≥ 0, whereas
// explicit PD at (q_n, q̇_n) diverges once h exceeds ~2/ω (tests/control/test_stable_pd.cpp).
//
// Base coordinates (Body::is_base) are unactuated: their gains and τ_ff are zero. A coordinate whose
// K_p, K_d and τ_ff are all zero is skipped outright — it gets exactly zero torque, zero potential,
// zero gradient and Hessian, and its target entries are never read (so they may hold anything,
// even NaN). All vectors are sized nq; every function writes into a preallocated output and
// allocates nothing (outputs are resized only if their size is wrong, which never happens once
// they are sized nq).
#pragma once
#include <Eigen/Core>
#include <utility>

#include "multibody/model.hpp"

namespace nmdp {

struct PdGains {
  Eigen::VectorXd kp;      // N·m/rad (N/m for prismatic joints), ≥ 0, zero on base coordinates
  Eigen::VectorXd kd;      // N·m·s/rad, ≥ 0, zero on base coordinates
  Eigen::VectorXd tau_ff;  // feed-forward torque, zero on base coordinates
};

// Gains with kp[j] = kp_kd(j).first and kd[j] = kp_kd(j).second on every actuated (non-base)
// coordinate j, zero elsewhere, no feed-forward.
template <class KpKd>
PdGains actuatedPdGains(const Model& model, KpKd kp_kd) {
  PdGains g;
  g.kp = Eigen::VectorXd::Zero(model.nq);
  g.kd = Eigen::VectorXd::Zero(model.nq);
  g.tau_ff = Eigen::VectorXd::Zero(model.nq);
  for (int j = 0; j < model.nq; ++j) {
    if (model.bodies[j].is_base) continue;
    const auto [kp, kd] = kp_kd(j);
    g.kp[j] = kp;
    g.kd[j] = kd;
  }
  return g;
}

// θ̄(t+h) and θ̄̇(t+h), sized nq; base entries are ignored.
struct PdTarget {
  Eigen::VectorXd position;
  Eigen::VectorXd velocity;
};

// DESIGN.md 5 reference gains: K_p = 1000, K_d = 1 for a 100 kg robot.
constexpr double kReferencePdMass = 100.0;
constexpr double kReferenceKp = 1000.0;
constexpr double kReferenceKd = 1.0;

// DESIGN.md 5's reference gains scaled *linearly* with the robot's total mass m = model.total_mass:
//   K_p = 1000 · m/100 = 10·m,   K_d = 1 · m/100 = 0.01·m   on every actuated coordinate,
// zero on base coordinates, τ_ff = 0. E.g. a 17.41 kg robot gets K_p = 174.1, K_d = 0.1741. Far
// below critical damping on a real robot (A1: ζ ≈ 0.07 at the knee); the scene default is
// defaultPdGains (control/default_gains.hpp). Kept for tests that need gains without a pose.
// Throws std::invalid_argument if total_mass is not positive and finite.
PdGains massScaledPdGains(const Model& model);

// Throws std::invalid_argument naming the problem unless kp, kd, tau_ff are sized nq, finite,
// kp, kd ≥ 0, and all three are zero on base coordinates.
void validatePdGains(const Model& model, const PdGains& gains);

// τ(θ) of the NE form into tau_out (nq). h > 0.
void pdTorque(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& theta, const Eigen::VectorXd& q_n,
              double h, Eigen::VectorXd& tau_out);

// diag(∂τ/∂θ) = −(K_p + K_d/h) into out (nq).
void pdTorqueJacobianDiagonal(const PdGains& gains, double h, Eigen::VectorXd& out);

// P(θ) of the PBD form.
double pdPotential(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& theta,
                   const Eigen::VectorXd& q_n, double h);

// ∇P(θ) into grad_out (nq); equals −pdTorque(...) exactly.
void pdPotentialGradient(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& theta,
                         const Eigen::VectorXd& q_n, double h, Eigen::VectorXd& grad_out);

// diag(∇²P) = K_p + K_d/h into out (nq); P is quadratic, so this is exact and independent of θ.
void pdPotentialHessianDiagonal(const PdGains& gains, double h, Eigen::VectorXd& out);

}  // namespace nmdp
