// The local error of one accepted (sub-)step, which integrator.accuracy (error control) bounds.
//
// A step of order p leaves a position error C h^{p+1} q^{(p+1)} (the exact solution put into the
// step's formula); q^{(p+1)} = v^{(p)} is estimated by divided differences of the velocities at the
// step's end and the states before it, so the estimate costs no extra solve:
//   order 1 (backward Euler)  e_q = ½ h (v_{n+1} − v_n)
//   order 2 (variable BDF2)   e_q = C(ω) h³ · 2 v[t_{n+1}, t_n, t_{n−1}],  C(ω) = (1+ω)²/(6ω(1+2ω)),
//                             ω = h/h_{n−1}  (C = 2/9 at a constant step)
// The error is measured in the robot's own metric, the kinetic-energy norm ‖x‖_H = √(xᵀH(q)x), which
// weighs every joint and the base by the mass it moves, and judged against the step's own
// displacement plus a floor:
//   err = ‖e_q‖_H / (accuracy · (‖q_{n+1} − q_n‖_H + √m · L_floor)),
// L_floor = 1 cm: the whole robot moved by 1 cm, so that a robot at rest is not asked for relative
// accuracy of nothing, and so that a step across a contact event, whose error is O(h·Δv) for a
// velocity jump Δv however small h is, can meet the tolerance by shrinking. err ≤ 1 accepts the
// step. In smooth motion the estimate falls as h^{p+1}.
#pragma once
#include <Eigen/Core>

#include "multibody/model.hpp"

namespace nmdp {

struct LocalErrorStep {
  int order = 1;          // the order the step was taken with (1 or 2)
  double h = 0.0;         // its size
  double h_prev = 0.0;    // the size of the step before it (order 2)
  const Eigen::VectorXd* q_before = nullptr;  // q_n
  const Eigen::VectorXd* q_after = nullptr;   // q_{n+1}
  const Eigen::VectorXd* v_after = nullptr;   // v_{n+1}
  const Eigen::VectorXd* v_before = nullptr;  // v_n
  const Eigen::VectorXd* v_prev = nullptr;    // v_{n−1} (order 2)
};

class LocalError {
 public:
  explicit LocalError(const Model& model);
  // err above (≥ 0; NaN if the state is not finite), with H = H(q_{n+1}) in the state's chart (the
  // caller has it from the energy check). Allocates nothing.
  double normalized(const LocalErrorStep& step, const Eigen::MatrixXd& H, double accuracy);
  // The next step's size after a step of `order` with normalized error `err`: the standard
  // controller h·0.9·err^{−1/(p+1)}, kept within [0.2 h, 2 h] (2: variable-step BDF2 stays
  // zero-stable for ratios below 1 + √2).
  static double nextStep(double h, double err, int order);

  static constexpr double kFloorLength = 0.01;  // m, L_floor above

 private:
  Eigen::VectorXd error_, displacement_, product_;
  double sqrt_mass_ = 0.0;
};

}  // namespace nmdp
