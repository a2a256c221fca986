// The second-order (variable-step BDF2) integrator, IntegratorOptions::order = 2 (solver/bdf2.hpp):
//  1. a pendulum converges to the exact solution at second order (error ratio ≈ 4 per halving of the
//     step, over three halvings) in the NE and PBD forms, first and zeroth order PGM; order 1 at ≈ 2;
//  2. free fall: from an exact history the trajectory is the parabola itself, to round-off, at any
//     sequence of step sizes; from initialState (a backward-Euler first step), across the sub-steps
//     of split steps and across chart rebases it follows the closed-form BDF2 recursion, including
//     the backward-Euler sub-steps that come after a sub-step shorter than h/(1+√2) or a rebase;
//  3. (contacts: test_second_order_contact.cpp)
//  4. NE and PBD trajectories approach each other at second order as dt → 0;
//  5. PGM and ZOPGM reach the same step; the same run twice is bit-identical; advance() allocates
//     nothing after warm-up; ne-mdp and orders other than 1 and 2 are refused.
// Robots: tests/data/pendulum.urdf (1 kg bob on a 1 m rod, fixed base), tests/data/box.urdf (1 kg
// box, floating base) and the project's quadruped (integrator_fixtures.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "multibody/crba.hpp"
#include "solver/bdf2.hpp"
#include "solver/integrator.hpp"
#include "integrator_fixtures.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp {
namespace {

using Vec = Eigen::VectorXd;
constexpr double kG = 9.81;
const char* const kNmdpMethods[] = {"ne-pgm", "ne-zopgm", "pbd-pgm", "pbd-zopgm"};

IntegratorOptions optionsFor(const char* method, int order) { return test::fixedStepOptions(method, order); }

// ---------------------------------------------------------------------------------------------
// 1. Pendulum
// ---------------------------------------------------------------------------------------------

using Pendulum = test::FixedPendulum;


TEST(SecondOrder, PendulumConvergesAtSecondOrder) {
  Pendulum p;
  const double theta0 = 1.0, T = 1.0;
  Data data(p.model);
  crba(p.model, data, Vec::Constant(1, theta0));
  const double w2 = 1.0 * kG * 1.0 / data.H(0, 0), w = std::sqrt(w2);  // m g l / H
  const auto [th_ref, v_ref] = test::pendulumReference(w2, theta0, 0.0, T);
  const std::vector<double> steps = {0.04, 0.02, 0.01, 0.005};
  for (int order : {1, 2}) {
    for (const char* name : kNmdpMethods) {
      SCOPED_TRACE(std::string(name) + " order " + std::to_string(order));
      const IntegratorOptions options = optionsFor(name, order);
      std::vector<double> errors;
      for (double dt : steps) {
        StepWorkspace ws(p.system, options);
        SimulationState state = initialState(p.system, options, Vec::Constant(1, theta0), Vec::Zero(1), dt);
        const ConstantPdTarget target(Vec::Zero(1));
        const int n = static_cast<int>(std::lround(T / dt));
        for (int i = 0; i < n; ++i) {
          const StepStats s = advance(p.system, options, target, state, dt, ws);
          ASSERT_TRUE(s.converged) << "dt " << dt << " step " << i << ": " << toString(s.status);
          ASSERT_EQ(s.substeps, 1);
        }
        // In the energy-like norm (angle, angular velocity / ω): no accidental zero crossing.
        errors.push_back(std::hypot(state.q[0] - th_ref, (state.qd[0] - v_ref) / w));
      }
      std::printf("pendulum order %d %-9s errors at t = 1 s:", order, name);
      for (double e : errors) std::printf(" %.3e", e);
      std::printf("  ratios");
      for (size_t k = 1; k < errors.size(); ++k) std::printf(" %.3f", errors[k - 1] / errors[k]);
      std::printf("  (dt 0.04 … 0.005)\n");
      const double expected = order == 2 ? 4.0 : 2.0;
      for (size_t k = 1; k < errors.size(); ++k) {
        EXPECT_GT(errors[k - 1] / errors[k], 0.85 * expected) << "halving " << k;
        EXPECT_LT(errors[k - 1] / errors[k], 1.15 * expected) << "halving " << k;
      }
      if (order == 2) {
        EXPECT_LT(errors.back(), 1e-3);  // small, not merely shrinking
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Free fall
// ---------------------------------------------------------------------------------------------

// The closed form of BDF2 for p̈ = g, written with the α coefficients (solver/bdf2.hpp uses the
// extrapolation form): α0 v_{n+1} + α1 v_n + α2 v_{n−1} = h g, α0 p_{n+1} + α1 p_n + α2 p_{n−1} =
// h v_{n+1}; backward Euler when there is no history or the step ratio exceeds 1 + √2.
struct Bdf2Ballistic {
  Vec3 p, v, p_prev, v_prev;
  double h_prev = 0, p_scale = 0, v_scale = 0;
  bool history = false;
  Bdf2Ballistic(const Vec3& p0, const Vec3& v0) : p(p0), v(v0) { scale(); }
  void step(double h, const Vec3& g) {
    Vec3 p_new, v_new;
    if (history && h / h_prev <= 1 + std::sqrt(2.0)) {
      const double w = h / h_prev, a0 = (1 + 2 * w) / (1 + w), a1 = -(1 + w), a2 = w * w / (1 + w);
      v_new = (h * g - a1 * v - a2 * v_prev) / a0;
      p_new = (h * v_new - a1 * p - a2 * p_prev) / a0;
    } else {
      v_new = v + h * g;
      p_new = p + h * v_new;
    }
    p_prev = p, v_prev = v, p = p_new, v = v_new, h_prev = h, history = true;
    scale();
  }
  void scale() {
    p_scale = std::max(p_scale, p.lpNorm<Eigen::Infinity>());
    v_scale = std::max(v_scale, v.lpNorm<Eigen::Infinity>());
  }
  // Normwise relative to the trajectory (a velocity crossing zero carries the round-off of ‖p‖/h).
  double error(const Vec3& p_got, const Vec3& v_got) const {
    return std::max((p_got - p).lpNorm<Eigen::Infinity>() / p_scale, (v_got - v).lpNorm<Eigen::Infinity>() / v_scale);
  }
};

// From an exact history (q, q̇ at −h_prev and at 0) BDF2 integrates a parabola exactly, at any step
// sequence: the error is round-off only, although the steps change by factors of 2 and 1/4.
TEST(SecondOrder, FreeFallFromAnExactHistoryIsTheParabola) {
  test::BoxOnPlane box(false);
  const Vec3 g = box.model.gravity, p0(0.1, -0.2, 1.0), v0(0.3, -0.2, 2.0);
  const std::vector<double> pattern = {0.01, 0.02, 0.02, 0.005, 0.01, 0.02, 0.04, 0.01};
  for (const char* name : kNmdpMethods) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name, 2);
    StepWorkspace ws(box.system, options);
    Vec q0 = Vec::Zero(6), qd0 = Vec::Zero(6);
    q0.head<3>() = p0;
    qd0.head<3>() = v0;
    const double h0 = 0.01;
    SimulationState state = initialState(box.system, options, q0, qd0, h0);
    state.q_prev.head<3>() = p0 - h0 * v0 + 0.5 * h0 * h0 * g;
    state.qd_prev.head<3>() = v0 - h0 * g;
    state.second_order_history = true;
    const ConstantPdTarget target(Vec::Zero(6));
    double max_err = 0, p_scale = 0, v_scale = 0;
    for (int i = 0; i < 40; ++i) {
      const double dt = pattern[i % pattern.size()];
      const StepStats s = advance(box.system, options, target, state, dt, ws);
      ASSERT_TRUE(s.converged) << "step " << i << ": " << toString(s.status);
      const double t = state.time;
      const Vec3 p = p0 + t * v0 + 0.5 * t * t * g, v = v0 + t * g;
      p_scale = std::max(p_scale, p.lpNorm<Eigen::Infinity>());
      v_scale = std::max(v_scale, v.lpNorm<Eigen::Infinity>());
      max_err = std::max({max_err, (state.q.head<3>() - p).lpNorm<Eigen::Infinity>() / p_scale,
                          (state.qd.head<3>() - v).lpNorm<Eigen::Infinity>() / v_scale});
    }
    std::printf("free fall from an exact history %-9s: max rel error %.2e over 40 steps of 5-40 ms\n", name, max_err);
    EXPECT_LE(max_err, 1e-12);
    EXPECT_LT(state.qd[2], -2.0);  // it fell
  }
}

// From initialState (backward Euler first) and across Algorithm 2's splits: the dropped box of
// test_integrator_physics.cpp, free flight until the impact, with the outer iterations capped so
// that the impact step splits. (Only until the impact, where the closed form ends; the landing is
// DroppedBoxStaysDownAfterTheImpact.)
TEST(SecondOrder, DroppedBoxFollowsTheClosedFormAcrossSplitSteps) {
  CoulombParameters params;
  params.zeta = 1e-24;  // no force in the air (see the order-1 test)
  params.k = 1e11;
  test::BoxOnPlane box(true, params);
  const Vec3 g = box.model.gravity;
  const double dt = 0.05;
  for (const char* name : {"ne-pgm", "pbd-pgm"}) {
    SCOPED_TRACE(name);
    IntegratorOptions options = optionsFor(name, 2);
    options.max_outer_iterations = 3;
    Vec q0 = Vec::Zero(6), qd0 = Vec::Zero(6);
    q0[2] = test::BoxOnPlane::kHalfHeight + 2.0;
    qd0[0] = 0.2;
    StepWorkspace ws(box.system, options);
    SimulationState state = initialState(box.system, options, q0, qd0, dt);
    const ConstantPdTarget target(Vec::Zero(6));
    Bdf2Ballistic ref(q0.head<3>(), qd0.head<3>());
    double max_err = 0, smallest = dt;
    bool flying = true;
    int split_steps = 0, free_substeps = 0;
    for (int i = 0; i < 30 && flying; ++i) {
      const StepStats s = advance(box.system, options, target, state, dt, ws);
      // The step of the impact on this very stiff cone (k = 1e11) with three outer iterations may
      // fail past the contact; every step before it must converge.
      bool touched = false;
      for (std::uint8_t c : ws.substep_in_contact) touched = touched || c;
      ASSERT_TRUE(s.converged || touched) << "step " << i << ": " << toString(s.status);
      split_steps += s.substeps > 1;
      for (size_t j = 0; j < ws.substep_sizes.size() && flying; ++j) {
        if (ws.substep_in_contact[j]) {
          flying = false;
          break;
        }
        ref.step(ws.substep_sizes[j], g);
        smallest = std::min(smallest, ws.substep_sizes[j]);
        ++free_substeps;
      }
      // The state is that of the last sub-step: comparable while the whole step flew.
      if (flying) max_err = std::max(max_err, ref.error(state.q.head<3>(), state.qd.head<3>()));
    }
    std::printf("drop order 2 %-8s: %d split steps, %d free sub-steps (smallest %.4g s), max rel error %.2e\n", name,
                split_steps, free_substeps, smallest, max_err);
    EXPECT_LE(max_err, 1e-12);
    EXPECT_FALSE(flying) << "the box never touched the ground";
    EXPECT_GT(split_steps, 0) << "no step split: the check does not cover splitting";
  }
}

// Steps whose ratio to their predecessor exceeds 1 + √2 (here 4) are backward Euler: free fall
// follows the recursion with that rule, and measurably not the one that takes BDF2 there too.
TEST(SecondOrder, StepsPastTheRatioBoundAreBackwardEuler) {
  test::BoxOnPlane box(false);
  const Vec3 g = box.model.gravity, p0(0.1, -0.2, 1.0), v0(0.3, -0.2, 2.0);
  const std::vector<double> pattern = {0.01, 0.01, 0.0025, 0.01, 0.01, 0.02, 0.005, 0.02};
  for (const char* name : kNmdpMethods) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name, 2);
    StepWorkspace ws(box.system, options);
    Vec q0 = Vec::Zero(6), qd0 = Vec::Zero(6);
    q0.head<3>() = p0;
    qd0.head<3>() = v0;
    SimulationState state = initialState(box.system, options, q0, qd0, pattern[0]);
    const ConstantPdTarget target(Vec::Zero(6));
    Bdf2Ballistic ref(p0, v0), always_bdf2(p0, v0);
    double max_err = 0, max_err_always = 0;
    for (int i = 0; i < 40; ++i) {
      const double dt = pattern[i % pattern.size()];
      ASSERT_TRUE(advance(box.system, options, target, state, dt, ws).converged) << "step " << i;
      const bool past_bound = always_bdf2.history && dt / always_bdf2.h_prev > kBdf2MaxStepRatio;
      ref.step(dt, g);
      if (past_bound) always_bdf2.h_prev = dt;  // ratio 1: BDF2 with the coefficients of equal steps
      always_bdf2.step(dt, g);
      max_err = std::max(max_err, ref.error(state.q.head<3>(), state.qd.head<3>()));
      max_err_always = std::max(max_err_always, always_bdf2.error(state.q.head<3>(), state.qd.head<3>()));
    }
    std::printf("ratio rule %-9s: max rel error %.2e (against BDF2 at every step %.2e)\n", name, max_err, max_err_always);
    EXPECT_LE(max_err, 1e-12);
    EXPECT_GT(max_err_always, 1e-6);
  }
}

// A tumbling box: its centre of mass follows the closed form although its orientation is nonlinear,
// and each chart rebase (which voids the history) is followed by a backward-Euler sub-step.
TEST(SecondOrder, TumblingBoxCentreOfMassFollowsTheClosedForm) {
  test::BoxOnPlane box(false);
  const Vec3 g = box.model.gravity;
  for (const char* name : kNmdpMethods) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name, 2);
    const double dt = 0.02;
    Vec q0 = Vec::Zero(6), qd0(6);
    q0.head<3>() = Vec3(0.0, 0.0, 5.0);
    qd0 << 0.5, 0.2, 3.0, 3.0, -4.0, 5.0;
    StepWorkspace ws(box.system, options);
    SimulationState state = initialState(box.system, options, q0, qd0, dt);
    const ConstantPdTarget target(Vec::Zero(6));
    Bdf2Ballistic ref(q0.head<3>(), qd0.head<3>());
    double max_err = 0;
    int rebases = 0;
    for (int i = 0; i < 100; ++i) {
      const Mat3 chart = state.base_chart;
      const StepStats s = advance(box.system, options, target, state, dt, ws);
      ASSERT_TRUE(s.converged) << "step " << i << ": " << toString(s.status);
      if (state.base_chart != chart) {  // re-charted before this step: it was backward Euler
        ++rebases;
        ref.history = false;
      }
      for (double h : ws.substep_sizes) ref.step(h, g);
      max_err = std::max(max_err, ref.error(state.q.head<3>(), state.qd.head<3>()));
    }
    std::printf("tumbling order 2 %-9s: COM max rel error %.2e, %d chart rebases\n", name, max_err, rebases);
    EXPECT_LE(max_err, 1e-12);
    EXPECT_GT(rebases, 0) << "the check does not cover a rebase";
  }
}

