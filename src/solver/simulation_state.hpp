// What a simulation carries from one time step to the next.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "multibody/spatial.hpp"
#include "solver/capped_simplex_qp.hpp"
#include "solver/system.hpp"

namespace nmdp {

// The sub-steps after a touchdown that are taken at first order (see contact_active below).
constexpr int kTouchdownRestartSubsteps = 2;

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
  int substeps_since_touchdown = kTouchdownRestartSubsteps;  // accepted sub-steps since the last touchdown (saturates)
  Mat3 base_chart = Mat3::Identity();  // floating base reference orientation (Data::base_chart)
  double beta = 1e-4;      // trust-region penalty carried over between steps (DESIGN.md 3)
  double beta_start = 1e-4;  // the least β the next step starts from (IntegratorOptions::adapt_start_penalty)
  Eigen::VectorXd w;       // contact weights of the last sub-step (Σ K_c), the warm start
  double h_next = 0.0;     // error control: the next sub-step's size (0: none chosen yet)
  // The weight QP's active set at its last solve, where the next solve starts (the QP's warm start,
  // solver/capped_simplex_qp.hpp): at_bound sized Σ K_c, cap sized C; not valid: a cold start. The
  // integrator hands it to the solver at the start of a step and takes it back at the end, so that
  // a run restored from its state repeats bit for bit.
  QpActiveSet qp_warm;
  bool qp_warm_valid = false;
};

// Starts at (q, q̇) at time 0; q_prev = q − h q̇ so that PBD starts with the same velocity;
// qd_prev = q̇ and no second-order history (the first step is backward Euler); the QP starts cold.
SimulationState initialState(const System& system, const IntegratorOptions& options, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& qd, double h);

}  // namespace nmdp
