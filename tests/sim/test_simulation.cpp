// buildSimulation and Simulation (sim/simulation.hpp): a scene built and stepped through the library
// gives bit-for-bit the /q, /qdot and /time `nmdp simulate` writes for it (every recorded row,
// output.every included); two simulations of one scene, and one moved, step identically; a bad
// scene fails with the CLI's message; observers see every completed step and no other; setState
// restores a run; a step allocates nothing once warmed up.
#include <gtest/gtest.h>

#include <csignal>
#include <nlohmann/json.hpp>

#include "contact_models/registry.hpp"
#include "io/hdf5_file.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

#define NMDP_COUNT_OPERATOR_NEW
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp {
namespace {

using test::sourcePath;

// The scene file with --set overrides, as `nmdp simulate SCENE --set ...` reads it.
SceneConfig sceneWith(const std::string& path, const std::vector<std::string>& overrides) {
  nlohmann::json scene = loadSceneJson(path);
  for (const std::string& assignment : overrides) applyOverride(scene, assignment, path + ": --set");
  return parseScene(scene, path);
}

Simulation build(const std::string& path, const std::vector<std::string>& overrides = {}) {
  return buildSimulation(sceneWith(path, overrides), ContactModelRegistry::withBuiltins());
}

std::vector<std::string> setArguments(const std::vector<std::string>& overrides) {
  std::vector<std::string> args;
  for (const std::string& o : overrides) args.insert(args.end(), {"--set", o});
  return args;
}

struct Case {
  const char* scene;
  std::vector<std::string> overrides;
};

// Every row the CLI writes is the library's state at that step: the initial state, every
// output.every-th step and the last.
TEST(Simulation, SteppedThroughTheLibraryGivesTheRowsTheCliWrites) {
  const test::TempDir dir;
  const std::vector<Case> cases = {{"models/scenes/quadruped_trot_flat.json", {"duration=0.5"}},
                                   {"models/scenes/quadruped_trot_sand.json", {"duration=0.3", "output.every=4"}},
                                   {"models/scenes/quadruped_jump_flat.json", {"duration=0.4", "integrator.method=pbd-zopgm"}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scene);
    const std::string out = dir.file("cli.h5");
    std::vector<std::string> args = {"simulate", sourcePath(c.scene), "--out", out, "--quiet"};
    const std::vector<std::string> sets = setArguments(c.overrides);
    args.insert(args.end(), sets.begin(), sets.end());
    const test::CliResult cli = test::runNmdp(args, dir);
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    const h5::File file = h5::File::openRead(out);
    const Eigen::MatrixXd q = file.readMatrix("/q"), qd = file.readMatrix("/qdot"), t = file.readMatrix("/time");

    Simulation sim = build(sourcePath(c.scene), c.overrides);
    const long steps = sim.scheduledSteps(), every = sim.scene().output_every;
    long row = 0;
    auto expectRow = [&](long step) {
      ASSERT_LT(row, q.rows()) << "step " << step;
      EXPECT_EQ(Eigen::VectorXd(q.row(row).transpose()), sim.state().q) << "step " << step;
      EXPECT_EQ(Eigen::VectorXd(qd.row(row).transpose()), sim.state().qd) << "step " << step;
      EXPECT_EQ(t(row, 0), sim.time()) << "step " << step;
      ++row;
    };
    expectRow(0);
    for (long i = 1; i <= steps; ++i) {
      ASSERT_TRUE(sim.step().converged) << "step " << i;
      if (i % every == 0 || i == steps) expectRow(i);
    }
    EXPECT_EQ(row, q.rows());
  }
}

TEST(Simulation, TwoSimulationsOfOneSceneAndAMovedOneStepIdentically) {
  const std::string scene = sourcePath("models/scenes/quadruped_trot_sand.json");
  Simulation a = build(scene), b = build(scene);
  Simulation moved_from = build(scene);
  for (int i = 0; i < 2; ++i) moved_from.step();  // a moved simulation carries its state along
  Simulation c = std::move(moved_from);
  for (int i = 1; i <= 8; ++i) {
    ASSERT_TRUE(a.step().converged);
    ASSERT_TRUE(b.step().converged);
    if (i > 2) {
      ASSERT_TRUE(c.step().converged);
    }
    EXPECT_EQ(a.state().q, b.state().q) << "step " << i;
    EXPECT_EQ(a.state().qd, b.state().qd) << "step " << i;
    EXPECT_EQ(a.contactWrenches(), b.contactWrenches()) << "step " << i;
    if (i >= 2) {
      EXPECT_EQ(a.state().q, c.state().q) << "step " << i;
    }
  }
  EXPECT_EQ(a.resolvedScene(), b.resolvedScene());
}

// What buildSimulation throws is what `nmdp simulate` prints, for errors found at every phase of the
// build: the robot's checks, the contact model, the terrain and the gait.
TEST(Simulation, BadSceneFailsWithTheCliMessage) {
  const test::TempDir dir;
  const std::string urdf = test::quadrupedUrdf();
  const std::vector<nlohmann::json> scenes = {
      {{"robot", {{"urdf", urdf}}}, {"controller", {{"kp", {{"no_such_joint", 1.0}}}}}},
      {{"robot", {{"urdf", urdf}}}, {"contacts", {{"model", {{"type", "coulom"}}}}}},
      {{"robot", {{"urdf", urdf}}}, {"contacts", {{"model", {{"type", "coulomb"}, {"mu", -1.0}}}}}},
      {{"robot", {{"urdf", urdf}}}, {"terrain", {{"type", "plane"}, {"slope", "steep"}}}},
      {{"robot", {{"urdf", urdf}}}, {"controller", {{"gait", {{"type", "trot"}, {"stride_length", 5.0}}}}}},
  };
  for (const nlohmann::json& scene : scenes) {
    SCOPED_TRACE(scene.dump());
    const std::string path = dir.write("bad.json", scene.dump());
    std::string message;
    try {
      build(path);
    } catch (const InputError& e) {
      message = e.what();
    }
    const test::CliResult cli = test::runNmdp({"simulate", path, "--out", dir.file("bad.h5"), "--quiet"}, dir);
    if (message.empty()) {  // a scene this list expected to fail runs: the CLI must run it too
      ADD_FAILURE() << "buildSimulation accepted the scene";
      continue;
    }
    EXPECT_EQ(cli.exit_code, 1);
    EXPECT_EQ(cli.err, "nmdp simulate: error: " + message + "\n");
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.h5")));
  }
}

TEST(Simulation, ObserversSeeEveryCompletedStepAndNoOther) {
  Simulation sim = build(sourcePath("models/scenes/quadruped_stand_flat.json"));
  std::vector<double> first, second;
  std::vector<int> outer;
  sim.addObserver([&](const Simulation& s, const StepStats& stats) {
    first.push_back(s.time());
    outer.push_back(stats.outer_iterations);
  });
  sim.addObserver([&](const Simulation& s, const StepStats&) {
    ASSERT_EQ(first.size(), second.size() + 1) << "observers run in the order added";
    second.push_back(s.time());
  });
  std::vector<int> returned;
  for (int i = 0; i < 3; ++i) returned.push_back(sim.step().outer_iterations);
  EXPECT_EQ(first, std::vector<double>({sim.dt(), 2 * sim.dt(), 3 * sim.dt()}));
  EXPECT_EQ(second, first);
  EXPECT_EQ(outer, returned);

  // A cancelled step is returned, not observed.
  const volatile std::sig_atomic_t raised = 1;
  const StepStats cancelled = sim.step(&raised);
  EXPECT_EQ(cancelled.status, StepStatus::Cancelled);
  EXPECT_FALSE(cancelled.converged);
  EXPECT_EQ(first.size(), 3u);
}

// After setState the run depends on the state alone: the same state set in a used simulation and in
// a fresh one steps bit for bit like the run that was never interrupted (tests/sim/test_restore_state.cpp
// covers more scenes).
TEST(Simulation, SetStateRestoresARun) {
  const std::string scene = sourcePath("models/scenes/quadruped_trot_flat.json");
  Simulation sim = build(scene);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(sim.step().converged);
  const SimulationState saved = sim.state();
  std::vector<Eigen::VectorXd> uninterrupted;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(sim.step().converged);
    uninterrupted.push_back(sim.state().q);
  }
  sim.setState(saved);
  EXPECT_EQ(sim.time(), saved.time);
  Simulation fresh = build(scene);
  fresh.setState(saved);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(sim.step().converged);
    ASSERT_TRUE(fresh.step().converged);
    EXPECT_EQ(sim.state().q, fresh.state().q) << "step " << i;
    EXPECT_EQ(sim.state().qd, fresh.state().qd) << "step " << i;
    EXPECT_EQ(sim.state().q, uninterrupted[i]) << "step " << i;
  }
  SimulationState wrong = saved;
  wrong.q.resize(saved.q.size() - 1);
  EXPECT_THROW(sim.setState(wrong), std::invalid_argument);
  EXPECT_THROW(sim.setTargets(nullptr), std::invalid_argument);
}

TEST(Simulation, StepAllocatesNothingOnceWarmedUp) {
  for (const char* scene : {"models/scenes/quadruped_trot_flat.json", "models/scenes/quadruped_trot_sand.json"}) {
    Simulation sim = build(sourcePath(scene));
    int observed = 0;
    sim.addObserver([&](const Simulation&, const StepStats&) { ++observed; });
    for (int i = 0; i < 5; ++i) sim.step();  // warm-up: contacts touch down, buffers reach their size
    StepStats stats;
    const test::AllocationCount count = test::countAllocations([&] { stats = sim.step(); });
    EXPECT_TRUE(stats.converged) << scene;
    EXPECT_EQ(observed, 6);
    EXPECT_EQ(count.total(), 0) << scene << ": " << count.news << " operator new, " << count.mallocs
                                << " malloc-family calls in one step after warm-up";
  }
}

}  // namespace
}  // namespace nmdp
