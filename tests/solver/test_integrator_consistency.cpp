// The integrator as a whole (advance(), StepSolver): independent methods agree, errors are clear,
// runs are reproducible and stepping allocates nothing.
//  * PGM and ZOPGM reach the same step solution (NE and PBD form) on random contact states, and the
//    paper's zeroth-order variant where the solution is pinned; the penalty a step starts from
//    changes its path, not its solution;
//  * NE and PBD trajectories converge to each other as dt → 0 (first order);
//  * a first-order method with a derivative-less contact model is refused, naming the zeroth-order
//    twin; the twin runs and never asks the model for a derivative;
//  * the solution of a step is projected to the full tolerance (its trials are projected loosely);
//  * the same run twice is bit-identical, for every method;
//  * advance() allocates nothing after warm-up, for every method.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>
#include <stdexcept>

#include "contact_models/coulomb_model.hpp"
#include "multibody/kinematics.hpp"
#include "solver/integrator.hpp"
#include "solver/step_solver.hpp"
#include "terrain/plane.hpp"
#include "integrator_fixtures.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp {
namespace {

using Vec = Eigen::VectorXd;

const char* const kAllMethods[] = {"ne-pgm", "ne-zopgm", "pbd-pgm", "pbd-zopgm", "ne-mdp"};

// A target that swings every actuated joint sinusoidally about a pose (its velocity is the true
// derivative), so runs exercise the PD target path.
class SwingTarget final : public PdTargetSource {
 public:
  SwingTarget(Vec pose, double amplitude, double omega) : pose_(std::move(pose)), a_(amplitude), w_(omega) {}
  void evaluate(double t, PdTarget& out) const override {
    for (Eigen::Index j = 0; j < pose_.size(); ++j) {
      const double phase = 0.7 * static_cast<double>(j);
      out.position[j] = pose_[j] + a_ * std::sin(w_ * t + phase);
      out.velocity[j] = a_ * w_ * std::cos(w_ * t + phase);
    }
  }

