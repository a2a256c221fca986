// The flat state vector (sim/state_vector.hpp): its layout, a round trip that keeps every bit, the
// messages for a vector that is not a state, and a run restored from a flat state in a fresh
// simulation that repeats the uninterrupted run bit for bit.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <limits>

#include "scene_simulation.hpp"
#include "sim/state_vector.hpp"

namespace nmdp {
namespace {

using test::repositorySimulation;

// A state with every part in use: contacts carrying load, a warm QP, a chart that is not the identity.
SimulationState stateInMotion(Simulation& sim, int steps) {
  for (int i = 0; i < steps; ++i) EXPECT_TRUE(sim.step().converged) << "step " << i;
  return sim.state();
}

const StateLayout::Part& part(const std::vector<StateLayout::Part>& parts, const std::string& name) {
  for (const StateLayout::Part& p : parts)
    if (p.name == name) return p;
  throw std::runtime_error("no part " + name);
}

TEST(StateVector, TheLayoutListsItsPartsInOrderWithoutGaps) {
  Simulation sim = repositorySimulation("quadruped_trot_flat.json");
  const StateLayout layout = stateLayout(sim.system());
  EXPECT_EQ(layout.nq, 18);
  EXPECT_EQ(layout.contacts, 4);
  EXPECT_EQ(layout.weights, static_cast<int>(sim.state().w.size()));
  const std::vector<StateLayout::Part> parts = layout.parts();
  std::vector<std::string> names;
  int offset = 0;
  for (const StateLayout::Part& p : parts) {
    names.push_back(p.name);
    EXPECT_EQ(p.offset, offset) << p.name;
    offset += p.length;
  }
  EXPECT_EQ(offset, layout.size());
  EXPECT_EQ(names, (std::vector<std::string>{"time", "q", "qdot", "q_prev", "qdot_prev", "h_prev",
                                             "second_order_history", "contact_active", "substeps_since_touchdown",
                                             "base_chart", "beta", "beta_start", "w", "h_next", "qp_warm_valid",
                                             "qp_warm_at_bound", "qp_warm_cap"}));
  EXPECT_EQ(part(parts, "q").offset, layout.q());
  EXPECT_EQ(part(parts, "qdot").offset, layout.qdot());
  EXPECT_EQ(part(parts, "w").length, layout.weights);
  EXPECT_EQ(part(parts, "qp_warm_cap").length, layout.contacts);
}

TEST(StateVector, ARoundTripKeepsEveryBit) {
  Simulation sim = repositorySimulation("quadruped_trot_flat.json");
  SimulationState s = stateInMotion(sim, 5);
  s.base_chart = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  s.h_next = 0.0125;
  s.second_order_history = true;
  const StateLayout layout = stateLayout(sim.system());
  Eigen::VectorXd x;
  flattenState(layout, s, x);
  ASSERT_EQ(x.size(), layout.size());
  EXPECT_EQ(x[StateLayout::time], s.time);
  EXPECT_EQ(x.segment(layout.q(), layout.nq), s.q);
  EXPECT_EQ(x.segment(layout.qdot(), layout.nq), s.qd);
  EXPECT_EQ(x[part(layout.parts(), "qp_warm_valid").offset], 1.0) << "a state in motion has a warm QP start";

  SimulationState back;  // empty: unflattenState sizes it
  unflattenState(layout, x, back);
  EXPECT_EQ(back.time, s.time);
  EXPECT_EQ(back.q, s.q);
  EXPECT_EQ(back.qd, s.qd);
  EXPECT_EQ(back.q_prev, s.q_prev);
  EXPECT_EQ(back.qd_prev, s.qd_prev);
  EXPECT_EQ(back.h_prev, s.h_prev);
  EXPECT_EQ(back.second_order_history, s.second_order_history);
  EXPECT_EQ(back.contact_active, s.contact_active);
  EXPECT_EQ(back.substeps_since_touchdown, s.substeps_since_touchdown);
  EXPECT_EQ(back.base_chart, s.base_chart);
  EXPECT_EQ(back.beta, s.beta);
  EXPECT_EQ(back.beta_start, s.beta_start);
  EXPECT_EQ(back.w, s.w);
  EXPECT_EQ(back.h_next, s.h_next);
  EXPECT_EQ(back.qp_warm_valid, s.qp_warm_valid);
  EXPECT_EQ(back.qp_warm.at_bound, s.qp_warm.at_bound);
  EXPECT_EQ(back.qp_warm.cap, s.qp_warm.cap);
  Eigen::VectorXd again;
  flattenState(layout, back, again);
  ASSERT_EQ(again.size(), x.size());
  EXPECT_EQ(std::memcmp(again.data(), x.data(), sizeof(double) * x.size()), 0);
}

// Each refused vector leaves the target state as it was, and names the part and the entry.
TEST(StateVector, AVectorThatIsNotAStateIsRefusedByName) {
  Simulation sim = repositorySimulation("quadruped_trot_flat.json");
  const StateLayout layout = stateLayout(sim.system());
  const std::vector<StateLayout::Part> parts = layout.parts();
  Eigen::VectorXd good;
  flattenState(layout, stateInMotion(sim, 3), good);
  struct Bad {
    std::string part;
    int index;
    double value;
    std::string message;  // expected within the error
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Bad> cases = {
      {"q", 2, nan, "flat state entry 3 (q[2]) is nan: expected a finite number"},
      {"time", 0, std::numeric_limits<double>::infinity(), "(time) is inf"},
      {"qdot", 17, nan, "(qdot[17]) is nan"},
      {"contact_active", 1, 0.5, "(contact_active[1]) is 0.5: expected 0 or 1"},
      {"second_order_history", 0, -1.0, "(second_order_history) is -1: expected 0 or 1"},
      {"qp_warm_valid", 0, 2.0, "(qp_warm_valid) is 2: expected 0 or 1"},
      {"qp_warm_at_bound", 7, 0.25, "(qp_warm_at_bound[7]) is 0.25"},
      {"substeps_since_touchdown", 0, 1.5, "(substeps_since_touchdown) is 1.5: expected an integer from 0 to 2"},
      {"substeps_since_touchdown", 0, 3.0, "(substeps_since_touchdown) is 3: expected an integer from 0 to 2"},
      {"h_prev", 0, 0.0, "(h_prev) is 0: expected a positive number"},
      {"beta", 0, -1e-4, "(beta) is -0.0001: expected a positive number"},
      {"h_next", 0, -0.01, "(h_next) is -0.01: expected a number ≥ 0"},
      {"w", 4, nan, "(w[4]) is nan"},
      {"base_chart", 0, 1.1, "(base_chart) are not a rotation matrix"},
      {"base_chart", 3, 0.2, "(base_chart) are not a rotation matrix"},
  };
  for (const Bad& c : cases) {
    SCOPED_TRACE(c.part + "[" + std::to_string(c.index) + "]");
    Eigen::VectorXd x = good;
    x[part(parts, c.part).offset + c.index] = c.value;
    SimulationState target = sim.state();
    const SimulationState before = target;
    try {
      unflattenState(layout, x, target);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
    EXPECT_EQ(target.q, before.q);
    EXPECT_EQ(target.time, before.time);
  }
  for (const int size : {layout.size() - 1, layout.size() + 1, 0}) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(size);
    SimulationState target;
    try {
      unflattenState(layout, x, target);
      ADD_FAILURE() << "accepted a vector of " << size << " entries";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), "flat state has " + std::to_string(size) + " entries, expected " +
                                           std::to_string(layout.size()) + " (nq = 18, 4 contacts, " +
                                           std::to_string(layout.weights) + " contact weights)");
    }
  }
}

// The state at step k of a run, flattened and restored in a fresh simulation of the same scene:
// the steps that follow are the uninterrupted run's, bit for bit.
TEST(StateVector, AFlatStateRestoredInAFreshSimulationRepeatsTheRun) {
  constexpr int kStepsBefore = 7, kStepsAfter = 8;
  for (const char* scene : {"quadruped_trot_sand.json", "quadruped_trot_flat.json", "quadruped_jump_flat.json"}) {
    SCOPED_TRACE(scene);
    Simulation sim = repositorySimulation(scene);
    const StateLayout layout = stateLayout(sim.system());
    Eigen::VectorXd flat;
    flattenState(layout, stateInMotion(sim, kStepsBefore), flat);
    const double time = sim.time();
    std::vector<Eigen::VectorXd> q, qd;
    for (int i = 0; i < kStepsAfter; ++i) {
      ASSERT_TRUE(sim.step().converged) << "step " << i;
      q.push_back(sim.state().q);
      qd.push_back(sim.state().qd);
    }
    Simulation fresh = repositorySimulation(scene);
    SimulationState restored;
    unflattenState(layout, flat, restored);
    fresh.setState(restored);
    EXPECT_EQ(fresh.time(), time);
    for (int i = 0; i < kStepsAfter; ++i) {
      ASSERT_TRUE(fresh.step().converged) << "step " << i;
      EXPECT_EQ(fresh.state().q, q[i]) << "step " << i;
      EXPECT_EQ(fresh.state().qd, qd[i]) << "step " << i;
    }
  }
}

}  // namespace
}  // namespace nmdp
