// The residual G(θ, w) of one step and everything the projected gradient method needs from it
// (DESIGN.md 2, 3), in either form:
//
//   NE   G = RNEA(θ, θ̇, θ̈) − Σ_c J_cᵀ V_c(θ) w_c − τ(θ),       K = ½ θ̇ᵀ H(θ) θ̇
//   PBD  G = ∇I(θ) + ∇U(θ) + ∇P(θ) − Σ_c J_cᵀ V_c(θ) w_c,      K = (1/2h²) Σ_k tr(B_k M̄_k B_kᵀ)
//
// with the contact term Σ J_cᵀ (∂V_c/∂θ) w_c of ∂G/∂θ built from the model's dV/dξ (first order),
// from central differences of V (zeroth order; the model's derivative is never requested), or
// dropped (the paper's zeroth-order ∂Ḡ/∂θ). The (∂J_cᵀ/∂θ) V_c w_c term needs no model derivative
// and is always there. A constant generalized
// force System::external_force is subtracted from G in both forms.
//
// NE: ∇K = H θ̇ / h + ∂T/∂q(θ, θ̇) exact (O(n), from RNEA's velocities and momenta), and
// ∇²K = H / h² (Gauss–Newton: the ∂H/∂θ terms dropped, DESIGN.md 2.1).
// PBD: K, ∇K, ∇²K exact.
// Contact-point K (KineticEnergyMeasure::ContactPoints): K = ½ Σ_c ‖u_c‖² with u_c the velocity of
// the sphere centre, J_c θ̇ (NE) or (p_c(θ) − p_c(q_n))/h (PBD); ∇K exact in both (NE adds the
// change of J_c(θ)θ̇ with θ), and the Gauss–Newton ∇²K = Σ J_cᵀ J_c / h² (linear rows of J_c). Armature (rotor inertia) enters the PBD energies as ½ a_j (Δθ_j)²/h² so
// both forms integrate the same H.
#pragma once
#include <Eigen/Cholesky>
#include <vector>

#include "contact_models/finite_difference_derivative.hpp"
#include "multibody/data.hpp"
#include "multibody/pbd_terms.hpp"
#include "solver/bdf2.hpp"
#include "config/integrator_options.hpp"
#include "solver/simulation_state.hpp"
#include "solver/step_stats.hpp"
#include "solver/system.hpp"

namespace nmdp {

enum class Form { NewtonEuler, PositionBased };

class StepResidual {
 public:
  explicit StepResidual(const System& system);

  // Fixes the data of one backward-Euler attempt of size h from (q_n, q̇_n) (NE) or
  // (q_n, q_prev, h_prev) (PBD), with the PD target at the end of the step and the floating-base
  // chart of the state.
  void prepare(const System& system, Form form, double h, const Eigen::VectorXd& q_n, const Eigen::VectorXd& qd_n,
               const Eigen::VectorXd& q_prev, double h_prev, const PdTarget& target, const Mat3& base_chart,
               KineticEnergyMeasure kinetic_energy = KineticEnergyMeasure::FullBody);

  // The same for an attempt of the second-order mode (solver/bdf2.hpp) from (q_n, q̇_n) after the
  // (sub-)step (q_prev, q̇_prev), with the coefficients ĥ, c of that step (BDF2's, or backward
  // Euler's {h, 0}). NE: the backward-Euler residual from (q̂, v̂) with step ĥ. PBD: the inertial
  // target T̂_k + ĥ V̂_k of each body, K against T̂_k over ĥ, the armature and PD terms from
  // (q̂, v̂, ĥ). h() is then ĥ, the step the residual's θ̇ and θ̈ divide by.
  void prepareSecondOrder(const System& system, Form form, const Bdf2Coefficients& coefficients,
                          const Eigen::VectorXd& q_n, const Eigen::VectorXd& qd_n, const Eigen::VectorXd& q_prev,
                          const Eigen::VectorXd& qd_prev, const PdTarget& target, const Mat3& base_chart,
                          KineticEnergyMeasure kinetic_energy = KineticEnergyMeasure::FullBody);

  // The velocity the discretization gives the new state θ: (θ − q_n)/h, or at second order (θ − q̂)/ĥ
  // (NE) and ĥ H(θ)⁻¹ ∇K_body(θ) (PBD, see below). Leaves the kinematics of θ in `data`.
  void velocity(const System& system, const Eigen::VectorXd& theta, Eigen::VectorXd& out);

  // G, ∂G/∂θ (its contact term as `derivative` says), B = Σ J_cᵀ V_c = −∂G/∂w, K, ∇K, ∇²K at (θ, w).
  void evaluate(const System& system, const Eigen::VectorXd& theta, const Eigen::VectorXd& w,
                ContactDerivative derivative);

  // G and K only (with the contact frames and V_c; J_c keep their previous values): what Newton's
  // line search needs, at about a fifth of the cost. ∂G/∂θ, B, ∇K and ∇²K keep their previous values.
  void evaluateValue(const System& system, const Eigen::VectorXd& theta, const Eigen::VectorXd& w);