 private:
  Vec pose_;
  double a_, w_;
};

// The ‖G‖∞ a projection ends at (StepSolver::project): the tolerance relative to the robot's weight,
// plus the round-off the inertial term's 1/h² makes of θ's.
double projectionTolerance(const IntegratorOptions& options, const Model& model, const Vec& theta, double h) {
  const double lever = 1.0 + theta.lpNorm<Eigen::Infinity>();
  return options.projection_tolerance * model.total_mass * std::max(model.gravity.norm(), 1.0) +
         1e3 * std::numeric_limits<double>::epsilon() * model.total_mass * lever * lever / (h * h);
}

IntegratorOptions optionsFor(const char* name) {
  IntegratorOptions o;
  o.kinetic_energy = KineticEnergyMeasure::FullBody;  // the paper's K
  o.accuracy = 0;                                    // and its fixed step
  o.method = *parseMethod(name);
  return o;
}

// ---------------------------------------------------------------------------------------------
// PGM vs ZOPGM: one step from the same state, first order against zeroth order.
//
// The zeroth-order methods take dV/dξ from central differences of V (ZerothOrderJacobian::
// FiniteDifference, the default), so they search with the first-order direction to the
// differences' accuracy and must stop at the same step: checked on random contact states (boxes
// sliding and tumbling into the ground, the quadruped with random joint and base velocities).
// The paper's zeroth-order Jacobian (ZerothOrderJacobian::Dropped) lacks the contact stiffness
// J_cᵀ(∂V_c/∂θ)w_c: its QP stops where the projected *inexact* gradient vanishes, which is the true
// minimiser only when the optimum is pinned (K's unconstrained minimum K = 0, a body held at rest);
// it is compared on such states only. (A box sliding at 1 m/s ends its dropped-term step 5e-4 m
// from the first-order one; docs/INTEGRATOR.md.)
// The stopping rule bounds the distance to the optimum: with ε = tol_w = 1e-10 and K's curvature
// at least m/h² in θ, ‖θ − θ*‖ ≲ √(2ε h²/m) ≈ 1.4e-7 for the 1 kg box at 10 ms; we allow 1e-6.
void expectSameStep(const System& system, const Vec& q, const Vec& qd, double dt, const std::string& what,
                    ZerothOrderJacobian zeroth_order = ZerothOrderJacobian::FiniteDifference) {
  const ConstantPdTarget target(q);
  for (const auto& [first, zeroth] : {std::pair{"ne-pgm", "ne-zopgm"}, std::pair{"pbd-pgm", "pbd-zopgm"}}) {
    Vec theta[2];
    for (int k = 0; k < 2; ++k) {
      IntegratorOptions options = optionsFor(k == 0 ? first : zeroth);
      options.epsilon = 1e-10;
      options.tol_w = 1e-10;
      options.zeroth_order_jacobian = zeroth_order;
      StepWorkspace ws(system, options);
      SimulationState state = initialState(system, options, q, qd, dt);
      const StepStats st = advance(system, options, target, state, dt, ws);
      ASSERT_TRUE(st.converged) << what << " " << methodName(options.method) << ": " << toString(st.status);
      theta[k] = state.q;
    }
    const double dtheta = (theta[0] - theta[1]).lpNorm<Eigen::Infinity>();
    std::printf("  %-36s %-9s vs %-9s (%s) |θ_pgm − θ_zopgm|∞ %.2e\n", what.c_str(), first, zeroth,
                zerothOrderJacobianName(zeroth_order), dtheta);
    EXPECT_LT(dtheta, 1e-6) << what << ": " << first << " vs " << zeroth;
  }
}

TEST(IntegratorConsistency, PgmAndZopgmReachTheSameStepOnRandomContactStates) {
  test::BoxOnPlane box(true);
  test::QuadrupedOnPlane robot;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    // A box 0-3 mm below its resting depth, tilted up to 0.1 rad, sliding at up to 1 m/s, sinking or
    // rising at up to 0.3 m/s and turning at up to 2 rad/s.
    Vec q = Vec::Zero(6), qd = Vec::Zero(6);
    q[2] = box.restingHeight() - 1.5e-3 * (1 + unit(rng));
    q[3] = 0.1 * unit(rng);
    q[4] = 0.1 * unit(rng);
    qd << unit(rng), unit(rng), 0.3 * unit(rng), 2 * unit(rng), 2 * unit(rng), 2 * unit(rng);
    expectSameStep(box.system, q, qd, 0.01, "random box " + std::to_string(trial));
  }
  for (int trial = 0; trial < 3; ++trial) {
    // The quadruped 2-5 mm deep, its base moving at up to 0.5 m/s and its joints at up to 2 rad/s.
    const Vec q = robot.standing(3.5e-3 + 1.5e-3 * unit(rng));
    Vec qd = Vec::Zero(robot.model.nq);
    for (int j = 0; j < 3; ++j) qd[j] = 0.5 * unit(rng);
    for (int j = 6; j < robot.model.nq; ++j) qd[j] = 2 * unit(rng);
    expectSameStep(robot.system, q, qd, 0.01, "random quadruped " + std::to_string(trial));
  }
}

