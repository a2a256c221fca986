// How straight a floating-base trot of a repository scene walks: the forward distance along the start
// heading, the largest |yaw| from the start heading (unwrapped) and the largest offset from the start
// line (tests of the heading feedback and of the walk on 3-D sand).
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "scene_simulation.hpp"

namespace nmdp::test {

struct HeadingRun {
  double forward = 0.0;      // m along the start heading at the end
  double max_yaw = 0.0;      // rad, largest |yaw − start yaw|
  double max_lateral = 0.0;  // m, largest |offset| from the start line
  bool completed = false;    // every step converged
};

inline HeadingRun runHeading(const std::string& scene, const std::vector<std::string>& overrides) {
  Simulation sim = repositorySimulation(scene, overrides);
  Vec3 start, start_rpy, position, rpy;
  sim.basePose(start, start_rpy);
  const Vec3 heading(std::cos(start_rpy.z()), std::sin(start_rpy.z()), 0.0), left(-heading.y(), heading.x(), 0.0);
  HeadingRun run;
  double yaw = start_rpy.z(), previous = start_rpy.z();
  for (long i = 0; i < sim.scheduledSteps(); ++i) {
    if (!sim.step().converged) return run;
    sim.basePose(position, rpy);
    yaw += std::remainder(rpy.z() - previous, 2 * M_PI);  // unwrapped
    previous = rpy.z();
    run.max_yaw = std::max(run.max_yaw, std::abs(yaw - start_rpy.z()));
    run.max_lateral = std::max(run.max_lateral, std::abs(left.dot(position - start)));
  }
  run.forward = heading.dot(position - start);
  run.completed = true;
  return run;
}

}  // namespace nmdp::test
