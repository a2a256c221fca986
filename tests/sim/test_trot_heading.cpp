// The default trot on a floating base holds its heading and its line (control/heading_feedback.hpp):
// the project's quadruped on rigid ground, with the feedback on and, to show the drift it removes,
// off.
#include <cmath>

#include "trot_heading_run.hpp"

namespace nmdp::test {
namespace {

HeadingRun runTrot(const std::vector<std::string>& overrides) { return runHeading("quadruped_trot_flat.json", overrides); }

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
