// rollout (sim/rollout.hpp): a batch of runs equals a loop of Simulation::step from the same states
// bit for bit, with the scene's gait and with controls (the setTargets / setFeedforward loop a
// policy would write); 1, 2 and 3 threads give the same bits; (q, q̇) rows start as the scene's own
// start state; a failed step leaves NaN; bad arguments are refused before anything runs.
#include <cstdio>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "scene_simulation.hpp"
#include "sim/rollout.hpp"

namespace nmdp {
namespace {

using test::coulombAndRbf;
using test::repositoryScene;

constexpr int kSteps = 5;

// Flat states of one run of the scene at the given steps: starts that differ in time, pose and
// contact state.
RowMajorMatrix startsAlongARun(const SceneConfig& scene, const std::vector<int>& at_steps) {
  Simulation sim = buildSimulation(scene, coulombAndRbf());
  const StateLayout layout = stateLayout(sim.system());
  RowMajorMatrix starts(static_cast<Eigen::Index>(at_steps.size()), layout.size());
  int done = 0;
  for (size_t i = 0; i < at_steps.size(); ++i) {
    for (; done < at_steps[i]; ++done) EXPECT_TRUE(sim.step().converged);
    Eigen::VectorXd x;
    flattenState(layout, sim.state(), x);
    starts.row(static_cast<Eigen::Index>(i)) = x.transpose();
  }
  return starts;
}

// What a caller writes by hand: each entry from its flat state, its controls applied with
// setTargets(HeldPdTarget) and setFeedforward before each step, the flat state recorded after it.
std::vector<double> loopOfSteps(const SceneConfig& scene, const RolloutRequest& request) {
  Simulation sim = buildSimulation(scene, coulombAndRbf());
  const StateLayout layout = stateLayout(sim.system());
  const int nq = layout.nq;
  std::vector<double> out;
  Eigen::VectorXd x;
  for (Eigen::Index b = 0; b < request.initial_states.rows(); ++b) {
    SimulationState s;
    unflattenState(layout, request.initial_states.row(b).transpose(), s);
    sim.setState(s);
    flattenState(layout, sim.state(), x);
    out.insert(out.end(), x.data(), x.data() + x.size());
    for (int k = 0; k < request.steps; ++k) {
      if (request.controls.size() > 0) {
        const Eigen::Index width = request.controls.cols() / request.steps;
        const Eigen::VectorXd u = request.controls.row(b).segment(k * width, width).transpose();
        sim.setTargets(std::make_unique<HeldPdTarget>(u.head(nq), u.segment(nq, nq)));
        if (width == 3 * nq) sim.setFeedforward(u.tail(nq));
      }
      EXPECT_TRUE(sim.step().converged) << "entry " << b << " step " << k;
      flattenState(layout, sim.state(), x);
      out.insert(out.end(), x.data(), x.data() + x.size());
    }
  }
  return out;
}

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(Rollout, EqualsALoopOfStepsBitForBit) {
  for (const char* name : {"quadruped_trot_sand.json", "quadruped_trot_flat.json"}) {
    SCOPED_TRACE(name);
    const SceneConfig scene = repositoryScene(name);
    RolloutRequest request;
    request.initial_states = startsAlongARun(scene, {0, 3, 6});
    request.steps = kSteps;
    const RolloutResult result = rollout(scene, coulombAndRbf(), request);
    EXPECT_TRUE(sameBits(result.states, loopOfSteps(scene, request)));
    EXPECT_EQ(result.status, std::vector<StepStatus>(3, StepStatus::Converged));
    EXPECT_EQ(result.steps_done, std::vector<int>(3, kSteps));
  }
}

TEST(Rollout, OneTwoAndThreeThreadsGiveTheSameBits) {
  const SceneConfig scene = repositoryScene("quadruped_trot_sand.json");
  RolloutRequest request;
  request.initial_states = startsAlongARun(scene, {0, 1, 2, 4, 7});
  request.steps = kSteps;
  request.threads = 1;
  const RolloutResult one = rollout(scene, coulombAndRbf(), request);
  for (int threads : {2, 3}) {
    request.threads = threads;
    const RolloutResult many = rollout(scene, coulombAndRbf(), request);
    EXPECT_TRUE(sameBits(one.states, many.states)) << threads << " threads";
    EXPECT_EQ(one.steps_done, many.steps_done);
  }
  request.threads = 8;  // more threads than entries: one simulation per entry at most
  EXPECT_TRUE(sameBits(one.states, rollout(scene, coulombAndRbf(), request).states));
}

// Controls of width 2 nq (targets) and 3 nq (and τ_ff): the trot's own targets around the start
// pose, perturbed per entry and step, against the same setTargets / setFeedforward loop.
TEST(Rollout, ControlsEqualTheSetTargetsAndSetFeedforwardLoop) {
  const SceneConfig scene = repositoryScene("quadruped_trot_flat.json");
  Simulation sim = buildSimulation(scene, coulombAndRbf());
  const Model& model = sim.model();
  const int nq = model.nq;
  RolloutRequest request;
  request.initial_states = startsAlongARun(scene, {0, 2, 5});
  request.steps = kSteps;
  for (const int width : {2 * nq, 3 * nq}) {
    SCOPED_TRACE(width);
    request.controls.setZero(3, kSteps * width);
    for (Eigen::Index b = 0; b < 3; ++b)
      for (int k = 0; k < kSteps; ++k)
        for (int j = 0; j < nq; ++j) {
          if (model.bodies[j].is_base) continue;
          const double wave = std::sin(0.7 * k + 0.3 * j + static_cast<double>(b));
          request.controls(b, k * width + j) = sim.initialConfiguration()[j] + 0.1 * wave;
          request.controls(b, k * width + nq + j) = 0.5 * wave;
          if (width == 3 * nq) request.controls(b, k * width + 2 * nq + j) = 2.0 * wave;
        }
    request.threads = 2;
    const RolloutResult result = rollout(scene, coulombAndRbf(), request);
    EXPECT_TRUE(sameBits(result.states, loopOfSteps(scene, request)));
    RolloutRequest gait = request;
    gait.controls.resize(0, 0);
    EXPECT_FALSE(sameBits(result.states, rollout(scene, coulombAndRbf(), gait).states)) << "the controls act";
  }
}

// (q, q̇) rows start as buildSimulation starts the scene: initialState at time 0.
TEST(Rollout, PositionAndVelocityRowsStartAsTheScenesOwnStart) {
  const SceneConfig scene = repositoryScene("quadruped_trot_flat.json");
  Simulation sim = buildSimulation(scene, coulombAndRbf());
  const int nq = sim.model().nq;
  RolloutRequest request;
  request.initial_states.resize(1, 2 * nq);
  request.initial_states << sim.initialConfiguration().transpose(), sim.initialVelocity().transpose();
  request.steps = kSteps;
  const RolloutResult result = rollout(scene, coulombAndRbf(), request);
  const StateLayout layout = stateLayout(sim.system());
  std::vector<double> expected;
  Eigen::VectorXd x;
  for (int k = 0; k <= kSteps; ++k) {
    if (k > 0) {
      ASSERT_TRUE(sim.step().converged);
    }
    flattenState(layout, sim.state(), x);
    expected.insert(expected.end(), x.data(), x.data() + x.size());
  }
  EXPECT_TRUE(sameBits(result.states, expected));
}

// A run that cannot take a step: its status, the steps it did, NaN from the failed step on; the
// other entries run on.
TEST(Rollout, AFailedStepLeavesNaNFromThereOn) {
  const SceneConfig scene =
      repositoryScene("quadruped_trot_flat.json", {"integrator.adaptive=false", "integrator.max_outer_iterations=1"});
  Simulation sim = buildSimulation(scene, coulombAndRbf());
  RolloutRequest request;
  request.initial_states = startsAlongARun(repositoryScene("quadruped_trot_flat.json"), {0, 6});
  request.steps = kSteps;
  const RolloutResult result = rollout(scene, coulombAndRbf(), request);
  const Eigen::Index nx = stateLayout(sim.system()).size();
  for (Eigen::Index b = 0; b < 2; ++b) {
    const int done = result.steps_done[static_cast<size_t>(b)];
    SCOPED_TRACE("entry " + std::to_string(b) + ", " + std::to_string(done) + " steps done");
    if (done == kSteps) {
      EXPECT_EQ(result.status[static_cast<size_t>(b)], StepStatus::Converged);
      continue;
    }
    EXPECT_NE(result.status[static_cast<size_t>(b)], StepStatus::Converged);
    const double* row = result.states.data() + b * (kSteps + 1) * nx;
    for (Eigen::Index i = 0; i < (done + 1) * nx; ++i) ASSERT_TRUE(std::isfinite(row[i])) << i;
    for (Eigen::Index i = (done + 1) * nx; i < (kSteps + 1) * nx; ++i) ASSERT_TRUE(std::isnan(row[i])) << i;
  }
  EXPECT_LT(result.steps_done[1], kSteps) << "one outer iteration does not converge a step in contact";
}

TEST(Rollout, BadArgumentsAreRefusedByName) {
  const SceneConfig scene = repositoryScene("quadruped_trot_flat.json");
  Simulation sim = buildSimulation(scene, coulombAndRbf());
  const Model& model = sim.model();
  const int nq = model.nq;
  const Eigen::Index nx = stateLayout(sim.system()).size();
  RolloutRequest good;
  good.initial_states = startsAlongARun(scene, {0, 2});
  good.steps = 2;
  const auto message = [&](const RolloutRequest& request) {
    try {
      rollout(scene, coulombAndRbf(), request);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const auto expectMessage = [&](const RolloutRequest& request, const std::string& part) {
    const std::string m = message(request);
    EXPECT_NE(m.find(part), std::string::npos) << m;
  };
  RolloutRequest r = good;
  r.threads = 0;
  expectMessage(r, "rollout: threads is 0, expected 1 to 256");
  r = good;
  r.steps = -1;
  expectMessage(r, "rollout: steps is -1");
  r = good;
  r.initial_states.resize(2, nx - 1);
  r.initial_states.setZero();
  expectMessage(r, "rollout: initial_states has " + std::to_string(nx - 1) + " columns, expected " +
                       std::to_string(nx) + " (flat states) or " + std::to_string(2 * nq) + " (q and q̇)");
  r = good;
  r.initial_states(1, 1 + nq + 4) = std::numeric_limits<double>::quiet_NaN();
  expectMessage(r, "rollout: initial_states row 1: flat state entry " + std::to_string(1 + nq + 4) + " (qdot[4]) is nan");
  r = good;
  r.initial_states.setZero(2, 2 * nq);
  r.initial_states(0, 3) = std::numeric_limits<double>::infinity();
  expectMessage(r, "rollout: initial_states[0, 3] is not finite");
  r = good;
  r.controls.setZero(2, good.steps * 2 * nq + 1);
  expectMessage(r, "rollout: controls is 2 x " + std::to_string(good.steps * 2 * nq + 1) + ", expected 2 x " +
                       std::to_string(good.steps * 2 * nq));
  r = good;
  r.controls.setZero(3, good.steps * 2 * nq);
  expectMessage(r, "rollout: controls is 3 x");
  r = good;
  r.controls.setZero(2, good.steps * 3 * nq);
  r.controls(1, 3 * nq + nq + 7) = std::numeric_limits<double>::quiet_NaN();
  expectMessage(r, "rollout: controls[1, " + std::to_string(3 * nq + nq + 7) + "] (step 1, target velocity of " +
                       model.bodies[7].joint_name + ") is not finite");
  r = good;
  r.controls.setZero(2, good.steps * 3 * nq);
  r.controls(0, 2 * nq + 1) = 1.0;
  expectMessage(r, "rollout: controls[0, " + std::to_string(2 * nq + 1) + "] (step 0, feed-forward torque of " +
                       model.bodies[1].joint_name + ") is nonzero on an unactuated base coordinate");
  r = good;
  r.steps = 1 << 30;
  expectMessage(r, "split the batch");
  char held[32];  // the count reads as a number, not as "...000.000000"
  std::snprintf(held, sizeof held, "%.3g", 2.0 * ((1 << 30) + 1.0) * static_cast<double>(nx));
  expectMessage(r, std::string("rollout: the result would hold ") + held + " doubles (batch 2 x ");
  EXPECT_EQ(message(good), "accepted");
}

}  // namespace
}  // namespace nmdp