// ---------------------------------------------------------------------------------------------
// 4. NE and PBD as dt → 0
// ---------------------------------------------------------------------------------------------


// The passive quadruped tumbling in the air with random joint velocities (as at order 1 in
// test_integrator_consistency.cpp, where the distance halves with dt): here it quarters.
TEST(SecondOrder, NeAndPbdApproachEachOtherAtSecondOrder) {
  test::QuadrupedOnPlane robot;
  robot.system.gains.kp.setZero();
  robot.system.gains.kd.setZero();
  const Vec q0 = robot.standing(-0.5);
  std::mt19937 rng(5);
  const Vec qd0 = test::randomVector(rng, robot.model.nq, 2.0);
  const ConstantPdTarget target(q0);
  std::vector<double> d;
  for (double dt : {4e-3, 2e-3, 1e-3}) {
    d.push_back(test::neToPbdDistance(robot, optionsFor("ne-pgm", 2), q0, qd0, target, dt, 0.2));
    std::printf("  passive swinging, order 2, dt %.0e: max |q_ne − q_pbd|∞ %.3e\n", dt, d.back());
  }
  std::printf("  ratios %.2f %.2f\n", d[0] / d[1], d[1] / d[2]);
  EXPECT_GT(d[0] / d[1], 3.4);
  EXPECT_GT(d[1] / d[2], 3.4);
}