// The penalty a step starts from (IntegratorOptions::adapt_start_penalty) and how fast it relaxes
// (IntegratorOptions::eta_limited) change the path of the trust-region iteration, not where it
// stops: the same kind of random states as above, from β_min (the inherited β after a converged
// step), the default and a penalty that makes the first moves tiny, the last also with DESIGN.md's
// reference relaxation factor (η = η_limited = 1.5). The solver stops once the decrease of K falls below
// what K resolves, r = 64 eps |K| + ‖∇K‖₁ · (the θ accuracy of the projection), which dominates ε
// here; both solutions then lie within r of K's minimum, so their K agree within r and, K's
// first-order term being non-negative at a constrained minimum, ½ΔθᵀΔ∇²K Δθ ≤ (√r + √r)² = 4r. (In
// θ itself they differ by up to 2e-6 in the light directions: a leg joint of 1e-4 kg·m² at 10 ms
// has a curvature of only 1 J/rad².)
TEST(IntegratorConsistency, StepSolutionDoesNotDependOnThePenaltySchedule) {
  test::BoxOnPlane box(true);
  test::QuadrupedOnPlane robot;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double h = 0.01;
  struct Solution {
    Vec theta;
    double K = 0, resolution = 0;
    Eigen::MatrixXd hess_K;
    int iterations = 0;
  };
  auto solve = [h](const System& system, const char* method, const Vec& q, const Vec& qd, double beta,
                   bool design_relaxation) {
    IntegratorOptions options = optionsFor(method);
    if (design_relaxation) options.eta = options.eta_limited = 1.5;  // DESIGN.md's reference η
    options.epsilon = 1e-10;
    options.tol_w = 1e-10;
    StepSolver solver(system);
    const SimulationState state = initialState(system, options, q, qd, h);
    const PdTarget target{q, Vec::Zero(q.size())};
    const StepAttempt a =
        solver.attempt(system, options, state, h, target, Vec::Zero(solver.residual().weightCount()), beta);
    EXPECT_EQ(a.status, StepStatus::Converged) << method << " from β " << beta;
    StepResidual& r = solver.residual();
    r.evaluate(system, solver.theta(), solver.weights(), ContactDerivative::Model);
    // The solver's K resolution (StepSolver::stepIsWorthTaking and project()).
    const double m = system.model->total_mass;
    const double G_tolerance = projectionTolerance(options, *system.model, solver.theta(), h);
    const double resolution = 64 * std::numeric_limits<double>::epsilon() * std::abs(r.K) +
                              r.grad_K.lpNorm<1>() * G_tolerance * h * h / m;
    return Solution{solver.theta(), r.K, resolution, r.hess_K, a.outer_iterations};
  };
  for (int trial = 0; trial < 6; ++trial) {
    const bool quadruped = trial >= 3;
    Vec q, qd;
    if (quadruped) {  // 2-5 mm deep, the base moving at up to 0.5 m/s and the joints at up to 2 rad/s
      q = robot.standing(3.5e-3 + 1.5e-3 * unit(rng));
      qd = Vec::Zero(robot.model.nq);
      for (int j = 0; j < 3; ++j) qd[j] = 0.5 * unit(rng);
      for (int j = 6; j < robot.model.nq; ++j) qd[j] = 2 * unit(rng);
    } else {  // a box 0-3 mm deep, tilted, sliding, sinking and turning
      q = Vec::Zero(6);
      qd = Vec::Zero(6);
      q[2] = box.restingHeight() - 1.5e-3 * (1 + unit(rng));
      q[3] = 0.1 * unit(rng);
      qd << unit(rng), unit(rng), 0.3 * unit(rng), 2 * unit(rng), 2 * unit(rng), 2 * unit(rng);
    }
    const System& system = quadruped ? robot.system : box.system;
    for (const char* method : {"ne-pgm", "pbd-pgm"}) {
      const Solution reference = solve(system, method, q, qd, 1e-4, false);
      const struct {
        double beta;
        bool design_relaxation;
      } schedules[] = {{1e-1, false}, {1e3, false}, {1e3, true}};
      for (const auto& schedule : schedules) {
        const Solution s = solve(system, method, q, qd, schedule.beta, schedule.design_relaxation);
        const Vec d = s.theta - reference.theta;
        const double r = std::max(s.resolution, reference.resolution), curvature = 0.5 * d.dot(reference.hess_K * d);
        char label[64];
        std::snprintf(label, sizeof label, "%s from β %g%s", method, schedule.beta,
                      schedule.design_relaxation ? ", relaxed by η only" : "");
        std::printf("  trial %d %-40s vs 1e-4: %2d vs %2d outer iterations; |ΔK| %.1e, ½ΔθᵀΔ∇²KΔθ %.1e, r %.1e, "
                    "|Δθ|∞ %.1e\n",
                    trial, label, s.iterations, reference.iterations, std::abs(s.K - reference.K), curvature, r,
                    d.lpNorm<Eigen::Infinity>());
        EXPECT_LE(std::abs(s.K - reference.K), r) << "trial " << trial << " " << label;
        EXPECT_LE(curvature, 4 * r) << "trial " << trial << " " << label;
      }
    }
  }
}

