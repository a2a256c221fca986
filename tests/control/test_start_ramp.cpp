// The start ramp (control/start_ramp.hpp): targets that start at the start pose at rest, join the
// gait with matching position and velocity, and whose velocity is their time derivative.
#include <cmath>
#include <limits>
#include <random>

#include "control/hermite_spline.hpp"
#include "control/start_ramp.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp::test {
namespace {

constexpr int kDim = 5;
constexpr double kRamp = 0.8;  // s
constexpr double kStep = 1e-6;  // s, central differences in time

// A periodic gait whose targets move fast at t = 0 and t = kRamp, so a ramp that dropped the
// gait's velocity or its own ṙ term would show.
std::unique_ptr<PdTargetSource> gait() {
  std::mt19937 rng(5);
  std::vector<double> times{0.0, 0.15, 0.3, 0.45};
  std::vector<Eigen::VectorXd> positions;
  for (size_t k = 0; k < times.size(); ++k) positions.push_back(randomVector(rng, kDim, 1.0));
  return std::make_unique<KeyframePdTarget>(times, positions, std::vector<Eigen::VectorXd>{}, SplineEndMode::Periodic,
                                            0.6);
}
Eigen::VectorXd startPose() { return Eigen::VectorXd::LinSpaced(kDim, -0.3, 0.5); }

PdTarget at(const PdTargetSource& source, double t) {
  PdTarget out{Eigen::VectorXd::Zero(kDim), Eigen::VectorXd::Zero(kDim)};
  source.evaluate(t, out);
  return out;
}

TEST(StartRamp, StartsAtThePoseAtRestAndThenIsTheGait) {
  const StartRampPdTarget ramp(gait(), startPose(), kRamp);
  const std::unique_ptr<PdTargetSource> plain = gait();
  for (double t : {-0.1, 0.0}) {
    EXPECT_EQ(at(ramp, t).position, startPose()) << t;
    EXPECT_EQ(at(ramp, t).velocity, Eigen::VectorXd::Zero(kDim)) << t;
  }
  // Halfway r = 1/2 and ṙ = π / (2T).
  const PdTarget half = at(ramp, kRamp / 2), g = at(*plain, kRamp / 2);
  EXPECT_LT((half.position - (startPose() + 0.5 * (g.position - startPose()))).norm(), 1e-14);
  EXPECT_LT((half.velocity - (0.5 * g.velocity + M_PI / (2 * kRamp) * (g.position - startPose()))).norm(), 1e-13);
  for (double t : {kRamp, kRamp + 0.01, 3.7}) {
    EXPECT_EQ(at(ramp, t).position, at(*plain, t).position) << t;
    EXPECT_EQ(at(ramp, t).velocity, at(*plain, t).velocity) << t;
  }
  // Just before the end it is already (nearly) the gait: no jump at T.
  const PdTarget before = at(ramp, kRamp - 1e-7), after = at(*plain, kRamp - 1e-7);
  EXPECT_LT((before.position - after.position).norm(), 1e-12);
  EXPECT_LT((before.velocity - after.velocity).norm(), 1e-5);
}

// θ̄̇ against central differences of θ̄, over the ramp, across its end and at its start. The
// targets are C¹ (the gait's spline and r are C¹, r̈ jumps at 0 and T), so a difference
// straddling a kink is off by up to step·max|θ̄̈|; the tolerance adds that, from second differences.
TEST(StartRamp, VelocityIsTheTimeDerivative) {
  const StartRampPdTarget ramp(gait(), startPose(), kRamp);
  constexpr double wide = 1e-4;
  std::vector<double> times{0.0, kStep / 2, kRamp, kRamp - kStep / 2, kRamp + kStep / 2, 1.2};
  for (int i = 1; i < 40; ++i) times.push_back(kRamp * i / 40.0 + 0.0013);
  for (double t : times) {
    const Eigen::VectorXd fd = (at(ramp, t + kStep).position - at(ramp, t - kStep).position) / (2 * kStep);
    double curvature = 0;
    for (double c : {t - 2 * wide, t + 2 * wide}) {
      const Eigen::VectorXd second =
          (at(ramp, c + wide).position - 2 * at(ramp, c).position + at(ramp, c - wide).position) / (wide * wide);
      curvature = std::max(curvature, second.cwiseAbs().maxCoeff());
    }
    const double tolerance = 1e-7 * std::max(1.0, fd.cwiseAbs().maxCoeff()) + kStep * curvature;
    EXPECT_LT((at(ramp, t).velocity - fd).cwiseAbs().maxCoeff(), tolerance)
        << "t = " << t << "\nvelocity " << at(ramp, t).velocity.transpose()
        << "\ncentral difference " << fd.transpose();
  }
}

TEST(StartRamp, RejectsBadArguments) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double duration : {0.0, -1.0, nan, std::numeric_limits<double>::infinity()})
    EXPECT_THROW(StartRampPdTarget(gait(), startPose(), duration), std::invalid_argument) << duration;
  EXPECT_THROW(StartRampPdTarget(nullptr, startPose(), kRamp), std::invalid_argument);
  Eigen::VectorXd bad = startPose();
  bad[2] = nan;
  EXPECT_THROW(StartRampPdTarget(gait(), bad, kRamp), std::invalid_argument);
}

TEST(StartRamp, EvaluatesWithoutAllocating) {
  const StartRampPdTarget ramp(gait(), startPose(), kRamp);
  PdTarget out{Eigen::VectorXd::Zero(kDim), Eigen::VectorXd::Zero(kDim)};
  double t = -0.1;
  const AllocationCount count = allocationsOf([&] {
    for (int i = 0; i < 50; ++i, t += 0.0317) ramp.evaluate(t, out);
  });
  EXPECT_EQ(count.total(), 0) << count.news << " operator new, " << count.mallocs << " malloc";
}

}  // namespace
}  // namespace nmdp::test
