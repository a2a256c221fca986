// What a time step returns: its status and statistics.
#pragma once

namespace nmdp {

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

// Adds the solver's iteration counts of one attempt (outer iterations, G evaluations, projections,
// Newton iterations, rejected moves) to a step's total.
void addIterationCounts(StepStats& total, const StepStats& attempt);

}  // namespace nmdp