  // What evaluate() adds to evaluateValue(): ∂G/∂θ, B, ∇K, ∇²K, J_c (and dV/dξ), at the (θ, w) of
  // the last evaluation, whose kinematics and RNEA it reuses (NE: evaluate() is evaluateValue() and
  // this). PBD evaluates from scratch.
  void addDerivatives(const System& system, const Eigen::VectorXd& theta, const Eigen::VectorXd& w,
                      ContactDerivative derivative);

  // Kinematics, contact frames, Jacobians, V_c (no derivative) and B at q only (ne-mdp).
  void evaluateContacts(const System& system, const Eigen::VectorXd& q);

  Form form() const { return form_; }
  double h() const { return h_; }  // the step θ̇ = (θ − q_n)/h divides by (ĥ at second order)
  int weightCount() const { return m_; }

  // Outputs of evaluate().
  Eigen::VectorXd G;
  Eigen::MatrixXd dG_dtheta;  // n×n
  Eigen::MatrixXd B;          // n×m, column block c = J_cᵀ V_c
  double K = 0.0;
  Eigen::VectorXd grad_K;
  Eigen::MatrixXd hess_K;
  std::vector<ContactFrame> frames;
  std::vector<ContactWrenches> wrenches;  // V_c (and dV/dξ unless the term is dropped)
  std::vector<Mat6X> jacobians;           // J_c (6×n)

  Data data;

 private:
  // ∂G/∂θ's contact terms (J_c, V_c, dV/dξ and B on the way), at the current contact frames; G's
  // contact forces are addContactForces'.
  void addContactDerivatives(const System& system, const Eigen::VectorXd& w, ContactDerivative derivative);
  void contactGeometry(const System& system, ContactDerivative derivative);  // J_c, V_c, dV/dξ, B at the frames
  void frameGeometry(const System& system);  // the contact frames
  void addContactForces(const System& system, const Eigen::VectorXd& w);  // G −= Σ J_cᵀ V_c w_c
  // What both orders fix: the form, K, the effective step, the target, the chart and the PD stiffness.
  void prepareStep(const System& system, Form form, double h, const PdTarget& target, const Mat3& base_chart,
                   KineticEnergyMeasure kinetic_energy);
  // PBD: kinematics at θ, G and K without the contacts (and ∂G/∂θ, ∇K, ∇²K with derivatives).
  void positionBasedTerms(const System& system, const Eigen::VectorXd& theta, bool derivatives);

  // NE: K = ½ Σ_k v_kᵀ I_k v_k + ½ Σ_j a_j θ̇_j² from RNEA's world velocities (= ½ θ̇ᵀ H θ̇).
  double bodyKineticEnergy(const Model& model) const;
  // Full-body-pd: ½ Σ_j (k_p,j + k_d,j/h)(θ_j − q_n,j)², the implicit PD's share of ∂G/∂θ as a metric
  // (q̂ and ĥ at second order).
  double pdMetricEnergy(const Eigen::VectorXd& theta) const;
  void contactPointEnergy(const Model& model, bool derivatives);
  std::vector<int> contact_bodies_;  // body of each contact (−1: welded to the world)
  std::vector<std::vector<int>> contact_chains_;  // per contact: its body and the body's ancestors
  void addKineticEnergyConfigurationGradient(const Model& model);  // += ∂T/∂q (NE)

  Form form_ = Form::NewtonEuler;
  bool second_order_ = false;  // prepared by prepareSecondOrder
  Eigen::LLT<Eigen::MatrixXd> mass_llt_;  // H(θ), for the PBD velocity at second order
  KineticEnergyMeasure kinetic_energy_ = KineticEnergyMeasure::FullBody;
  std::vector<Vec3> contact_points_n_;  // sphere centres at q_n (PBD's contact-point K; extrapolated at order 2)
  std::vector<Vec3> contact_points_prev_;  // at q_prev (order 2)
  double h_ = 0.0;  // ĥ at second order
  int n_ = 0, m_ = 0, K_vertices_ = 0;
  Eigen::VectorXd q_n_, qd_n_;  // the step's start (q̂, v̂ at second order)
  PdTarget target_;
  Eigen::VectorXd pd_hessian_, work_, work2_;
  Eigen::MatrixXd hess_work_;
  // One contact's chain gathered: J_cᵀ on its rows (contiguous columns for the products), and a
  // column of J_cᵀ ∂(V_c w_c)/∂θ.
  Eigen::Matrix<double, Eigen::Dynamic, 6> chain_jacobian_transpose_;
  Eigen::VectorXd chain_column_;
  // PBD: K's targets (T(q_n), or T̂ at order 2) and I's; at order 2 also T and Ṫ at q_n and q_prev.
  BodyTransforms kinetic_targets_, transforms_n_, transforms_prev_, inertial_targets_, rates_n_, rates_prev_;
  Eigen::VectorXd armature_target_;
  Data data_prev_;  // kinematics of q_n and q_prev (PBD targets)
  FiniteDifferenceDerivative finite_difference_;
};

}  // namespace nmdp
