// Gait keyframes (DESIGN.md 5): cubic Hermite splines that hit their keyframes, whose velocity is
// the true time derivative, that wrap smoothly when periodic and hold their ends otherwise; the
// keyframe PD target evaluates them without allocating.
#include <random>
#include <stdexcept>

#include "control/gait.hpp"
#include "control/hermite_spline.hpp"
#include "spline_derivative.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp::test {
namespace {

// Non-uniform durations (0.1 s to 2.3 s) make a missing division by the duration obvious.
struct SplineCase {
  std::vector<double> times{-0.4, -0.3, 0.4, 2.7, 3.0};
  std::vector<Eigen::VectorXd> positions;
  SplineCase() {
    std::mt19937 rng(11);
    for (size_t k = 0; k < times.size(); ++k) positions.push_back(randomVector(rng, 3, 2.0));
  }
};

TEST(HermiteSpline, HitsKeyframesExactly) {
  const SplineCase c;
  for (SplineEndMode mode : {SplineEndMode::HoldEnds, SplineEndMode::Periodic}) {
    const HermiteSpline spline(c.times, c.positions, {}, mode, 4.1);
    for (size_t k = 0; k < c.times.size(); ++k)
      EXPECT_EQ(positionAt(spline, c.times[k]), c.positions[k]) << "keyframe " << k;
  }
}

TEST(HermiteSpline, VelocityIsTheTimeDerivativeOfPosition) {
  const SplineCase c;
  const HermiteSpline automatic(c.times, c.positions);
  expectVelocityIsTimeDerivative(automatic, probeTimes(c.times));

  std::mt19937 rng(5);
  std::vector<Eigen::VectorXd> velocities;
  for (size_t k = 0; k < c.times.size(); ++k) velocities.push_back(randomVector(rng, 3, 3.0));
  const HermiteSpline given(c.times, c.positions, velocities);
  // Holding the end positions with nonzero given end velocities makes ṗ jump at the two ends.
  std::vector<double> inside;
  for (double t : probeTimes(c.times))
    if (t > c.times.front() + 1e-5 && t < c.times.back() - 1e-5) inside.push_back(t);
  expectVelocityIsTimeDerivative(given, inside);
  for (size_t k = 0; k < c.times.size(); ++k) {
    EXPECT_EQ(given.slope(static_cast<int>(k)), velocities[k]);
    if (k > 0 && k + 1 < c.times.size()) {  // ends hold: velocity 0 from outside
      EXPECT_LT((velocityAt(given, c.times[k]) - velocities[k]).norm(), 1e-12) << "keyframe " << k;
    }
  }
}

TEST(HermiteSpline, PeriodicWrapIsSmoothAndRepeats) {
  const SplineCase c;
  const double period = 4.1;  // the wrap segment 3.0 → 3.7 is 0.7 s long
  const HermiteSpline spline(c.times, c.positions, {}, SplineEndMode::Periodic, period);
  ASSERT_EQ(spline.knotTimes().back(), c.times.front() + period);
  std::vector<double> probes = probeTimes(spline.knotTimes());
  for (double t : {-9.1, -4.5, 5.3, 12.0}) probes.push_back(t);
  expectVelocityIsTimeDerivative(spline, probes);
  for (double t : probes) {
    EXPECT_LT((positionAt(spline, t + period) - positionAt(spline, t)).norm(), 1e-12) << t;
    EXPECT_LT((positionAt(spline, t - 3 * period) - positionAt(spline, t)).norm(), 1e-12) << t;
    EXPECT_LT((velocityAt(spline, t + period) - velocityAt(spline, t)).norm(), 1e-9) << t;
  }
  EXPECT_LT((positionAt(spline, c.times.front() + period) - c.positions.front()).norm(), 1e-12);
}

TEST(HermiteSpline, AutomaticSlopesAreExactForQuadratics) {
  // p(t) = 3t² − t: the parabola slopes reproduce ṗ at interior keyframes whatever the spacing,
  // and a Hermite cubic with exact slopes reproduces the quadratic everywhere.
  const std::vector<double> times{0.0, 0.2, 0.9, 1.0, 2.5};
  std::vector<Eigen::VectorXd> positions;
  for (double t : times) positions.push_back(Eigen::VectorXd::Constant(1, 3 * t * t - t));
  const HermiteSpline spline(times, positions);
  for (int k = 1; k + 1 < static_cast<int>(times.size()); ++k)
    EXPECT_NEAR(spline.slope(k)[0], 6 * times[k] - 1, 1e-12) << "keyframe " << k;
  for (double t : {0.4, 0.95})
    EXPECT_NEAR(positionAt(spline, t)[0], 3 * t * t - t, 1e-12);
  // Uniform spacing: the Catmull–Rom slope.
  const HermiteSpline uniform({0, 1, 2}, {Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Constant(1, 5.0),
                                          Eigen::VectorXd::Constant(1, 2.0)});
  EXPECT_NEAR(uniform.slope(1)[0], (2.0 - 1.0) / 2.0, 1e-15);
}

TEST(HermiteSpline, HoldEndsOutsideTheKeyframes) {
  const SplineCase c;
  const HermiteSpline spline(c.times, c.positions);
  EXPECT_EQ(positionAt(spline, -10.0), c.positions.front());
  EXPECT_EQ(positionAt(spline, 10.0), c.positions.back());
  EXPECT_TRUE(velocityAt(spline, -10.0).isZero(0.0));
  EXPECT_TRUE(velocityAt(spline, 10.0).isZero(0.0));
  EXPECT_LT(velocityAt(spline, c.times.back() - 1e-9).norm(), 1e-6);  // continuous into the hold
  const HermiteSpline single({1.0}, {c.positions[0]});
  EXPECT_EQ(positionAt(single, 7.0), c.positions[0]);
  EXPECT_TRUE(velocityAt(single, 0.5).isZero(0.0));
}

TEST(HermiteSpline, RejectsBadKeyframes) {
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(2), b = Eigen::VectorXd::Ones(2), c = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(HermiteSpline({}, {}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 0.0}, {a, b}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a, c}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a, b}, {a}), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, 1.0}, {a, b}, {}, SplineEndMode::Periodic, 1.0), std::invalid_argument);
  EXPECT_THROW(HermiteSpline({0.0, NAN}, {a, b}), std::invalid_argument);
  try {
    HermiteSpline({0.0, 1.0, 0.5}, {a, b, a});
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("keyframe 2"), std::string::npos) << e.what();
  }
}

TEST(KeyframePdTarget, EvaluatesTheSplineWithoutAllocating) {
  const SplineCase c;
  const KeyframePdTarget target(c.times, c.positions, {}, SplineEndMode::Periodic, 4.1);
  const PdTargetSource& source = target;
  PdTarget out{Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3)};
  double t = 0.0;
  const AllocationCount count = allocationsOf([&] {
    for (int i = 0; i < 100; ++i, t += 0.0731) source.evaluate(t, out);
  });
  EXPECT_EQ(count.total(), 0) << count.news << " operator new, " << count.mallocs << " malloc";
  source.evaluate(c.times[2], out);
  EXPECT_EQ(out.position, c.positions[2]);
}

}  // namespace
}  // namespace nmdp::test