// ---------------------------------------------------------------------------------------------
// 5. PGM vs ZOPGM, determinism, allocation, refusals
// ---------------------------------------------------------------------------------------------

// One order-2 step from a state with a history (q_prev, q̇_prev one step of h_prev earlier): the
// first- and zeroth-order methods stop at the same θ (tolerances as at order 1, 1e-6).
void expectSameStep(const System& system, const Vec& q, const Vec& qd, const Vec& q_prev, const Vec& qd_prev,
                    double h_prev, double dt, const std::string& what) {
  const ConstantPdTarget target(q);
  for (const auto& [first, zeroth] : {std::pair{"ne-pgm", "ne-zopgm"}, std::pair{"pbd-pgm", "pbd-zopgm"}}) {
    Vec theta[2];
    for (int k = 0; k < 2; ++k) {
      IntegratorOptions options = optionsFor(k == 0 ? first : zeroth, 2);
      options.epsilon = 1e-10;
      options.tol_w = 1e-10;
      StepWorkspace ws(system, options);
      SimulationState state = initialState(system, options, q, qd, dt);
      state.q_prev = q_prev;
      state.qd_prev = qd_prev;
      state.h_prev = h_prev;
      state.second_order_history = true;
      const StepStats st = advance(system, options, target, state, dt, ws);
      ASSERT_TRUE(st.converged) << what << " " << methodName(options.method) << ": " << toString(st.status);
      theta[k] = state.q;
    }
    const double dtheta = (theta[0] - theta[1]).lpNorm<Eigen::Infinity>();
    std::printf("  order 2 %-28s %-9s vs %-9s |θ_pgm − θ_zopgm|∞ %.2e\n", what.c_str(), first, zeroth, dtheta);
    EXPECT_LT(dtheta, 1e-6) << what << ": " << first << " vs " << zeroth;
  }
}

