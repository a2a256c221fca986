// The straight walk on 3-D sand: the project's quadruped on a floating base, default trot, 10 s on
// the 3-D sand model (models/scenes/quadruped_trot_sand3d.json), at dt = 10, 25 and 50 ms, walks
// forward with |yaw| below 0.1 rad, a lateral drift below 5 % of the forward distance, and the
// forward distance within 10 % of the same robot on a planar base with the planar model fitted from
// the same RFT medium and foot (data/granular/rft3d_quadruped_planar_rbf.h5). docs/RESULTS.md has
// the same for A1 and Solo-12.
#include <cmath>

#include "trot_heading_run.hpp"

namespace nmdp::test {
namespace {

HeadingRun walk(const std::vector<std::string>& overrides) { return runHeading("quadruped_trot_sand3d.json", overrides); }

class Sand3dWalk : public ::testing::TestWithParam<double> {};

TEST_P(Sand3dWalk, FloatingQuadrupedWalksStraightAndAsFarAsOnAPlanarBase) {
  const std::string dt = "integrator.dt=" + std::to_string(GetParam());
  const HeadingRun floating = walk({dt});
  ASSERT_TRUE(floating.completed);
  EXPECT_GT(floating.forward, 1.0);
  EXPECT_LT(floating.max_yaw, 0.1);                                // 0.054–0.055 rad measured
  EXPECT_LT(floating.max_lateral, 0.05 * floating.forward);       // 0.8 %
  const HeadingRun planar = walk({dt, "robot.base=planar",
                            R"(contacts.model={"type": "rbf", "file": "../../data/granular/rft3d_quadruped_planar_rbf.h5"})"});
  ASSERT_TRUE(planar.completed);
  EXPECT_NEAR(floating.forward, planar.forward, 0.10 * planar.forward);  // 4.17 m against 4.34 m
}

INSTANTIATE_TEST_SUITE_P(Steps, Sand3dWalk, ::testing::Values(0.01, 0.025, 0.05));

}  // namespace
}  // namespace nmdp::test
