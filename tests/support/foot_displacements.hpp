// Where the feet of a quadruped go under a gait target: foot displacements from the standing pose.
#pragma once
#include <array>

#include "control/gait.hpp"
#include "control/leg_ik.hpp"

namespace nmdp::test {

// Foot displacements from standing, by FK of the target joints with the trunk fixed.
inline std::array<Vec3, 4> footDisplacements(const Model& model, const QuadrupedLegs& legs, const StandingPose& pose,
                                             LegIkSolver& ik, const PdTargetSource& source, double t) {
  PdTarget out{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
  source.evaluate(t, out);
  std::array<Vec3, 4> d;
  for (int id = 0; id < 4; ++id) d[id] = ik.footInTrunk(legs.legs[id], out.position) - pose.feet[id];
  return d;
}

}  // namespace nmdp::test
