// A run restored from its state (Simulation::setState, sim/simulation.hpp) repeats the run that was
// never interrupted bit for bit: everything a step carries to the next is in SimulationState (the
// weight QP's warm active set included), in the same simulation and in a fresh one; and the
// state's vectors keep their buffers over steps and setState (the Python bindings view them).
#include <gtest/gtest.h>

#include "scene_simulation.hpp"

namespace nmdp {
namespace {

using test::carryOverScenes;
using test::repositorySimulation;
using test::SceneCase;

std::string describe(const SceneCase& c) {
  std::string text = c.name;
  for (const std::string& o : c.overrides) text += " " + o;
  return text;
}

// The state after each of `steps` steps.
std::vector<SimulationState> run(Simulation& sim, int steps) {
  std::vector<SimulationState> states;
  for (int i = 0; i < steps; ++i) {
    const StepStats stats = sim.step();
    EXPECT_TRUE(stats.converged) << "step " << i << ": " << toString(stats.status);
    states.push_back(sim.state());
  }
  return states;
}

void expectSameRun(const std::vector<SimulationState>& expected, const std::vector<SimulationState>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(expected[i].q, actual[i].q) << "step " << i;  // ==: every bit
    EXPECT_EQ(expected[i].qd, actual[i].qd) << "step " << i;
    EXPECT_EQ(expected[i].time, actual[i].time) << "step " << i;
    EXPECT_EQ(expected[i].w, actual[i].w) << "step " << i;
  }
}

// Restores at several steps: the uninterrupted run arrives at each with the weight QP's active set
// of its last solve, and a restore that started the QP cold would differ wherever that set decides
// the solver's path (in these scenes at some of these steps, not all).
constexpr int kSteps = 14;
const int kRestoreAt[] = {2, 5, 7, 8, 10};

TEST(RestoreState, ARunRestoredInAFreshSimulationRepeatsTheUninterruptedRunBitForBit) {
  for (const SceneCase& c : carryOverScenes()) {
    SCOPED_TRACE(describe(c));
    Simulation sim = repositorySimulation(c.name, c.overrides);
    std::vector<SimulationState> uninterrupted = {sim.state()};
    for (const SimulationState& s : run(sim, kSteps)) uninterrupted.push_back(s);
    for (const int k : kRestoreAt) {
      SCOPED_TRACE("restored at step " + std::to_string(k));
      const std::vector<SimulationState> expected(uninterrupted.begin() + k + 1, uninterrupted.end());
      Simulation fresh = repositorySimulation(c.name, c.overrides);
      fresh.setState(uninterrupted[static_cast<size_t>(k)]);
      expectSameRun(expected, run(fresh, kSteps - k));
      sim.setState(uninterrupted[static_cast<size_t>(k)]);  // used: its workspace holds a later step's buffers
      expectSameRun(expected, run(sim, kSteps - k));
    }
  }
}

TEST(RestoreState, SetStateOfTheCurrentStateChangesNothing) {
  for (const SceneCase& c : carryOverScenes()) {
    SCOPED_TRACE(describe(c));
    Simulation a = repositorySimulation(c.name, c.overrides), b = repositorySimulation(c.name, c.overrides);
    std::vector<SimulationState> plain, restored;
    for (int i = 0; i < kSteps; ++i) {
      ASSERT_TRUE(a.step().converged) << "step " << i;
      b.setState(SimulationState(b.state()));
      ASSERT_TRUE(b.step().converged) << "step " << i;
      plain.push_back(a.state());
      restored.push_back(b.state());
    }
    expectSameRun(plain, restored);
  }
}

TEST(RestoreState, TheStateCarriesTheQpWarmStart) {
  Simulation sim = repositorySimulation("quadruped_trot_flat.json");
  const SimulationState& s = sim.state();
  EXPECT_FALSE(s.qp_warm_valid) << "a run starts cold";
  EXPECT_EQ(s.qp_warm.at_bound.size(), static_cast<size_t>(s.w.size()));
  EXPECT_EQ(s.qp_warm.cap.size(), s.contact_active.size());
  run(sim, 3);
  EXPECT_TRUE(sim.state().qp_warm_valid);

  SimulationState wrong = sim.state();
  wrong.qp_warm.cap.pop_back();
  EXPECT_THROW(sim.setState(wrong), std::invalid_argument);
}

// A numpy array made from state().q keeps looking at q: the step copies into the state's vectors
// rather than swapping them with q_prev, and setState copies into them.
TEST(RestoreState, TheStateVectorsKeepTheirBuffers) {
  Simulation sim = repositorySimulation("quadruped_trot_sand.json");
  const double* q = sim.state().q.data();
  const double* qd = sim.state().qd.data();
  run(sim, 3);
  const SimulationState saved = sim.state();
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(sim.step().converged);
    EXPECT_EQ(sim.state().q.data(), q) << "step " << i;
    EXPECT_EQ(sim.state().qd.data(), qd) << "step " << i;
  }
  sim.setState(saved);
  EXPECT_EQ(sim.state().q.data(), q);
  EXPECT_EQ(sim.state().qd.data(), qd);
  EXPECT_EQ(sim.state().q, saved.q);
  ASSERT_TRUE(sim.step().converged);
  EXPECT_EQ(sim.state().q.data(), q);
  EXPECT_EQ(sim.state().qd.data(), qd);
}

// A floating base re-centres its chart when the pitch nears gimbal lock (solver/integrator.cpp):
// the chart is part of the state, and a restore across a rebase repeats the run too.
TEST(RestoreState, ARestoreRepeatsARunThatRebasesItsChart) {
  const std::vector<std::string> pitching = {"robot.initial.base_rpy=[0, 0.7, 0]",
                                             "robot.initial.velocity.base_angular=[0, 1.5, 0]"};
  Simulation sim = repositorySimulation("quadruped_jump_flat.json", pitching);
  std::vector<SimulationState> states = {sim.state()};
  for (int i = 0; i < 12; ++i) {
    ASSERT_TRUE(sim.step().converged) << "step " << i;
    states.push_back(sim.state());
  }
  size_t rebased = 0;  // the first state in a new chart
  while (rebased < states.size() && states[rebased].base_chart.isIdentity(0.0)) ++rebased;
  ASSERT_TRUE(rebased > 0 && rebased + 3 < states.size()) << "the pitching jump rebases its chart at state " << rebased;
  Simulation fresh = repositorySimulation("quadruped_jump_flat.json", pitching);
  fresh.setState(states[rebased - 1]);
  for (size_t i = rebased; i < states.size(); ++i) {
    ASSERT_TRUE(fresh.step().converged) << "state " << i;
    EXPECT_EQ(fresh.state().base_chart, states[i].base_chart) << "state " << i;
    EXPECT_EQ(fresh.state().q, states[i].q) << "state " << i;
    EXPECT_EQ(fresh.state().qd, states[i].qd) << "state " << i;
  }
}

}  // namespace
}  // namespace nmdp
