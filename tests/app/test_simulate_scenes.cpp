// `nmdp simulate` on the example scenes (DESIGN.md 11): every scene in models/scenes runs a second
// with finite output; RoboSimian (../shared) walks forward steadily and jumps and lands upright over
// its full scenes; the quadruped's jump scenes jump and land upright at dt = 1 ms; the default demo
// trots forward on sand. Runs are kept short (1 s at the scenes' dt; the RoboSimian scenes and the
// 1 ms jumps take a second or two).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>

#include "run_files.hpp"
#include "simulate_run.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::vector<std::string> exampleScenes() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(sourcePath("models/scenes")))
    if (e.path().extension() == ".json") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The files a scene refers to that live in ../shared and are absent ("" if none).
std::string missingSharedFile(const std::string& scene_path) {
  json scene;
  try {
    scene = json::parse(readText(scene_path));
  } catch (...) {
    return "";  // the run reports it
  }
  const fs::path folder = fs::path(scene_path).parent_path();
  const std::string shared = fs::weakly_canonical(NMDP_SHARED_DIR).string();
  std::vector<std::string> refs;
  auto collect = [&](const json& node, const char* key) {
    if (node.is_object() && node.contains(key) && node.at(key).is_string()) refs.push_back(node.at(key).get<std::string>());
  };
  if (scene.contains("robot")) collect(scene["robot"], "urdf");
  if (scene.contains("contacts") && scene["contacts"].is_object() && scene["contacts"].contains("model"))
    collect(scene["contacts"]["model"], "file");
  if (scene.contains("terrain")) collect(scene["terrain"], "file");
  for (const std::string& r : refs) {
    const fs::path p = fs::weakly_canonical(fs::path(r).is_absolute() ? fs::path(r) : folder / r);
    if (!fs::exists(p) && p.string().rfind(shared, 0) == 0) return p.string();
  }
  return "";
}

