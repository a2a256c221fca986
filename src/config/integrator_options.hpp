// The integrator's configuration (DESIGN.md 2-6): the method and every option of a time step, as a
// scene's "integrator" object sets them.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace nmdp {

// The five methods of the toolkit, by their scene names.
enum class Method { NePgm, NeZopgm, PbdPgm, PbdZopgm, NeMdp };

const char* methodName(Method method);               // "ne-pgm", ...
std::optional<Method> parseMethod(const std::string& name);
const std::vector<std::string>& methodNames();       // every valid name, for messages
inline bool isPositionBased(Method m) { return m == Method::PbdPgm || m == Method::PbdZopgm; }
inline bool isZeroOrder(Method m) { return m == Method::NeZopgm || m == Method::PbdZopgm; }
// Whether the method evaluates the contact model's derivative dV/dξ.
inline bool needsContactDerivative(Method m) { return m == Method::NePgm || m == Method::PbdPgm; }

// The kinetic energy K that maximal dissipation minimizes (DESIGN.md 2): of the whole robot (the
// paper's statement), of unit point masses at the contact points (what the original authors used
// by default: friction then stops the feet sliding rather than the whole body moving), or of the
// whole robot plus ½ Σ_j (h² k_p,j + h k_d,j) θ̇_j² (full-body-pd). The last makes ∇²K the step's
// ∂G/∂θ = H/h² + K_p + K_d/h (Gauss–Newton), so that for linear dynamics minimizing K gives each
// contact the force of largest dissipation at the step's end velocity, the rigid Coulomb law, at
// any h; the full-body K does so only as h → 0 (the implicit PD is outside its metric), and the two
// are the same without PD gains. docs/INTEGRATOR.md, "Which friction law K stands for".
// full-body-pd is the default (the law a user's robot should get at any step); full-body is the
// paper's and stays selectable.
enum class KineticEnergyMeasure { FullBody, ContactPoints, FullBodyPd };
const char* kineticEnergyName(KineticEnergyMeasure k);  // "full-body", "contact-points", "full-body-pd"
std::optional<KineticEnergyMeasure> parseKineticEnergy(const std::string& name);

// How the zeroth-order methods account for the change of the vertices with the pose, the term
// Σ_c J_cᵀ (∂V_c/∂θ) w_c of ∂G/∂θ, without asking the model for a derivative:
//  - FiniteDifference: dV/dξ by central differences of V (12 extra evaluations per contact). The
//    step then has the first-order method's exact direction and solution, to the differences' accuracy.
//  - Dropped: the paper's ∂Ḡ/∂θ, the term left out. Its Newton steps and QP model lack the contact
//    stiffness, so at large steps on stiff ground the step splits, and it stops where the projected
//    inexact gradient vanishes, which is not in general the first-order solution.
enum class ZerothOrderJacobian { FiniteDifference, Dropped };
const char* zerothOrderJacobianName(ZerothOrderJacobian z);  // "finite-difference", "dropped"
std::optional<ZerothOrderJacobian> parseZerothOrderJacobian(const std::string& name);