TEST(IntegratorConsistency, PaperZerothOrderReachesTheSameStepWhereItIsPinned) {
  test::BoxOnPlane box(true);
  Vec q = Vec::Zero(6), qd = Vec::Zero(6);
  q[2] = box.restingHeight();
  expectSameStep(box.system, q, qd, 0.01, "box at rest", ZerothOrderJacobian::Dropped);
  // Sliding at 1 m/s, the first-order step takes μ g h off the speed (friction saturated), not all.
  qd[0] = 1.0;
  IntegratorOptions options = optionsFor("ne-pgm");
  StepWorkspace ws(box.system, options);
  SimulationState state = initialState(box.system, options, q, qd, 0.01);
  const ConstantPdTarget target(q);
  ASSERT_TRUE(advance(box.system, options, target, state, 0.01, ws).converged);
  EXPECT_NEAR(state.qd[0], 1.0 - 0.7 * 9.81 * 0.01, 1e-3);

  test::QuadrupedOnPlane robot;
  expectSameStep(robot.system, robot.standing(0.0035), Vec::Zero(robot.model.nq), 0.01, "quadruped standing",
                 ZerothOrderJacobian::Dropped);
}

// ---------------------------------------------------------------------------------------------
// NE vs PBD as dt → 0: both are first-order discretisations of the same dynamics, so the distance
// between their trajectories over a fixed time shrinks linearly with dt (test::neToPbdDistance).
void expectLinearConvergence(const test::QuadrupedOnPlane& robot, const Vec& q0, const Vec& qd0, const PdTargetSource& target,
                             const char* what) {
  std::vector<double> diffs;
  for (double dt : {4e-3, 2e-3, 1e-3}) {
    diffs.push_back(test::neToPbdDistance(robot, optionsFor("ne-pgm"), q0, qd0, target, dt, 0.2));
    std::printf("  %s dt %.0e: max |q_ne − q_pbd|∞ %.3e\n", what, dt, diffs.back());
  }
  EXPECT_GE(diffs[0] / diffs[1], 1.6) << what;
  EXPECT_GE(diffs[1] / diffs[2], 1.6) << what;
}

// A passive quadruped tumbling in the air (no ground contact: feet 0.5 m up, 0.2 s of fall covers
// 0.2 m), legs swinging from random initial velocities. Passive, because the default PD gains make
// the joints stiff (√(K_p/I) ~ 200 rad/s, h ω ~ 0.8 at dt = 4 ms): the asymptotic regime would need
// far smaller steps.
TEST(IntegratorConsistency, NeAndPbdConvergeSwingingInTheAir) {
  test::QuadrupedOnPlane robot;
  robot.system.gains.kp.setZero();
  robot.system.gains.kd.setZero();
  const Vec q0 = robot.standing(-0.5);
  std::mt19937 rng(5);
  Vec qd0 = test::randomVector(rng, robot.model.nq, 2.0);
  const ConstantPdTarget target(q0);
  expectLinearConvergence(robot, q0, qd0, target, "passive swinging");
}

// The PD-held quadruped dropped from 5 mm onto the ground: landing, then standing.
TEST(IntegratorConsistency, NeAndPbdConvergeLanding) {
  test::QuadrupedOnPlane robot(BaseType::Planar);
  const Vec q0 = robot.standing(-0.005);
  const ConstantPdTarget target(robot.standing());
  expectLinearConvergence(robot, q0, Vec::Zero(robot.model.nq), target, "landing (planar)");
}

// ---------------------------------------------------------------------------------------------
// A Coulomb model that claims no derivative and throws if one is asked for.
class NoDerivativeCoulomb final : public ContactModel {
 public:
  int vertexCount() const override { return inner_.vertexCount(); }
  DerivativeSupport derivative() const override { return DerivativeSupport::None; }
  std::string describe() const override { return "coulomb without derivative (test)"; }
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain, std::vector<ContactWrenches>& out,
                bool with_derivatives) const override {
    if (with_derivatives) throw std::logic_error("NoDerivativeCoulomb: a derivative was requested");
    ++calls;
    inner_.evaluate(frames, terrain, out, false);
  }
  mutable long calls = 0;

 private:
  CoulombModel inner_;
};

