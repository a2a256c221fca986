// A simulation's whole state as one flat vector of doubles, for the Python bindings' get_state /
// set_state and for rollouts: everything a step reads from the state (SimulationState), so that
// restoring a vector makes the steps that follow repeat bit for bit.
//
// Layout (n = nq, C contacts, m = C·K contact weights), every entry a double, flags 0 or 1:
//   time | q (n) | q̇ (n) | q_prev (n) | q̇_prev (n) | h_prev | second_order_history |
//   contact_active (C) | substeps_since_touchdown | base_chart (9, column-major) | beta | beta_start |
//   w (m) | h_next | qp_warm_valid | qp_warm_at_bound (m) | qp_warm_cap (C)
// 4n + 2m + 2C + 17 entries, so that time, q and q̇ come first: x[0], x[1 : 1+n], x[1+n : 1+2n].
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "solver/simulation_state.hpp"

namespace nmdp {

// Where each part of the flat state starts, and the sizes it was made for.
struct StateLayout {
  int nq = 0, contacts = 0, weights = 0;
  int size() const;           // entries in all
  static constexpr int time = 0;
  int q() const { return 1; }
  int qdot() const { return 1 + nq; }
  // One name per part in order ("time", "q", "qdot", "q_prev", ...) with its offset and length.
  struct Part {
    std::string name;
    int offset, length;
  };
  std::vector<Part> parts() const;
};

StateLayout stateLayout(const System& system);

// Writes `state` into out (resized to layout.size() if its size differs; no allocation otherwise).
// std::invalid_argument if the state's sizes are not the layout's.
void flattenState(const StateLayout& layout, const SimulationState& state, Eigen::VectorXd& out);
// Reads a flat state into `state` (its vectors resized to the layout; a vector of the right size
// keeps its buffer). std::invalid_argument naming the entry and its part ("flat state entry 3
// (q[2]) is nan: expected a finite number") if x has the wrong size, an entry is not finite, h_prev,
// beta or beta_start is not positive, h_next is negative, a flag is not 0 or 1,
// substeps_since_touchdown is not an integer from 0 to 2, or the base chart is not a rotation (to
// 1e-9); then `state` is left as it was.
void unflattenState(const StateLayout& layout, const Eigen::Ref<const Eigen::VectorXd>& x, SimulationState& state);

}  // namespace nmdp
