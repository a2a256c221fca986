// The default trot on a floating base holds its heading and its line (control/heading_feedback.hpp):
// the project's quadruped on rigid ground, with the feedback on and, to show the drift it removes,
// off.
#include <cmath>

#include "scene_simulation.hpp"

namespace nmdp::test {
namespace {

struct HeadingRun {
  double forward = 0.0;      // m along the start heading at the end
  double max_yaw = 0.0;      // rad, largest |yaw − start yaw|
  double max_lateral = 0.0;  // m, largest |offset| from the start line
  bool completed = false;
};

HeadingRun runTrot(const std::vector<std::string>& overrides) {
  Simulation sim = repositorySimulation("quadruped_trot_flat.json", overrides);
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

// The bounds: |yaw| < 0.1 rad and the sideways drift below 5 % of the forward distance.
constexpr double kMaxYaw = 0.1;
constexpr double kMaxLateralShare = 0.05;

class TrotHeading : public ::testing::TestWithParam<double> {};

TEST_P(TrotHeading, FloatingQuadrupedHoldsItsHeadingAndLine) {
  const std::string dt = "integrator.dt=" + std::to_string(GetParam());
  const HeadingRun on = runTrot({dt});  // the scene's 10 s
  ASSERT_TRUE(on.completed);
  EXPECT_GT(on.forward, 3.0);  // it walks as far as without the feedback (3.7 m in 10 s)
  EXPECT_LT(on.max_yaw, kMaxYaw);
  EXPECT_LT(on.max_lateral, kMaxLateralShare * on.forward);

  // Without the feedback the same trot turns away: the test above can fail.
  const HeadingRun off = runTrot({dt, "controller.gait.heading_feedback=false"});
  ASSERT_TRUE(off.completed);
  EXPECT_GT(off.max_yaw, 2 * on.max_yaw);  // 0.27 rad against 0.07 when measured
  EXPECT_GT(off.max_lateral, 5 * on.max_lateral);  // 16 % of the distance against 1.5 %
  EXPECT_TRUE(off.max_yaw > kMaxYaw || off.max_lateral > kMaxLateralShare * off.forward)
      << "max |yaw| " << off.max_yaw << " rad, max |lateral| " << off.max_lateral << " m over " << off.forward << " m";
}

INSTANTIATE_TEST_SUITE_P(Steps, TrotHeading, ::testing::Values(0.01, 0.025, 0.05));

}  // namespace
}  // namespace nmdp::test