TEST(IntegratorConsistency, FirstOrderMethodRefusesModelWithoutDerivative) {
  NoDerivativeCoulomb model;
  test::QuadrupedOnPlane robot(BaseType::Floating, &model);
  for (const auto& [first, twin] : {std::pair{"ne-pgm", "ne-zopgm"}, std::pair{"pbd-pgm", "pbd-zopgm"}}) {
    SCOPED_TRACE(first);
    const IntegratorOptions options = optionsFor(first);
    for (int k = 0; k < 2; ++k) {
      try {
        if (k == 0)
          validateSystem(robot.system, options);
        else
          StepWorkspace ws(robot.system, options);
        ADD_FAILURE() << first << " accepted a model without derivative";
      } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(twin), std::string::npos) << "message does not name " << twin << ": " << msg;
        EXPECT_NE(msg.find(first), std::string::npos) << msg;
      }
    }
  }
  // The zeroth-order twins (and ne-mdp, which needs no derivative either) run with it.
  for (const char* name : {"ne-zopgm", "pbd-zopgm", "ne-mdp"}) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name);
    const double dt = options.method == Method::NeMdp ? 1e-3 : 0.02;
    const Vec q0 = robot.standing(-0.002);
    const ConstantPdTarget target(robot.standing());
    StepWorkspace ws(robot.system, options);
    SimulationState state = initialState(robot.system, options, q0, Vec::Zero(q0.size()), dt);
    model.calls = 0;
    for (int i = 0; i < static_cast<int>(std::lround(0.3 / dt)); ++i) {
      StepStats st;
      ASSERT_NO_THROW(st = advance(robot.system, options, target, state, dt, ws));
      ASSERT_TRUE(st.converged) << "step " << i << ": " << toString(st.status);
    }
    EXPECT_GT(model.calls, 0);
    double fz = 0;
    for (const Vec6& f : ws.contact_wrench) fz += f[5];
    EXPECT_GT(fz, 0.5 * robot.model.total_mass * 9.81) << "the robot must land on the model's contacts";
  }
}

// ---------------------------------------------------------------------------------------------
// Determinism: the same 1 s run twice, with fresh workspaces, is bit-identical.
TEST(IntegratorConsistency, SameRunTwiceIsBitIdentical) {
  test::QuadrupedOnPlane robot;
  const Vec q0 = robot.standing(-0.003);
  std::mt19937 rng(9);
  const Vec qd0 = test::randomVector(rng, robot.model.nq, 0.3);
  const SwingTarget target(robot.standing(), 0.15, 6.0);
  for (const char* name : kAllMethods) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name);
    const double dt = options.method == Method::NeMdp ? 1e-3 : 0.01;
    const int steps = static_cast<int>(std::lround(1.0 / dt));
    std::vector<double> runs[2];
    for (int r = 0; r < 2; ++r) {
      StepWorkspace ws(robot.system, options);
      SimulationState state = initialState(robot.system, options, q0, qd0, dt);
      for (int i = 0; i < steps; ++i) {
        const StepStats st = advance(robot.system, options, target, state, dt, ws);
        // A failed step is reported, and must fail identically in both runs (its status is compared).
        EXPECT_TRUE(st.converged) << "run " << r << " step " << i << ": " << toString(st.status);
        runs[r].push_back(static_cast<double>(st.status));
        runs[r].push_back(static_cast<double>(st.outer_iterations));
        runs[r].push_back(static_cast<double>(st.substeps));
        if (!st.converged) break;
        runs[r].insert(runs[r].end(), state.q.data(), state.q.data() + state.q.size());
        runs[r].insert(runs[r].end(), state.qd.data(), state.qd.data() + state.qd.size());
        for (const Vec6& f : ws.contact_wrench) runs[r].insert(runs[r].end(), f.data(), f.data() + 6);
      }
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(double)), 0)
        << "the two runs differ";
  }
}