TEST(SecondOrder, PgmAndZopgmReachTheSameStep) {
  std::mt19937 rng(17);
  test::BoxOnPlane box(true);
  for (int trial = 0; trial < 3; ++trial) {
    Vec q = Vec::Zero(6), qd = test::randomVector(rng, 6, 1.0);
    q[2] = box.restingHeight() + 0.0005;
    q.segment<3>(3) = test::randomVector(rng, 3, 0.05);
    qd[2] = -0.3;
    const double h_prev = trial == 1 ? 0.005 : 0.01;
    const Vec qd_prev = qd + test::randomVector(rng, 6, 0.1);
    expectSameStep(box.system, q, qd, q - h_prev * qd, qd_prev, h_prev, 0.01, "box trial " + std::to_string(trial));
  }
  test::QuadrupedOnPlane robot;
  for (int trial = 0; trial < 2; ++trial) {
    const Vec q = robot.standing(0.003);
    const Vec qd = test::randomVector(rng, robot.model.nq, 0.2);
    const Vec qd_prev = qd + test::randomVector(rng, robot.model.nq, 0.05);
    expectSameStep(robot.system, q, qd, q - 0.01 * qd, qd_prev, 0.01, 0.01, "quadruped trial " + std::to_string(trial));
  }
}

// Joint targets swinging sinusoidally about a pose.
class SwingTarget final : public PdTargetSource {
 public:
  SwingTarget(Vec pose, double amplitude, double omega) : pose_(std::move(pose)), a_(amplitude), w_(omega) {}
  void evaluate(double t, PdTarget& out) const override {
    for (Eigen::Index j = 0; j < pose_.size(); ++j) {
      out.position[j] = pose_[j] + a_ * std::sin(w_ * t + 0.7 * static_cast<double>(j));
      out.velocity[j] = a_ * w_ * std::cos(w_ * t + 0.7 * static_cast<double>(j));
    }
  }