class ExampleScene : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleScene, OneSecondCompletes) {
  const std::string scene = sceneFile(GetParam());
  if (const std::string missing = missingSharedFile(scene); !missing.empty())
    GTEST_SKIP() << "../shared is absent (" << missing << "): skipping " << GetParam();
  TempDir dir;
  const std::string out = dir.file("run.h5");
  const CliResult r = runComplete({scene, "--set", "duration=1", "--quiet"}, dir, out);
  if (!fs::exists(out)) return;
  const json config = configOf(out);
  const double dt = config["integrator"]["dt"].get<double>();
  const long expected = std::lround(1.0 / dt) + 1;
  EXPECT_EQ(completeRows(out), expected) << "stderr: " << r.err;
  for (const auto& [name, shape] : kNumericDatasets) {
    const Dataset d = readDataset(out, name);
    ASSERT_TRUE(d.ok) << name;
    if (name == "/contacts/features") {
      // A patched ground reports the heaviest material's columns: NaN where that material reads
      // less (the rigid ground has no lean angles), but never infinite, and the depth always.
      const size_t columns = d.dims.back();
      for (size_t i = 0; i < d.values.size(); ++i)
        EXPECT_TRUE(i % columns == 0 ? std::isfinite(d.values[i]) : !std::isinf(d.values[i])) << name << " value " << i;
      continue;
    }
    EXPECT_TRUE(allFinite(d.values, d.values.size())) << name << " has a non-finite value";
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, ExampleScene, ::testing::ValuesIn(exampleScenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = fs::path(info.param).stem().string();
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

// ---- RoboSimian in the paper's configuration (../shared) ------------------------------------------
// The full 10 s of models/scenes/robosimian_{walk,jump}_planar.json (a second or two each): the
// walk moves forward at a steady pace without falling, the jump leaves the ground and lands upright.

struct Trajectory {
  std::vector<double> time, x, z, roll, pitch;
  std::vector<double> normal_forces;  // N × C, the world z force of each contact
  long contacts = 0;
  json config;
};

Trajectory runScene(const std::string& name, const TempDir& dir, const std::vector<std::string>& settings = {}) {
  const std::string out = dir.file(name + ".h5");
  std::vector<std::string> args = {sceneFile(name + ".json"), "--quiet"};
  for (const std::string& s : settings) args.insert(args.end(), {"--set", s});
  runComplete(args, dir, out);
  Trajectory t;
  if (!fs::exists(out)) return t;
  t.time = readDataset(out, "/time").values;
  const Dataset position = readDataset(out, "/base/position"), rpy = readDataset(out, "/base/rpy");
  const Dataset wrench = readDataset(out, "/contacts/wrench");
  t.contacts = wrench.dims.size() == 3 ? static_cast<long>(wrench.dims[1]) : 0;
  for (size_t i = 0; i < t.time.size(); ++i) {
    t.x.push_back(position.values[3 * i]);
    t.z.push_back(position.values[3 * i + 2]);
    t.roll.push_back(rpy.values[3 * i]);
    t.pitch.push_back(rpy.values[3 * i + 1]);
    for (long c = 0; c < t.contacts; ++c) t.normal_forces.push_back(wrench.values[(i * t.contacts + c) * 6 + 5]);
  }
  t.config = configOf(out);
  return t;
}

TEST(SimulateCli, RoboSimianWalksForwardSteadily) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  TempDir dir;
  const Trajectory walk = runScene("robosimian_walk_planar", dir);
  ASSERT_EQ(walk.time.size(), 201u);
  const double standing = walk.config["robot"]["initial"]["height"].get<double>();
  const double period = walk.config["controller"]["gait"]["period"].get<double>();
  const double stride = walk.config["controller"]["gait"]["stride_length"].get<double>();
  const double dt = walk.config["integrator"]["dt"].get<double>();
  for (size_t i = 0; i < walk.time.size(); ++i) {
    EXPECT_GT(walk.z[i], 0.7 * standing) << "t = " << walk.time[i] << ": the torso fell";
    EXPECT_LT(walk.z[i], 1.3 * standing) << "t = " << walk.time[i];
    EXPECT_LT(std::abs(walk.pitch[i]), 0.1) << "t = " << walk.time[i];
  }
  // Per gait cycle the feet push the torso back by 2 strides (one per diagonal pair); it advances
  // by at least a quarter of that, and by nearly the same distance every cycle after the first.
  const long per_cycle = std::lround(period / dt);
  std::vector<double> advance;
  for (size_t i = per_cycle; i + per_cycle < walk.x.size(); i += per_cycle) advance.push_back(walk.x[i + per_cycle] - walk.x[i]);
  ASSERT_GE(advance.size(), 8u);
  const double mean = std::accumulate(advance.begin(), advance.end(), 0.0) / advance.size();
  EXPECT_GT(mean, 0.5 * stride) << "the walk barely moves forward";
  for (size_t k = 0; k < advance.size(); ++k)
    EXPECT_NEAR(advance[k], mean, 0.2 * mean) << "cycle " << k + 2 << " of the walk";
  std::cout << "RoboSimian walk: " << walk.x.back() - walk.x.front() << " m in " << walk.time.back() << " s, "
            << mean << " m per " << period << " s cycle, torso height "
            << *std::min_element(walk.z.begin(), walk.z.end()) / standing << "–"
            << *std::max_element(walk.z.begin(), walk.z.end()) / standing << " of standing\n";
}

TEST(SimulateCli, RoboSimianJumpsAndLandsUpright) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  TempDir dir;
  const Trajectory jump = runScene("robosimian_jump_planar", dir);
  ASSERT_EQ(jump.time.size(), 201u);
  ASSERT_EQ(jump.contacts, 4);
  const double standing = jump.config["robot"]["initial"]["height"].get<double>();
  const double period = jump.config["controller"]["gait"]["period"].get<double>();
  const double dt = jump.config["integrator"]["dt"].get<double>();
  // Symmetric poses on a symmetric robot: the torso stays about level (the paper's ground truth)
  // and near where it started. The 1 ms run tilts by up to 0.044 rad and moves 5.6 cm over the
  // five jumps (the fixed 50 ms step, which damps the push-off, tilted 0.002 rad).
  for (size_t i = 0; i < jump.time.size(); ++i) {
    EXPECT_LT(std::abs(jump.pitch[i]), 0.1) << "t = " << jump.time[i] << ": the torso tilts";
    EXPECT_NEAR(jump.x[i], 0.0, 0.15) << "t = " << jump.time[i];
  }
  // Each of the 5 cycles: airborne (every contact force below 1 N, i.e. in the air) for several
  // steps with the torso well above standing, then back on four loaded feet, resting at the same
  // height every cycle (the PD gains let it settle some 5 % below the standing pose).
  const long per_cycle = std::lround(period / dt);
  int jumps = 0;
  std::vector<double> rest_heights;
  for (long start = 0; start + per_cycle < static_cast<long>(jump.time.size()); start += per_cycle) {
    long airborne = 0;
    double peak = 0;
    for (long i = start + 1; i <= start + per_cycle; ++i) {
      bool in_air = true;
      for (long c = 0; c < jump.contacts; ++c) in_air = in_air && jump.normal_forces[i * jump.contacts + c] < 1.0;
      airborne += in_air;
      peak = std::max(peak, jump.z[i]);
    }
    const long rest = start + per_cycle;  // the end of the pause
    SCOPED_TRACE("cycle starting at t = " + std::to_string(jump.time[start]));
    EXPECT_GE(airborne, 3) << "the jump did not leave the ground";
    EXPECT_GT(peak, standing + 0.15);
    EXPECT_NEAR(jump.z[rest], standing, 0.1 * standing) << "not back standing after the pause";
    if (!rest_heights.empty()) {
      // (The 1 ms run rests at 0.7550-0.7619 m from cycle to cycle, the tilt of each landing differing.)
      EXPECT_NEAR(jump.z[rest], rest_heights.back(), 0.01) << "a different landing";
    }
    rest_heights.push_back(jump.z[rest]);
    for (long c = 0; c < jump.contacts; ++c) EXPECT_GT(jump.normal_forces[rest * jump.contacts + c], 50.0) << "contact " << c;
    jumps += airborne >= 3;
    std::cout << "RoboSimian jump at t = " << jump.time[start] << ": " << airborne * dt << " s in the air, torso peak "
              << peak << " m (standing " << standing << " m)\n";
  }
  EXPECT_EQ(jumps, 5);
}

// The quadruped's jump scenes at dt = 1 ms: one cycle (2 s) leaves the ground, stays upright and
// lands on four loaded feet. A shorter, harder push-off flips the robot over in the air at 1 ms.
class QuadrupedJumpScene : public ::testing::TestWithParam<std::string> {};

TEST_P(QuadrupedJumpScene, LeavesTheGroundAndLandsUprightAtOneMillisecond) {
  TempDir dir;
  const Trajectory jump = runScene(GetParam(), dir, {"integrator.dt=0.001", "duration=2"});
  ASSERT_EQ(jump.time.size(), 2001u);
  ASSERT_EQ(jump.contacts, 4);
  const double standing = jump.config["robot"]["initial"]["height"].get<double>();
  ASSERT_EQ(jump.config["controller"]["gait"]["period"].get<double>(), 2.0);
  long airborne = 0;
  double peak = 0, tilt = 0;
  for (size_t i = 1; i < jump.time.size(); ++i) {
    bool in_air = true;
    for (long c = 0; c < jump.contacts; ++c) in_air = in_air && jump.normal_forces[i * jump.contacts + c] < 1.0;
    airborne += in_air;
    peak = std::max(peak, jump.z[i]);
    tilt = std::max({tilt, std::abs(jump.roll[i]), std::abs(jump.pitch[i])});
  }
  // Measured (full-body-pd K): rigid 65 airborne steps, apex 0.468 m, tilt 0.18 rad; sand 41, 0.439 m,
  // 0.12 rad.
  EXPECT_GE(airborne, 20) << "the jump did not leave the ground";
  EXPECT_GT(peak, standing + 0.05);
  EXPECT_LT(tilt, 0.3) << "the torso tipped";
  const size_t end = jump.time.size() - 1;
  EXPECT_GT(jump.z[end], 0.8 * standing) << "not standing after the pause";
  for (long c = 0; c < jump.contacts; ++c) EXPECT_GT(jump.normal_forces[end * jump.contacts + c], 5.0) << "contact " << c;
}

INSTANTIATE_TEST_SUITE_P(Scenes, QuadrupedJumpScene, ::testing::Values("quadruped_jump_flat", "quadruped_jump_sand"));

// ---- the default demo: the quadruped trots forward on the project's RFT-fitted sand ----------

// The whole 10 s of models/scenes/quadruped_trot_sand.json (scripts/demo.sh runs it): the trot must
// carry the robot forward at a steady pace without falling: nominally about 1.8 m in 10 s, some
// 0.35 m every 2 s window, the torso 0.77-1.0 of the standing height (data/granular/README.md). A
// robot drifting backward fails both forward checks below.
TEST(SimulateCli, SandTrotMovesForwardSteadilyWithoutFalling) {
  const std::string scene = sceneFile("quadruped_trot_sand.json");
  TempDir dir;
  const std::string out = dir.file("sand_trot.h5");
  const CliResult r = runComplete({scene, "--quiet"}, dir, out);
  ASSERT_TRUE(fs::exists(out)) << r.err;
  const json config = configOf(out);
  const double dt = config["integrator"]["dt"].get<double>();
  const double duration = config["duration"].get<double>();
  const double standing = config["robot"]["initial"]["height"].get<double>();
  ASSERT_EQ(duration, 10.0) << "the demo scene runs 10 s";
  ASSERT_EQ(dt, 0.05) << "the demo scene runs at dt = 50 ms";
  const long N = completeRows(out);
  ASSERT_EQ(N, std::lround(duration / dt) + 1) << r.err;
  const Dataset position = readDataset(out, "/base/position");
  const Dataset rpy = readDataset(out, "/base/rpy");
  ASSERT_TRUE(position.ok && rpy.ok);
  ASSERT_GE(position.values.size(), static_cast<size_t>(3 * N));
  auto x = [&](long i) { return position.values[i * 3 + 0]; };
  auto z = [&](long i) { return position.values[i * 3 + 2]; };

  // Forward: at least 5 cm/s on average, and every 2 s window (the first included) moves forward by
  // at least 10 cm and by at least half the run's mean advance per 2 s: no backward drift, no
  // stall, a steady pace.
  const double distance = x(N - 1) - x(0);
  EXPECT_GT(distance, 0.5) << "forward distance in 10 s";
  const long window = std::lround(2.0 / dt);
  const double mean_window = distance * window / (N - 1);
  long slowest = 0;
  for (long i = 0; i + window < N; ++i)
    if (x(i + window) - x(i) < x(slowest + window) - x(slowest)) slowest = i;
  const double slowest_advance = x(slowest + window) - x(slowest);
  EXPECT_GT(slowest_advance, std::max(0.1, 0.5 * mean_window))
      << "the slowest 2 s window, from t = " << slowest * dt << " s; the mean advance per 2 s is " << mean_window << " m";
  // Without falling: the torso stays within 30 % of its standing height, and upright.
  long lowest = 0, highest = 0, most_pitched = 0;
  for (long i = 0; i < N; ++i) {
    if (z(i) < z(lowest)) lowest = i;
    if (z(i) > z(highest)) highest = i;
    if (std::abs(rpy.values[i * 3 + 1]) > std::abs(rpy.values[most_pitched * 3 + 1])) most_pitched = i;
  }
  EXPECT_GT(z(lowest), 0.7 * standing) << "lowest torso at t = " << lowest * dt << " s; standing height " << standing;
  EXPECT_LT(z(highest), 1.3 * standing) << "highest torso at t = " << highest * dt << " s; standing height " << standing;
  EXPECT_LT(std::abs(rpy.values[most_pitched * 3 + 1]), 0.5) << "pitch at t = " << most_pitched * dt << " s";
}

}  // namespace
}  // namespace nmdp::test