// ---------------------------------------------------------------------------------------------
// Trial steps of the PGM loop are projected only as far as their trust-region test needs; the
// solution a step returns must still satisfy G(θ, w) = 0 to the full projection tolerance. Checked
// on single 50 ms steps of the quadruped pressed into the ground with random velocities, where the
// early trials lower K by far more than the tolerance resolves (so they are projected loosely).
TEST(IntegratorConsistency, StepSolutionIsProjectedToTheFullTolerance) {
  test::QuadrupedOnPlane robot;
  const Vec q0 = robot.standing(-0.003);
  const SwingTarget target(robot.standing(), 0.15, 6.0);
  const double h = 0.05;
  std::mt19937 rng(5);
  for (const char* name : {"ne-pgm", "ne-zopgm", "pbd-pgm", "pbd-zopgm"}) {
    SCOPED_TRACE(name);
    const IntegratorOptions options = optionsFor(name);
    StepSolver solver(robot.system);
    PdTarget pd{Vec::Zero(robot.model.nq), Vec::Zero(robot.model.nq)};
    target.evaluate(h, pd);
    for (int trial = 0; trial < 6; ++trial) {
      const Vec qd0 = test::randomVector(rng, robot.model.nq, 0.2);
      const SimulationState state = initialState(robot.system, options, q0, qd0, h);
      double beta = options.beta_initial;
      const Vec w_start = Vec::Zero(solver.residual().weightCount());
      const StepAttempt attempt = solver.attempt(robot.system, options, state, h, pd, w_start, beta);
      ASSERT_EQ(attempt.status, StepStatus::Converged) << "trial " << trial;
      const Vec theta = solver.theta(), w = solver.weights();
      solver.residual().evaluateValue(robot.system, theta, w);
      EXPECT_LE(solver.residual().G.lpNorm<Eigen::Infinity>(), projectionTolerance(options, robot.model, theta, h))
          << "trial " << trial;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// No heap allocation inside advance() once warmed up, for every method (the zeroth-order ones with
// both Jacobians, the first-order ones also with error control), on the standing quadruped.
TEST(IntegratorConsistency, AdvanceAllocatesNothingAfterWarmUp) {
  test::QuadrupedOnPlane robot;
  const Vec q0 = robot.standing(0.002);
  const SwingTarget target(robot.standing(), 0.05, 6.0);
  std::vector<std::pair<const char*, ZerothOrderJacobian>> runs;
  for (const char* name : kAllMethods) runs.emplace_back(name, ZerothOrderJacobian::FiniteDifference);
  for (const char* name : {"ne-zopgm", "pbd-zopgm"}) runs.emplace_back(name, ZerothOrderJacobian::Dropped);
  // And with error control, whose estimate and retries must reuse the same buffers.
  for (const char* name : {"ne-pgm", "pbd-pgm"}) runs.emplace_back(name, ZerothOrderJacobian::FiniteDifference);
  const size_t first_controlled = runs.size() - 2;
  for (size_t run = 0; run < runs.size(); ++run) {
    const auto& [name, zeroth_order] = runs[run];
    const bool controlled = run >= first_controlled;
    SCOPED_TRACE(std::string(name) + " " + zerothOrderJacobianName(zeroth_order) + (controlled ? " accuracy 0.05" : ""));
    IntegratorOptions options = optionsFor(name);
    options.zeroth_order_jacobian = zeroth_order;
    if (controlled) options.accuracy = 0.05;
    const double dt = options.method == Method::NeMdp ? 1e-3 : 0.02;
    StepWorkspace ws(robot.system, options);
    SimulationState state = initialState(robot.system, options, q0, Vec::Zero(q0.size()), dt);
    for (int i = 0; i < 5; ++i) EXPECT_TRUE(advance(robot.system, options, target, state, dt, ws).converged) << "warm-up " << i;
    bool converged = true;
    const test::AllocationCount count = test::countAllocations([&] {
      for (int i = 0; i < 10; ++i) converged = advance(robot.system, options, target, state, dt, ws).converged && converged;
    });
    EXPECT_TRUE(converged);
    EXPECT_EQ(count.total(), 0) << count.news << " operator new, " << count.mallocs << " malloc-family calls in 10 steps";
  }
}

}  // namespace
}  // namespace nmdp