 private:
  Vec pose_;
  double a_, w_;
};

TEST(SecondOrder, SameRunTwiceIsBitIdentical) {
  test::QuadrupedOnPlane robot;
  const Vec q0 = robot.standing(-0.003);
  std::mt19937 rng(9);
  const Vec qd0 = test::randomVector(rng, robot.model.nq, 0.3);
  const SwingTarget target(robot.standing(), 0.15, 6.0);
  const double dt = 0.01;
  for (const char* name : kNmdpMethods) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name, 2);
    std::vector<double> runs[2];
    for (int r = 0; r < 2; ++r) {
      StepWorkspace ws(robot.system, options);
      SimulationState state = initialState(robot.system, options, q0, qd0, dt);
      for (int i = 0; i < 100; ++i) {
        const StepStats st = advance(robot.system, options, target, state, dt, ws);
        EXPECT_TRUE(st.converged) << "run " << r << " step " << i << ": " << toString(st.status);
        EXPECT_GT(st.outer_iterations, 0);
        EXPECT_GE(st.substeps, 1);
        runs[r].push_back(static_cast<double>(st.status));
        runs[r].push_back(static_cast<double>(st.outer_iterations));
        runs[r].push_back(static_cast<double>(st.g_evaluations));
        runs[r].push_back(static_cast<double>(st.substeps));
        if (!st.converged) break;
        runs[r].insert(runs[r].end(), state.q.data(), state.q.data() + state.q.size());
        runs[r].insert(runs[r].end(), state.qd.data(), state.qd.data() + state.qd.size());
        for (const Vec6& f : ws.contact_wrench) runs[r].insert(runs[r].end(), f.data(), f.data() + 6);
      }
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(double)), 0) << "the runs differ";
  }
}

