// bench_mujoco's speed at equal accuracy (bench/equal_accuracy.hpp): the within-5 % test and the
// cheapest configuration per engine.
#include <gtest/gtest.h>

#include "bench/equal_accuracy.hpp"

using nmdp::bench::Accuracy;
using nmdp::bench::Configuration;
using nmdp::bench::cheapestWithin;
using nmdp::bench::withinTolerance;

namespace {
const Accuracy kFinest{true, 2.0, 0.1};  // walked 2 m, turned 0.1 rad
}

TEST(EqualAccuracy, WithinNeedsDisplacementRmsAndYaw) {
  EXPECT_TRUE(withinTolerance({true, 2.09, 0.0}, 0.09, kFinest));
  EXPECT_TRUE(withinTolerance({true, 1.91, -0.29}, 0.0, kFinest));
  EXPECT_FALSE(withinTolerance({true, 2.11, 0.0}, 0.0, kFinest));   // 5.5 % further
  EXPECT_FALSE(withinTolerance({true, 1.89, 0.0}, 0.0, kFinest));   // 5.5 % shorter
  EXPECT_FALSE(withinTolerance({true, 2.0, 0.0}, 0.1, kFinest));    // RMS exactly 5 %: not below
  EXPECT_FALSE(withinTolerance({true, 2.0, 0.3}, 0.0, kFinest));    // |yaw| 0.3 rad: not below
  EXPECT_FALSE(withinTolerance({true, 2.0, -0.31}, 0.0, kFinest));
  EXPECT_FALSE(withinTolerance({true, 2.0, 0.0}, NAN, kFinest));    // no deviation measured
}

TEST(EqualAccuracy, BothRunsMustBeStableAndTheFinestMustMove) {
  EXPECT_FALSE(withinTolerance({false, 2.0, 0.0}, 0.0, kFinest));
  EXPECT_FALSE(withinTolerance({true, 2.0, 0.0}, 0.0, {false, 2.0, 0.0}));
  EXPECT_FALSE(withinTolerance({true, 0.0, 0.0}, 0.0, {true, 0.0, 0.0}));
}

TEST(EqualAccuracy, CheapestIsPerEngineAmongTimedRunsWithinTolerance) {
  const std::vector<Configuration> c = {
      {"MuJoCo", "MuJoCo", 0.0005, 0.030, 0.030, true, false},  // the finest, run once: not a candidate
      {"MuJoCo", "MuJoCo", 0.002, 0.0065, 0.0064, true, true},
      {"MuJoCo", "MuJoCo", 0.005, 0.0030, 0.0030, false, true},  // cheaper but not within 5 %
      {"MuJoCo", "MuJoCo, implicit kd", 0.002, 0.0068, 0.0068, true, true},
      {"nmdp", "ne-pgm", 0.01, 0.0086, 0.0086, true, true},
      {"nmdp", "pbd-pgm", 0.01, 0.0163, 0.0162, true, true},
      {"nmdp", "ne-pgm", 0.05, 0.0020, 0.0020, false, true},
  };
  const Configuration* mj = cheapestWithin(c, "MuJoCo");
  ASSERT_NE(mj, nullptr);
  EXPECT_EQ(mj->family, "MuJoCo");
  EXPECT_EQ(mj->dt, 0.002);
  const Configuration* ours = cheapestWithin(c, "nmdp");
  ASSERT_NE(ours, nullptr);
  EXPECT_EQ(ours->family, "ne-pgm");
  EXPECT_EQ(ours->dt, 0.01);
  EXPECT_EQ(cheapestWithin({c[0], c[2]}, "MuJoCo"), nullptr);
  EXPECT_EQ(cheapestWithin(c, "Drake"), nullptr);
}
