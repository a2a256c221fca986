// What one time step of the integrator needs and returns (DESIGN.md 2-6): the method, its options,
// the system being simulated, the state carried from step to step, and per-step statistics.
#pragma once
#include <Eigen/Core>
#include <csignal>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "control/stable_pd.hpp"
#include "multibody/model.hpp"
#include "solver/contact_kinematics.hpp"
#include "terrain/terrain.hpp"

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

// What the contact term of ∂G/∂θ is built from in one evaluation of the residual.
enum class ContactDerivative { Model, FiniteDifference, Dropped };

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

// A request to stop that the integrator polls between sub-steps and between the outer iterations
// of a step (e.g. a flag set by a SIGINT handler): once it reads nonzero the step ends with
// StepStatus::Cancelled, the state at its last accepted sub-step. Null: never.
using CancelFlag = const volatile std::sig_atomic_t*;

// The simulated system: robot, contacts, contact model, terrain and joint gains. Referenced, not
// owned; everything must outlive the workspaces built from it.
struct System {
  const Model* model = nullptr;
  std::vector<ContactPoint> contacts;
  const ContactModel* contact_model = nullptr;  // may be null when there are no contacts
  const Terrain* terrain = nullptr;             // may be null when there are no contacts
  PdGains gains;                                // sized nq (zero gains: a passive robot)
  // Constant generalized force added to the actuation (e.g. a push on the base), sized nq or empty.
  Eigen::VectorXd external_force;
};

// Throws std::invalid_argument naming the problem: sizes, missing contact model or terrain, or a
// first-order method with a contact model that has no derivative (suggesting the zeroth-order twin).
void validateSystem(const System& system, const IntegratorOptions& options);

// What carries over from one step to the next.
struct SimulationState {
  double time = 0.0;
  Eigen::VectorXd q, qd;   // configuration and velocity at `time`, in the chart base_chart
  Eigen::VectorXd q_prev;  // configuration one (sub-)step earlier (PBD, BDF2), same chart
  Eigen::VectorXd qd_prev;  // velocity one (sub-)step earlier (BDF2), same chart
  double h_prev = 0.0;     // size of that (sub-)step
  // Whether (q_prev, qd_prev, h_prev) is an accepted (sub-)step in the current chart that a
  // second-order step may build on: false at the start, after a chart rebase (the base angle rates
  // are chart-dependent) and after a sub-step in which a contact touched down (see contact_active);
  // true after every other accepted sub-step.
  bool second_order_history = false;
  // Per contact: whether it carried force in the last sub-step. A contact that starts to carry force
  // is an impact, a jump of the velocity inside the sub-step. BDF2 across it would carry the
  // position's extrapolation past the contact, and BDF2 after it would extrapolate the jump into a
  // rebound; so at order 2 a sub-step in which a contact touches down is retaken at first order, and
  // so are the two after it (a compliant contact's impact at a coarse step ends within the next),
  // as multistep methods restart at a discontinuity.
  std::vector<std::uint8_t> contact_active;
  int substeps_since_touchdown = 2;  // accepted sub-steps since the last touchdown (saturates at 2)
  Mat3 base_chart = Mat3::Identity();  // floating base reference orientation (Data::base_chart)
  double beta = 1e-4;      // trust-region penalty carried over between steps (DESIGN.md 3)
  double beta_start = 1e-4;  // the least β the next step starts from (IntegratorOptions::adapt_start_penalty)
  Eigen::VectorXd w;       // contact weights of the last sub-step (Σ K_c), the warm start
  double h_next = 0.0;     // error control: the next sub-step's size (0: none chosen yet)
};

// Starts at (q, q̇) at time 0; q_prev = q − h q̇ so that PBD starts with the same velocity;
// qd_prev = q̇ and no second-order history (the first step is backward Euler).
SimulationState initialState(const System& system, const IntegratorOptions& options, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& qd, double h);

enum class StepStatus {
  Converged,           // the step (every sub-step) converged
  ProjectionFailed,    // Newton on G(·, w) = 0 diverged at the smallest allowed sub-step
  TrustRegionFailed,   // β exceeded β_max
  MaxIterations,       // outer-iteration cap reached
  QpFailed,            // the capped-simplex QP failed
  NonFinite,           // a NaN or infinity appeared (state, model output)
  Diverged,            // converged, but the energy rose beyond what drives the robot can supply
                       // (IntegratorOptions::energy_tolerance); StepStats::energy says by how much
  Cancelled,           // the CancelFlag was raised; the step stopped where it was
};
const char* toString(StepStatus status);

// The energy balance of a (sub-)step (solver/energy_balance.hpp), in J.
struct StepEnergy {
  double excess = 0.0;     // energy gain beyond what the PD targets, feed-forward and external forces supply
  double supplied = 0.0;   // what they can supply
  double turnover = 0.0;   // the sub-step's energy scale (EnergyBalance::turnover)
  double tolerance = 0.0;  // the excess allowed: energy_tolerance · turnover + free_fall
  double free_fall = 0.0;  // ½ m (‖g‖ h)² of the sub-step
};

struct StepStats {
  StepStatus status = StepStatus::Converged;
  bool converged = false;
  int outer_iterations = 0;  // summed over sub-steps and failed attempts
  int g_evaluations = 0;     // evaluations of G (adding ∂G/∂θ to one counts as another)
  int projections = 0;       // calls of the manifold projection
  int newton_iterations = 0;
  int rejected = 0;          // outer iterations rejected by the trust region
  int substeps = 0;          // accepted sub-steps (1 when no split happened)
  double min_substep = 0.0;  // smallest accepted sub-step (s)
  double wall_time = 0.0;    // s
  // Error control (IntegratorOptions::accuracy): the largest normalized local error of the accepted
  // sub-steps (≤ 1 unless a sub-step at min_substep had to be accepted), and the sub-steps it rejected.
  double error_estimate = 0.0;
  int error_rejections = 0;
  // Order 2: sub-steps retaken at first order because a contact touched down in them.
  int first_order_restarts = 0;
  // The sub-step closest to the divergence check's limit (largest excess − tolerance), or the one
  // that failed it.
  StepEnergy energy;
};

}  // namespace nmdp