// The order-2 trajectory is not the order-1 one (the option is not ignored), on the same run.
TEST(SecondOrder, DiffersFromFirstOrder) {
  Pendulum p;
  Vec q[2];
  for (int order : {1, 2}) {
    const IntegratorOptions options = optionsFor("ne-pgm", order);
    StepWorkspace ws(p.system, options);
    SimulationState state = initialState(p.system, options, Vec::Constant(1, 1.0), Vec::Zero(1), 0.01);
    const ConstantPdTarget target(Vec::Zero(1));
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(advance(p.system, options, target, state, 0.01, ws).converged);
    q[order - 1] = state.q;
  }
  EXPECT_GT(std::abs(q[0][0] - q[1][0]), 1e-6);
}

TEST(SecondOrder, AdvanceAllocatesNothingAfterWarmUp) {
  test::QuadrupedOnPlane robot;
  const Vec q0 = robot.standing(0.002);
  const SwingTarget target(robot.standing(), 0.05, 6.0);
  for (const char* name : kNmdpMethods) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name, 2);
    const double dt = 0.02;
    StepWorkspace ws(robot.system, options);
    SimulationState state = initialState(robot.system, options, q0, Vec::Zero(q0.size()), dt);
    // Warm up until the feet have settled and BDF2 steps are being taken (a touchdown restarts).
    for (int i = 0; i < 5 || (i < 40 && !state.second_order_history); ++i)
      EXPECT_TRUE(advance(robot.system, options, target, state, dt, ws).converged) << i;
    ASSERT_TRUE(state.second_order_history);
    bool converged = true;
    const test::AllocationCount count = test::countAllocations([&] {
      for (int i = 0; i < 10; ++i) converged = advance(robot.system, options, target, state, dt, ws).converged && converged;
    });
    EXPECT_TRUE(converged);
    EXPECT_EQ(count.total(), 0) << count.news << " operator new, " << count.mallocs << " malloc-family calls in 10 steps";
  }
}

TEST(SecondOrder, RefusesNeMdpAndOtherOrders) {
  test::BoxOnPlane box(true);
  IntegratorOptions options = optionsFor("ne-mdp", 2);
  try {
    validateSystem(box.system, options);
    ADD_FAILURE() << "ne-mdp at order 2 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ne-mdp is first order only"), std::string::npos) << e.what();
  }
  for (int order : {0, 3}) {
    options = optionsFor("ne-pgm", order);
    try {
      validateSystem(box.system, options);
      ADD_FAILURE() << "order " << order << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("order " + std::to_string(order)), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(validateSystem(box.system, optionsFor("ne-mdp", 1)));
  EXPECT_NO_THROW(validateSystem(box.system, optionsFor("pbd-zopgm", 2)));
}

// The rule of solver/bdf2.hpp: BDF2 needs a history and a ratio h/h_prev ≤ 1 + √2, else the step
// is backward Euler's (ĥ = h, no extrapolation).
TEST(SecondOrder, StepCoefficientRule) {
  test::BoxOnPlane box(false);
  const IntegratorOptions options = optionsFor("ne-pgm", 2);
  SimulationState state = initialState(box.system, options, Vec::Zero(6), Vec::Zero(6), 0.01);
  auto isBackwardEuler = [&](double h) {
    const Bdf2Coefficients c = secondOrderStepCoefficients(state, h);
    return c.h_hat == h && c.extrapolation == 0.0;
  };
  EXPECT_TRUE(isBackwardEuler(0.01));  // no history yet
  state.second_order_history = true;
  EXPECT_FALSE(isBackwardEuler(0.01));
  EXPECT_FALSE(isBackwardEuler(0.02));
  EXPECT_FALSE(isBackwardEuler(0.001));
  EXPECT_TRUE(isBackwardEuler(0.04));  // ratio 4 > 1 + √2
  // ω = 1: ĥ = 2h/3, x̂ = (4 x_n − x_{n−1})/3 = x_n + (x_n − x_{n−1})/3; ω = 2: ĥ = 3h/5, c = 4/5.
  Bdf2Coefficients c = secondOrderStepCoefficients(state, 0.01);
  EXPECT_NEAR(c.h_hat, 0.02 / 3, 1e-17);
  EXPECT_NEAR(c.extrapolation, 1.0 / 3, 1e-16);
  c = secondOrderStepCoefficients(state, 0.02);
  EXPECT_NEAR(c.h_hat, 0.02 * 3 / 5, 1e-17);
  EXPECT_NEAR(c.extrapolation, 0.8, 1e-16);
}

}  // namespace
}  // namespace nmdp
