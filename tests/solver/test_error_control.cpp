// Error control (IntegratorOptions::accuracy, solver/local_error.hpp):
//  * the estimate is the step's local error: on a pendulum, one step's estimate against the error
//    of that step started from the exact state;
//  * a tighter tolerance gives a smaller global error and more sub-steps, each step still ends at
//    t + dt, no sub-step is longer than dt, and the estimate of every accepted sub-step is ≤ 1;
//  * a box dropped on the ground at a 50 ms step: the landing is where sub-steps are rejected, and
//    the controlled run lands where a 1 ms run does, closer than the fixed 50 ms step;
//  * reruns are bit-identical, and a bad tolerance is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "control/pd_target_source.hpp"
#include "integrator_fixtures.hpp"
#include "multibody/crba.hpp"
#include "solver/integrator.hpp"
#include "solver/local_error.hpp"
#include "test_support.hpp"

namespace nmdp {
namespace {

constexpr double kG = 9.81;

using Pendulum = test::FixedPendulum;

// The exact (θ, θ̇) after T from (θ0, v0): θ̈ = −(g/l) sin θ, the bob's 1e-6 inertia neglected
// (1e-6 relative).
std::pair<double, double> exactPendulum(double theta0, double v0, double T) {
  return test::pendulumReference(kG, theta0, v0, T, 100000);
}

Eigen::VectorXd one(double x) { return Eigen::VectorXd::Constant(1, x); }

TEST(LocalError, FirstOrderEstimateIsTheStepsPositionError) {
  // One backward-Euler step from the exact state at t = 0.3 s of a swing from 1 rad: the estimate
  // ½h(v_{n+1} − v_n) against the step's actual position error, for three step sizes.
  Pendulum p;
  const auto [th_n, v_n] = exactPendulum(1.0, 0.0, 0.3);
  for (double h : {0.02, 0.01, 0.005}) {
    SCOPED_TRACE(h);
    IntegratorOptions options;
    options.accuracy = 0;  // one step of h
    StepWorkspace ws(p.system, options);
    SimulationState state = initialState(p.system, options, one(th_n), one(v_n), h);
    ConstantPdTarget target(Eigen::VectorXd::Zero(1));
    ASSERT_TRUE(advance(p.system, options, target, state, h, ws).converged);
    const double actual = state.q[0] - exactPendulum(th_n, v_n, h).first;
    const double estimate = 0.5 * h * (state.qd[0] - v_n);
    // The estimate is the leading term: it and the actual error agree to O(h) relative.
    EXPECT_NEAR(estimate / actual, 1.0, 10 * h) << "estimate " << estimate << " actual " << actual;
    // And LocalError::normalized is that error in the H norm over the tolerance's scale.
    LocalError local(p.model);
    LocalErrorStep s;
    s.order = 1;
    s.h = h;
    const Eigen::VectorXd q0 = one(th_n), v0 = one(v_n);
    s.q_before = &q0;
    s.q_after = &state.q;
    s.v_before = &v0;
    s.v_after = &state.qd;
    const double accuracy = 1e-3;
    Data data(p.model);
    crba(p.model, data, state.q);
    const double sqrt_H = std::sqrt(data.H(0, 0));
    const double expected = sqrt_H * std::abs(estimate) /
                            (accuracy * (sqrt_H * std::abs(state.q[0] - th_n) + std::sqrt(p.model.total_mass) *
                                                                                     LocalError::kFloorLength));
    EXPECT_NEAR(local.normalized(s, data.H, accuracy), expected, 1e-12 * expected);
  }
}

TEST(LocalError, SecondOrderEstimateIsExactForACubic) {
  // q(t) = t³ (third derivative 6) sampled at t − h_prev, t, t + h: the variable-step BDF2 position
  // error is C(ω) h³ · 6 with C(ω) the error constant of the step's own formula (its residual for
  // t³), and the estimate's divided difference of v = 3t² reproduces the third derivative exactly.
  Pendulum p;
  LocalError local(p.model);
  Data data(p.model);
  const double accuracy = 1e-3;
  for (double omega : {0.5, 1.0, 2.0}) {
    SCOPED_TRACE(omega);
    const double h = 0.01, h_prev = h / omega, t = 0.2;
    const auto q = [](double x) { return x * x * x; };
    const auto v = [](double x) { return 3 * x * x; };
    const double a0 = (1 + 2 * omega) / (1 + omega), a1 = -(1 + omega), a2 = omega * omega / (1 + omega);
    const double residual = (a0 * q(t + h) + a1 * q(t) + a2 * q(t - h_prev)) / h - v(t + h);
    const double step_error = std::abs(residual * h / a0);  // the position error the step leaves
    const Eigen::VectorXd q_before = one(q(t)), q_after = one(q(t + h));
    const Eigen::VectorXd v_prev = one(v(t - h_prev)), v_before = one(v(t)), v_after = one(v(t + h));
    LocalErrorStep s;
    s.order = 2;
    s.h = h;
    s.h_prev = h_prev;
    s.q_before = &q_before;
    s.q_after = &q_after;
    s.v_prev = &v_prev;
    s.v_before = &v_before;
    s.v_after = &v_after;
    crba(p.model, data, q_after);
    const double sqrt_H = std::sqrt(data.H(0, 0));
    const double scale =
        accuracy * (sqrt_H * (q(t + h) - q(t)) + std::sqrt(p.model.total_mass) * LocalError::kFloorLength);
    EXPECT_NEAR(local.normalized(s, data.H, accuracy) * scale / sqrt_H, step_error, 1e-9 * step_error);
  }
}

struct ControlledRun {
  double theta = 0, velocity = 0;
  long substeps = 0, rejections = 0;
};

ControlledRun runPendulum(const Pendulum& p, double accuracy, double dt, double T) {
  IntegratorOptions options;
  options.accuracy = accuracy;
  StepWorkspace ws(p.system, options);
  SimulationState state = initialState(p.system, options, one(1.0), one(0.0), dt);
  ConstantPdTarget target(Eigen::VectorXd::Zero(1));
  ControlledRun r;
  const int steps = static_cast<int>(std::lround(T / dt));
  for (int i = 0; i < steps; ++i) {
    const StepStats s = advance(p.system, options, target, state, dt, ws);
    EXPECT_TRUE(s.converged) << "step " << i << ": " << toString(s.status);
    EXPECT_NEAR(state.time, (i + 1) * dt, 1e-12) << "step " << i;
    if (accuracy > 0) {
      EXPECT_LE(s.error_estimate, 1.0) << "step " << i;
    }
    for (double h : ws.substep_sizes) EXPECT_LE(h, dt * (1 + 1e-12)) << "step " << i;
    r.substeps += s.substeps;
    r.rejections += s.error_rejections;
  }
  r.theta = state.q[0];
  r.velocity = state.qd[0];
  return r;
}

TEST(ErrorControl, TighterAccuracyGivesSmallerErrorAndMoreSubsteps) {
  Pendulum p;
  const double dt = 0.05, T = 1.0;
  const auto [th_ref, v_ref] = exactPendulum(1.0, 0.0, T);
  const double w = std::sqrt(kG);
  const ControlledRun fixed = runPendulum(p, 0.0, dt, T);
  const double fixed_error = std::hypot(fixed.theta - th_ref, (fixed.velocity - v_ref) / w);
  double last_error = 0;
  long last_substeps = fixed.substeps;
  for (double accuracy : {1e-1, 1e-2, 1e-3}) {
    SCOPED_TRACE(accuracy);
    const ControlledRun r = runPendulum(p, accuracy, dt, T);
    const double error = std::hypot(r.theta - th_ref, (r.velocity - v_ref) / w);
    std::printf("pendulum, accuracy %g: error %.3e, %ld sub-steps, %ld rejected (fixed 50 ms: %.3e, %ld)\n", accuracy,
                error, r.substeps, r.rejections, fixed_error, fixed.substeps);
    EXPECT_GT(r.substeps, last_substeps);
    if (last_error == 0) {
      EXPECT_LT(error, fixed_error);
    } else {
      // Backward Euler's global error is proportional to its step. Where the 1 cm floor dominates the
      // scale, the step's error ½h²a is held to the tolerance, so h ∝ √accuracy: a tenth of the
      // tolerance, about √10 ≈ 3.2 times less error; where the displacement dominates, 10 times.
      EXPECT_LT(error, last_error / 2.5);
    }
    last_error = error;
    last_substeps = r.substeps;
  }
}

TEST(ErrorControl, LandingIsWhereSubstepsAreRejected) {
  // The box dropped from 5 cm above its resting height on the plane; 0.3 s at 50 ms. Free fall of a
  // backward-Euler step is an error too, so sub-steps shrink early; the landing must be among the
  // rejections and the run must end nearer the 1 ms run than the fixed 50 ms run does.
  test::BoxOnPlane box(true);
  const int z = box.model.dofIndex("base_z");
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(box.model.nq);
  q0[z] = box.restingHeight() + 0.05;
  const Eigen::VectorXd qd0 = Eigen::VectorXd::Zero(box.model.nq);
  ConstantPdTarget target(Eigen::VectorXd::Zero(box.model.nq));
  // The landing time of the free fall: √(2·0.05/g) ≈ 0.101 s.
  auto run = [&](double accuracy, double dt, double T, std::vector<double>* heights, std::vector<int>* rejections) {
    IntegratorOptions options;
    options.accuracy = accuracy;
    StepWorkspace ws(box.system, options);
    SimulationState state = initialState(box.system, options, q0, qd0, dt);
    const int steps = static_cast<int>(std::lround(T / dt));
    for (int i = 0; i < steps; ++i) {
      const StepStats s = advance(box.system, options, target, state, dt, ws);
      EXPECT_TRUE(s.converged) << "step " << i;
      if (heights) heights->push_back(state.q[z]);
      if (rejections) rejections->push_back(s.error_rejections);
    }
    return state.q[z];
  };
  const double reference = run(0.0, 0.001, 0.3, nullptr, nullptr);
  const double fixed = run(0.0, 0.05, 0.3, nullptr, nullptr);
  std::vector<int> rejections;
  const double controlled = run(0.01, 0.05, 0.3, nullptr, &rejections);
  std::printf("box height at 0.3 s: 1 ms %.6f, 50 ms %.6f, 50 ms with accuracy 0.01 %.6f; rejections per step:",
              reference, fixed, controlled);
  for (int r : rejections) std::printf(" %d", r);
  std::printf("\n");
  // Steps 2 and 3 (0.05–0.15 s) hold the landing.
  EXPECT_GT(rejections[2] + rejections[3], 0);
  EXPECT_LT(std::abs(controlled - reference), std::abs(fixed - reference));
}

TEST(ErrorControl, RerunsAreBitIdentical) {
  test::QuadrupedOnPlane robot;
  const Eigen::VectorXd q0 = robot.standing(-0.02);  // dropped 2 cm
  ConstantPdTarget target(robot.standing());
  IntegratorOptions options;
  options.accuracy = 0.01;
  auto run = [&] {
    StepWorkspace ws(robot.system, options);
    SimulationState state = initialState(robot.system, options, q0, Eigen::VectorXd::Zero(q0.size()), 0.05);
    long substeps = 0;
    for (int i = 0; i < 6; ++i) {
      const StepStats s = advance(robot.system, options, target, state, 0.05, ws);
      EXPECT_TRUE(s.converged) << "step " << i;
      substeps += s.substeps;
    }
    return std::make_pair(state.q, substeps);
  };
  const auto a = run(), b = run();
  EXPECT_GT(a.second, 6);  // the drop was controlled: some step was split
  EXPECT_EQ(a.second, b.second);
  for (Eigen::Index i = 0; i < a.first.size(); ++i) EXPECT_EQ(a.first[i], b.first[i]) << "coordinate " << i;
}

// The estimate's H(θ) comes from the energy check when it is on, from its own CRBA when it is off:
// the same computation, so the controlled run is the same bit for bit either way.
TEST(ErrorControl, MassMatrixFromTheEnergyCheckOrItsOwnGiveTheSameRun) {
  test::QuadrupedOnPlane robot;
  const Eigen::VectorXd q0 = robot.standing(-0.02);
  ConstantPdTarget target(robot.standing());
  auto run = [&](double energy_tolerance) {
    IntegratorOptions options;
    options.accuracy = 0.01;
    options.energy_tolerance = energy_tolerance;
    StepWorkspace ws(robot.system, options);
    SimulationState state = initialState(robot.system, options, q0, Eigen::VectorXd::Zero(q0.size()), 0.05);
    long substeps = 0;
    for (int i = 0; i < 6; ++i) {
      const StepStats s = advance(robot.system, options, target, state, 0.05, ws);
      EXPECT_TRUE(s.converged) << "step " << i;
      substeps += s.substeps;
    }
    return std::make_pair(state.q, substeps);
  };
  const auto checked = run(IntegratorOptions().energy_tolerance);
  const auto unchecked = run(std::numeric_limits<double>::infinity());
  EXPECT_GT(checked.second, 6);
  EXPECT_EQ(checked.second, unchecked.second);
  for (Eigen::Index i = 0; i < checked.first.size(); ++i) EXPECT_EQ(checked.first[i], unchecked.first[i]) << i;
}

TEST(ErrorControl, BadToleranceIsRefused) {
  Pendulum p;
  for (double bad : {-1e-3, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    IntegratorOptions options;
    options.accuracy = bad;
    EXPECT_THROW(validateSystem(p.system, options), std::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace nmdp