struct IntegratorOptions {
  Method method = Method::NePgm;
  // The order of the time discretization of the NMDP methods (solver/bdf2.hpp): 1 is the paper's
  // backward Euler; 2 is variable-step BDF2 (its NE form is backward Euler's residual from the
  // extrapolated (q̂, v̂) with step ĥ; its PBD form applies BDF2 to each body's transform). A step
  // without a BDF2 history (the first after initialState or a chart rebase) or after a sub-step
  // shorter than h/(1+√2) is a backward-Euler step from (q_n, q̇_n). ne-mdp is first order only.
  int order = 1;
  KineticEnergyMeasure kinetic_energy = KineticEnergyMeasure::FullBodyPd;
  bool adaptive = true;          // Algorithm 2: halve a failed step down to min_substep
  double min_substep = 1e-5;     // s
  // Projected gradient method (DESIGN.md 3).
  double epsilon = 1e-6;         // accept-and-stop threshold on the K decrease (J) and on ‖Δθ‖∞
  double tol_w = 1e-8;           // stop when ‖Σ_c J_cᵀV_cΔw_c‖∞ < tol_w·m‖g‖ (Δw as a generalized force)
  // Trust-region relaxation: β ← max(β/η, β_min) after an accepted step. DESIGN.md's reference is
  // 1.5; 5 reaches the penalty a step's long first moves need in fewer directions (each a
  // factorization, a solve for D and a QP), and a move that overshoots is rejected at ×η_reject.
  // It takes about a seventh fewer instructions than 1.5 on the A1 and RoboSimian walks
  // (docs/INTEGRATOR.md).
  double eta = 5.0;
  // β ← η_reject·β after a rejected one. DESIGN.md uses η both ways; the QP's model fails by far
  // when it fails (a 1.5× penalty barely shortens the step), so a sharp increase wastes fewer
  // projections: on the trot, 10 takes 72 G evaluations per step against 135 with 1.5.
  double eta_reject = 10.0;
  // β ← max(β/η_limited, β_min) instead after an accepted move that the penalty, not the QP's model,
  // limited: the model agreed with K (ρ > 0.75) and predicted at least 0.3 of the decrease of the
  // step's previous move, so K is still falling at about the same pace. On the A1 trot a step's
  // first moves go on like that for ten at ρ ≈ 1 while β relaxes by η; near the solution the
  // predicted decreases shrink faster, and those moves relax by η as before. η_limited = η gives
  // DESIGN.md's rule. It paid with η = 1.5 (η_limited = 3); with η = 5 a larger η_limited gains
  // nothing measurable (10: A1 6.87 against 6.91 outer iterations per step), so by default the two
  // are equal and the rule is DESIGN.md's. Measured in docs/INTEGRATOR.md.
  double eta_limited = 5.0;
  double beta_min = 1e-4;
  double beta_max = 1e6;
  double beta_initial = 1e-4;    // β of the first step; later steps inherit it (SimulationState::beta)
  // Start each step from at least the β its predecessor's first move called for, not only from the
  // β its last moves relaxed to (DESIGN.md carries the latter, usually β_min). The first move of a
  // step is the long one; from β_min on stiff ground it jumps so far that its projection takes many
  // damped Newton iterations and K falls by 0.4× the QP's prediction. Its agreement ratio ρ sets the
  // next step's starting β the way a trust region's radius is set: ρ < 0.5 doubles the β it was
  // accepted at, ρ > 0.9 halves it. Measured in docs/INTEGRATOR.md.
  bool adapt_start_penalty = true;
  int max_outer_iterations = 100;
  // Manifold projection: Newton on G(·, w) = 0.
  double projection_tolerance = 1e-9;  // ‖G‖∞ relative to the robot's weight m‖g‖ (or m·1 m/s²)
  int projection_max_iterations = 30;
  // A Newton step is accepted only if it decreases ‖G‖∞ (DESIGN.md 3); before calling the
  // projection diverged, a step that does not may be halved this many times (0: full steps only, as
  // the paper). Measured on the quadruped landing at dt = 50 ms: no splits with 10, splits without.
  int projection_backtracking = 10;
  // The zeroth-order methods' stand-in for the model's derivative (see ZerothOrderJacobian; their cost
  // on the trot is in docs/INTEGRATOR.md).
  ZerothOrderJacobian zeroth_order_jacobian = ZerothOrderJacobian::FiniteDifference;
  // Start Newton from θ = q_n + h q̇_n instead of q_n (DESIGN.md 3 allows a better predictor).
  bool predict_first_iterate = false;  // measured on the trot: 8 % fewer outer iterations, 7 % of steps split
  // Start each step from the previous step's contact weights instead of w = 0 (both are feasible;
  // DESIGN.md 3 starts from 0). Measured: on the flat trot at 50 ms, w = 0 takes 20 % fewer outer
  // iterations and 31–46 % fewer instructions (its first projection is the contact-free step, a few
  // Newton iterations, against about nine damped ones from the old weights at q_n) and gives the
  // same sand trot (1.7253 m either way); but the per-step problem is nonconvex, and from w = 0 the
  // RoboSimian walk finds other steps (2.19 m in 10 s, unevenly, against 2.89 m), and the paper's
  // dropped-term zeroth order stops short of sticking (a pushed block creeps 3e-4 m in 1 s). Kept on.
  bool warm_start_weights = true;
  // The divergence check (solver/energy_balance.hpp): a converged (sub-)step whose energy rises by
  // more than the PD targets, feed-forward and external forces can supply, plus this share of the
  // step's energy turnover, fails with StepStatus::Diverged. 0.5 sits between the NMDP methods'
  // largest excess (about a third of it) and ne-mdp's first unphysical step past its stability
  // limit (about twice it). Infinity disables the check.
  double energy_tolerance = 0.5;
  // Error control (solver/local_error.hpp): a relative tolerance on each sub-step's estimated local
  // position error. Above 0, a step of dt is covered by sub-steps a standard controller sizes (never
  // above dt, the output still every dt); the failure halving of Algorithm 2 stays. 0: off, every
  // step is dt unless it fails (the paper's Algorithm 2 alone). On by default at 0.01: with it the
  // trots and walks of the step-size evaluation stay near their 1 ms runs from 5 to 50 ms, without
  // it they drift by up to 79 % (docs/RESULTS.md).
  double accuracy = 0.01;
};

}  // namespace nmdp
