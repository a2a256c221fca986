// Variable-step BDF2 (IntegratorOptions::order = 2) as a backward-Euler step from extrapolated data.
//
// With ω = h/h_prev, BDF2 is (α0 y_{n+1} + α1 y_n + α2 y_{n−1})/h = ẏ_{n+1} with
// α0 = (1+2ω)/(1+ω), α1 = −(1+ω), α2 = ω²/(1+ω) (ω = 1: 3/2, −2, 1/2). Applied to q̇ = v, v̇ = a:
//   θ̇ = (θ − q̂)/ĥ,   θ̈ = (θ̇ − v̂)/ĥ,
//   ĥ = h/α0 = h (1+ω)/(1+2ω),   x̂ = −(α1 x_n + α2 x_{n−1})/α0 = x_n + c (x_n − x_{n−1}),  c = ω²/(1+2ω),
// which is backward Euler with (q_n, q̇_n, h) replaced by (q̂, v̂, ĥ). The PBD form applies the
// same extrapolation to each body's transform and its rate (multibody/pbd_terms.hpp).
//
// Variable-step BDF2 is zero-stable while every step ratio stays below 1 + √2. Algorithm 2's
// halving can follow a sub-step of h/4 or less with one of h (the sibling of a split parent), so a
// sub-step whose ratio exceeds that bound is taken at first order instead, as is a step without a
// history (the first, and the first after a chart rebase): backward Euler from the state's (q_n, q̇_n),
// which is the same formula with ĥ = h and c = 0 (in the PBD form: the inertial target T_n + h Ṫ_n,
// from the state's velocity rather than from q_prev as at order 1).
#pragma once

#include "config/integrator_options.hpp"
#include "solver/simulation_state.hpp"
#include "solver/step_stats.hpp"
#include "solver/system.hpp"

namespace nmdp {

struct Bdf2Coefficients {
  double h_hat = 0.0;          // ĥ
  double extrapolation = 0.0;  // c: x̂ = x_n + c (x_n − x_{n−1})
};

inline Bdf2Coefficients bdf2Coefficients(double h, double h_prev) {
  const double omega = h / h_prev;
  return {h * (1.0 + omega) / (1.0 + 2.0 * omega), omega * omega / (1.0 + 2.0 * omega)};
}

// The largest step ratio h/h_prev a second-order step is taken at: 1 + √2.
constexpr double kBdf2MaxStepRatio = 2.414213562373095;

// The coefficients of a (sub-)step of size h from `state` under IntegratorOptions::order = 2: BDF2's
// when the state has a history and h/h_prev ≤ 1 + √2, else backward Euler's {h, 0}.
inline Bdf2Coefficients secondOrderStepCoefficients(const SimulationState& state, double h) {
  if (state.second_order_history && state.h_prev > 0 && h <= kBdf2MaxStepRatio * state.h_prev)
    return bdf2Coefficients(h, state.h_prev);
  return {h, 0.0};
}

}  // namespace nmdp
