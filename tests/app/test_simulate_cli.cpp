// `nmdp simulate` end to end (DESIGN.md 11): every example scene runs; the output layout is the
// documented one and its first row is the initial state; swapping the method or the contact model
// with --set is a configuration change only; bad input gives one line on stderr, exit code 1 and
// no output file; runs are deterministic; a run killed with SIGKILL leaves a readable file (SWMR
// reading); --quiet (how a run ends early: test_simulate_ending.cpp);
// RoboSimian (../shared) walks forward steadily and jumps and lands upright over its full scenes;
// the quadruped's jump scenes jump and land upright at dt = 1 ms. Runs are kept short (duration
// 0.5–1 s at dt 0.05; the RoboSimian scenes and the 1 ms jumps take a second or two).
// tests/CMakeLists.txt gives tests no HDF5 include folder (nmdp_io links HDF5 privately); Debian
// installs the serial headers under hdf5/serial.
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <set>
#include <thread>

#include "contact_models/coulomb_model.hpp"
#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string sceneFile(const std::string& name) { return sourcePath("models/scenes/" + name); }
std::string trotScene() { return sceneFile("quadruped_trot_flat.json"); }

std::string commandLine(const std::vector<std::string>& args) {
  std::string s = "nmdp";
  for (const std::string& a : args) s += " " + shellQuote(a);
  return s;
}

// ---- reading the output with the HDF5 C API -----------------------------------------------------

// A numeric dataset read as double (row-major, any rank), with its dimensions and stored type.
struct Dataset {
  bool ok = false;
  std::vector<hsize_t> dims;
  H5T_class_t type_class = H5T_NO_CLASS;
  size_t type_size = 0;
  std::vector<double> values;
  long rows() const { return dims.empty() ? 0 : static_cast<long>(dims[0]); }
  size_t rowSize() const {
    size_t s = 1;
    for (size_t i = 1; i < dims.size(); ++i) s *= dims[i];
    return s;
  }
};

bool exists(hid_t file, const std::string& name) {
  // H5Lexists needs every intermediate group to exist.
  size_t pos = 0;
  while ((pos = name.find('/', pos + 1)) != std::string::npos)
    if (H5Lexists(file, name.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0;
}

// Opens the output as the README says: plainly, or as a SWMR reader for a killed run's file.
hid_t openOutput(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures are reported by the test
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  return f >= 0 ? f : H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, H5P_DEFAULT);
}

Dataset readDataset(const std::string& path, const std::string& name) {
  Dataset out;
  const hid_t f = openOutput(path);
  if (f < 0) return out;
  if (exists(f, name)) {
    const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    if (d >= 0) {
      const hid_t space = H5Dget_space(d), type = H5Dget_type(d);
      out.dims.resize(std::max(0, H5Sget_simple_extent_ndims(space)));
      H5Sget_simple_extent_dims(space, out.dims.data(), nullptr);
      out.type_class = H5Tget_class(type);
      out.type_size = H5Tget_size(type);
      const hssize_t count = H5Sget_simple_extent_npoints(space);
      out.values.resize(static_cast<size_t>(std::max<hssize_t>(count, 0)));
      out.ok = out.type_class == H5T_STRING ||
               count == 0 || H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data()) >= 0;
      H5Tclose(type);
      H5Sclose(space);
      H5Dclose(d);
    }
  }
  H5Fclose(f);
  return out;
}

// Every dataset path in the file ("/time", "/base/position", ...).
std::set<std::string> datasetNames(const std::string& path) {
  std::set<std::string> names;
  const hid_t f = openOutput(path);
  if (f < 0) return names;
  struct Visit {
    hid_t file;
    std::set<std::string>* names;
  } visit{f, &names};
  const H5L_iterate_t callback = [](hid_t, const char* name, const auto*, void* data) -> herr_t {
    Visit& v = *static_cast<Visit*>(data);
    const hid_t object = H5Oopen(v.file, name, H5P_DEFAULT);
    if (object >= 0) {
      if (H5Iget_type(object) == H5I_DATASET) v.names->insert(std::string("/") + name);
      H5Oclose(object);
    }
    return 0;
  };
  H5Lvisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, callback, &visit);
  H5Fclose(f);
  return names;
}

// The number of complete rows: the scalar /steps when the writer stores one, else len(/time).
long completeRows(const std::string& path) {
  const Dataset steps = readDataset(path, "/steps");
  if (steps.ok && steps.values.size() == 1) return std::lround(steps.values[0]);
  const Dataset time = readDataset(path, "/time");
  return time.ok ? time.rows() : -1;
}

json configOf(const std::string& path) {
  try {
    const h5::File file = h5::File::openRead(path);
    return json::parse(file.readStringAttribute("/", "config"));
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": root attribute 'config' is not readable JSON: " << e.what();
    return json();
  }
}

std::string statusOf(const std::string& path) {
  try {
    return TrajectoryWriter::readStatus(path);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
    return "<unreadable>";
  }
}

// ---- running ------------------------------------------------------------------------------------

// `nmdp simulate ARGS...` must complete: exit 0, status "complete". Returns the output path.
CliResult runComplete(const std::vector<std::string>& args, const TempDir& dir, const std::string& out) {
  std::vector<std::string> full = {"simulate"};
  full.insert(full.end(), args.begin(), args.end());
  full.insert(full.end(), {"--out", out});
  SCOPED_TRACE(commandLine(full));
  const CliResult r = runNmdp(full, dir);
  EXPECT_TRUE(r.exited) << "nmdp was killed by a signal";
  EXPECT_EQ(r.exit_code, 0) << "stderr: " << r.err;
  EXPECT_TRUE(fs::exists(out)) << out << " was not written; stderr: " << r.err;
  if (fs::exists(out)) {
    EXPECT_EQ(statusOf(out), "complete") << "stderr: " << r.err;
  }
  return r;
}

// The contract for bad input: exit code 1, nothing on stdout, one stderr line
// "nmdp simulate: error: ..." containing every string of `expect`, and no output file.
void expectSimulateError(std::vector<std::string> args, const TempDir& dir, const std::vector<std::string>& expect) {
  const std::string out = dir.file("bad_input_output.h5");
  // --out first, so that a trailing "--set" without a value stays the last argument.
  args.insert(args.begin(), {"simulate", "--out", out});
  SCOPED_TRACE(commandLine(args));
  const CliResult r = runNmdp(args, dir);
  ASSERT_TRUE(r.exited) << "nmdp was killed by a signal";
  EXPECT_EQ(r.exit_code, 1) << "stderr: " << r.err;
  EXPECT_TRUE(r.out.empty()) << "nothing on stdout for bad input, got:\n" << r.out;
  EXPECT_FALSE(fs::exists(out)) << "bad input created the output file";
  for (const auto& entry : fs::directory_iterator(dir.path()))  // nor a temporary one
    EXPECT_NE(entry.path().filename().string().rfind("bad_input_output.h5", 0), 0u) << entry.path();
  fs::remove(out);
  ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
  EXPECT_EQ(r.err.rfind("nmdp simulate: error: ", 0), 0u) << r.err;
  for (const std::string& s : expect) EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
}

double maxAbsDifference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return INFINITY;
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

bool allFinite(const std::vector<double>& v, size_t count) {
  for (size_t i = 0; i < std::min(count, v.size()); ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

// The numeric datasets of DESIGN.md 11 and their shapes after the row dimension (-1: any size).
const std::vector<std::pair<std::string, std::vector<long>>> kNumericDatasets = {
    {"/time", {}},
    {"/q", {-1}},
    {"/qdot", {-1}},
    {"/base/position", {3}},
    {"/base/rpy", {3}},
    {"/contacts/wrench", {-1, 6}},
    {"/stats/outer_iterations", {}},
    {"/stats/g_evaluations", {}},
    {"/stats/substeps", {}},
    {"/stats/min_substep", {}},
    {"/stats/wall_time", {}},
    {"/stats/converged", {}},
    {"/stats/error_estimate", {}},
};

// ---- 1. every example scene completes -----------------------------------------------------------

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

// The quadruped's jump scenes at dt = 1 ms: one cycle
// (2 s) leaves the ground, stays upright and lands on four loaded feet. With the scenes' earlier
// timing (period 1 s, a 90 ms push-off) the robot rose 0.5 m and flipped over in the air at 1 ms.
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

// ---- 1b. the default demo: the quadruped trots forward on the project's RFT-fitted sand ----------

// The whole 10 s of models/scenes/quadruped_trot_sand.json (scripts/demo.sh runs it): the trot must
// carry the robot forward at a steady pace without falling. Measured on the scene as shipped
// (data/granular/README.md): 1.79 m in 10 s, every 2 s window 0.33-0.36 m, torso 0.77-1.0 of the
// standing height. With the first hand-made model and the default steps the robot drifted backward
// (-0.23 m in 10 s, every 2 s window negative), which fails both forward checks below.
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

// ---- 2. output layout ---------------------------------------------------------------------------

TEST(SimulateCli, OutputLayoutIsDesign11AndTheFirstRowIsTheInitialState) {
  TempDir dir;
  const std::string out = dir.file("layout.h5");
  runComplete({trotScene(), "--set", "duration=0.5", "--quiet"}, dir, out);
  ASSERT_TRUE(fs::exists(out));

  // Exactly the documented datasets, plus /status (and /steps, the complete-row count, if present).
  std::set<std::string> expected_names = {"/joint_names", "/contacts/names", "/status"};
  for (const auto& [name, shape] : kNumericDatasets) expected_names.insert(name);
  std::set<std::string> names = datasetNames(out);
  names.erase("/steps");
  EXPECT_EQ(names, expected_names);

  constexpr double dt = 0.05, duration = 0.5;
  const long N = std::lround(duration / dt) + 1;  // the initial row and one per step
  EXPECT_EQ(completeRows(out), N);

  const h5::File file = h5::File::openRead(out);
  const std::vector<std::string> joint_names = file.readStrings("/joint_names");
  const std::vector<std::string> contact_names = file.readStrings("/contacts/names");
  const long n = static_cast<long>(joint_names.size()), C = static_cast<long>(contact_names.size());
  EXPECT_EQ(n, 18) << "floating quadruped: 6 base + 12 joint coordinates";
  EXPECT_EQ(C, 4) << "auto contacts on a quadruped: one per foot";
  for (const std::string& c : contact_names) EXPECT_FALSE(c.empty());

  std::map<std::string, Dataset> data;
  for (const auto& [name, shape] : kNumericDatasets) {
    SCOPED_TRACE(name);
    const Dataset d = readDataset(out, name);
    ASSERT_TRUE(d.ok) << name << " missing or unreadable";
    std::vector<hsize_t> want = {static_cast<hsize_t>(N)};
    for (long s : shape) want.push_back(static_cast<hsize_t>(s == -1 ? (name == "/contacts/wrench" ? C : n) : s));
    EXPECT_EQ(d.dims, want) << name << " has the wrong shape";
    EXPECT_TRUE(allFinite(d.values, d.values.size())) << name;
    data[name] = d;
  }
  EXPECT_EQ(data["/time"].type_class, H5T_FLOAT);
  EXPECT_EQ(data["/q"].type_class, H5T_FLOAT);
  EXPECT_EQ(data["/stats/converged"].type_class, H5T_INTEGER);
  EXPECT_EQ(data["/stats/outer_iterations"].type_class, H5T_INTEGER);
  if (::testing::Test::HasFatalFailure() || data["/q"].values.size() != static_cast<size_t>(N * n)) return;

  // Time: 0, dt, ..., duration.
  for (long i = 0; i < N; ++i) EXPECT_NEAR(data["/time"].values[i], i * dt, 1e-9) << "row " << i;
  for (long i = 0; i < N; ++i) EXPECT_EQ(data["/stats/converged"].values[i], 1.0) << "row " << i;

  // The resolved config: JSON with absolute paths, the method, dt and the override.
  const json config = configOf(out);
  ASSERT_TRUE(config.is_object()) << config.dump();
  ASSERT_TRUE(config.contains("robot") && config["robot"].contains("urdf")) << config.dump(2);
  const std::string urdf = config["robot"]["urdf"].get<std::string>();
  EXPECT_TRUE(fs::path(urdf).is_absolute()) << urdf;
  EXPECT_TRUE(fs::exists(urdf) && fs::equivalent(urdf, quadrupedUrdf())) << urdf;
  EXPECT_EQ(config["integrator"]["method"], "ne-pgm");
  EXPECT_EQ(config["integrator"]["dt"], dt);
  EXPECT_EQ(config["duration"], duration) << "the --set override is recorded";
  EXPECT_EQ(config["controller"]["gait"]["type"], "trot");

  // The first row is the initial state of the resolved config: joint pose, height, at rest.
  const json& initial = config["robot"]["initial"];
  ASSERT_TRUE(initial.contains("joints") && initial.contains("height")) << config.dump(2);
  for (long j = 0; j < n; ++j) {
    const std::string& name = joint_names[j];
    if (initial["joints"].contains(name)) {
      EXPECT_NEAR(data["/q"].values[j], initial["joints"][name].get<double>(), 1e-12) << name;
    }
    EXPECT_EQ(data["/qdot"].values[j], 0.0) << name << ": the run starts at rest";
  }
  EXPECT_NEAR(data["/q"].values[2], initial["height"].get<double>(), 1e-12) << "q[2] is the base height";
  EXPECT_EQ(data["/stats/outer_iterations"].values[0], 0.0) << "row 0 is the initial state, not a step";

  // q's base translation is /base/position (floating base: x, y, z are q[0..2]) on every row.
  for (long i = 0; i < N; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(data["/q"].values[i * n + k], data["/base/position"].values[i * 3 + k], 1e-12)
          << "row " << i << " axis " << k;
  // The robot stands on the ground at the start and stays up while trotting.
  EXPECT_GT(data["/base/position"].values[(N - 1) * 3 + 2], 0.5 * initial["height"].get<double>());
}

// ---- 3. swapping the method or the contact model ------------------------------------------------

struct RunResult {
  std::vector<double> q;
  json config;
};
RunResult runVariant(const std::vector<std::string>& sets, const TempDir& dir, const std::string& name) {
  std::vector<std::string> args = {trotScene(), "--set", "duration=0.5", "--quiet"};
  for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
  const std::string out = dir.file(name + ".h5");
  runComplete(args, dir, out);
  RunResult r;
  if (!fs::exists(out)) return r;
  r.q = readDataset(out, "/q").values;
  r.config = configOf(out);
  return r;
}

// The configs are equal once the keys at `paths` (json pointers) are removed. /output/file differs
// by construction (each variant is written to its own --out file, and the config records it).
void expectSameConfigBut(json a, json b, std::vector<std::string> pointers) {
  pointers.push_back("/output/file");
  for (const std::string& p : pointers) {
    const json::json_pointer ptr(p);
    const json::json_pointer parent = ptr.parent_pointer();
    if (a.contains(ptr)) a[parent].erase(ptr.back());
    if (b.contains(ptr)) b[parent].erase(ptr.back());
  }
  EXPECT_EQ(a, b) << "the configs differ in more than the override:\n" << json::diff(a, b).dump(2);
}

TEST(SimulateCli, SwappingTheMethodIsOneSetOnly) {
  TempDir dir;
  const RunResult base = runVariant({}, dir, "default");
  const RunResult pbd = runVariant({"integrator.method=pbd-pgm"}, dir, "pbd");
  ASSERT_FALSE(base.q.empty());
  ASSERT_FALSE(pbd.q.empty());
  ASSERT_EQ(base.q.size(), pbd.q.size());
  EXPECT_GT(maxAbsDifference(base.q, pbd.q), 1e-9) << "ne-pgm and pbd-pgm gave the same /q";
  EXPECT_EQ(base.config["integrator"]["method"], "ne-pgm");
  EXPECT_EQ(pbd.config["integrator"]["method"], "pbd-pgm");
  expectSameConfigBut(base.config, pbd.config, {"/integrator/method"});
}

TEST(SimulateCli, SwappingTheContactModelIsOneSetOnly) {
  TempDir dir;
  const RunResult base = runVariant({}, dir, "default");
  const RunResult mu = runVariant({"contacts.model.mu=0.3"}, dir, "mu");
  const std::string sand = sourcePath("data/granular/handmade_sand_rbf.h5");
  const RunResult rbf = runVariant({"contacts.model.type=rbf", "contacts.model.file=" + sand}, dir, "rbf");
  ASSERT_FALSE(base.q.empty());
  ASSERT_FALSE(mu.q.empty());
  ASSERT_FALSE(rbf.q.empty());
  ASSERT_EQ(base.q.size(), mu.q.size());
  ASSERT_EQ(base.q.size(), rbf.q.size());
  EXPECT_GT(maxAbsDifference(base.q, mu.q), 1e-9) << "mu = 0.3 gave the same /q as the default Coulomb model";
  EXPECT_GT(maxAbsDifference(base.q, rbf.q), 1e-9) << "the sand RBF gave the same /q as Coulomb";
  EXPECT_EQ(mu.config["contacts"]["model"]["mu"], 0.3) << mu.config["contacts"].dump();
  EXPECT_EQ(rbf.config["contacts"]["model"]["type"], "rbf") << rbf.config["contacts"].dump();
  EXPECT_TRUE(rbf.config["contacts"]["model"].contains("file") &&
              fs::equivalent(rbf.config["contacts"]["model"]["file"].get<std::string>(), sand))
      << rbf.config["contacts"].dump();
  expectSameConfigBut(base.config, mu.config, {"/contacts/model"});
  expectSameConfigBut(base.config, rbf.config, {"/contacts/model"});
}

// The stored config's contacts.model lists every parameter of the model with the value used (the
// defaults too), and the stored config, run as a scene, repeats the run bit for bit.
TEST(SimulateCli, ConfigHasTheContactModelDefaultsAndRerunsTheSameRun) {
  TempDir dir;
  const CoulombParameters defaults;
  const std::string sand = sourcePath("data/granular/handmade_sand_rbf.h5");
  struct Variant {
    std::string name;
    std::vector<std::string> sets;
  };
  for (const Variant& v : {Variant{"coulomb", {}}, Variant{"rbf", {"contacts.model.type=rbf", "contacts.model.file=" + sand}}}) {
    SCOPED_TRACE(v.name);
    const RunResult first = runVariant(v.sets, dir, v.name);
    ASSERT_FALSE(first.q.empty());
    const json& model = first.config["contacts"]["model"];
    if (v.name == "coulomb") {
      EXPECT_EQ(model, json({{"type", "coulomb"}, {"mu", defaults.mu}, {"K", defaults.K}, {"k", defaults.k},
                             {"p", defaults.p}, {"zeta", defaults.zeta}}));
    } else {
      EXPECT_EQ(model["format"], "hdf5") << model.dump();
      for (const char* key : {"file", "torque_centre", "cutoff", "cutoff_width"}) EXPECT_TRUE(model.contains(key)) << key;
    }
    const std::string scene = dir.write(v.name + "_resolved.json", first.config.dump(2));
    const std::string again_out = dir.file(v.name + "_again.h5");
    runComplete({scene, "--quiet"}, dir, again_out);
    ASSERT_TRUE(fs::exists(again_out));
    for (const char* name : {"/q", "/qdot", "/contacts/wrench"}) {
      const Dataset a = readDataset(dir.file(v.name + ".h5"), name), b = readDataset(again_out, name);
      ASSERT_TRUE(a.ok && b.ok) << name;
      ASSERT_EQ(a.dims, b.dims) << name;
      EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(double)), 0)
          << name << " differs when the stored config is run again (max |diff| " << maxAbsDifference(a.values, b.values) << ")";
    }
    expectSameConfigBut(first.config, configOf(again_out), {});
  }
}

// ---- 4. bad input -------------------------------------------------------------------------------

// A minimal scene in `dir` around the project's quadruped, with `extra` merged in.
std::string writeScene(const TempDir& dir, const std::string& name, const json& extra = json::object()) {
  json scene = {{"robot", {{"urdf", quadrupedUrdf()}}}, {"duration", 0.5}};
  scene.merge_patch(extra);
  return dir.write(name, scene.dump(2));
}

TEST(SimulateCli, MissingSceneFile) {
  TempDir dir;
  const std::string missing = dir.file("no_such_scene.json");
  expectSimulateError({missing}, dir, {missing, "no such file"});
}

TEST(SimulateCli, MalformedJson) {
  TempDir dir;
  const std::string scene = dir.write("broken.json", "{\n  \"robot\": {\"urdf\": \"q.urdf\"},\n  \"duration\": ,\n}\n");
  expectSimulateError({scene}, dir, {scene + ":3:", "invalid JSON"});
}

TEST(SimulateCli, UnknownKeySuggestsTheClosest) {
  TempDir dir;
  const std::string scene = writeScene(dir, "typo.json", {{"integrator", {{"metod", "ne-pgm"}}}});
  expectSimulateError({scene}, dir, {scene, "integrator.metod", "unknown key", "did you mean 'method'"});
  const std::string top = writeScene(dir, "typo_top.json", {{"duraton", 1.0}});
  expectSimulateError({top}, dir, {top, "duraton", "did you mean 'duration'"});
}

TEST(SimulateCli, WrongType) {
  TempDir dir;
  const std::string scene = writeScene(dir, "type.json", {{"duration", "long"}});
  expectSimulateError({scene}, dir, {scene, "duration", "expected a number", "\"long\""});
  const std::string adaptive = writeScene(dir, "type2.json", {{"integrator", {{"adaptive", "yes"}}}});
  expectSimulateError({adaptive}, dir, {"integrator.adaptive", "expected true or false"});
}

TEST(SimulateCli, OutOfRangeDt) {
  TempDir dir;
  const std::string scene = writeScene(dir, "dt.json");
  expectSimulateError({scene, "--set", "integrator.dt=0"}, dir, {"integrator.dt", "0"});
  expectSimulateError({scene, "--set", "integrator.dt=-0.01"}, dir, {"integrator.dt", "-0.01"});
  expectSimulateError({scene, "--set", "integrator.dt=2"}, dir, {"integrator.dt", "2"});
  expectSimulateError({scene, "--set", "duration=0"}, dir, {"duration"});
}

TEST(SimulateCli, UnknownMethod) {
  TempDir dir;
  const std::string scene = writeScene(dir, "method.json");
  expectSimulateError({scene, "--set", "integrator.method=ne-pgmm"}, dir,
                      {"integrator.method", "unknown method 'ne-pgmm'", "did you mean 'ne-pgm'", "pbd-zopgm"});
}

TEST(SimulateCli, MissingUrdf) {
  TempDir dir;
  const std::string scene = dir.write("nourdf.json", json({{"robot", {{"urdf", "robots/missing.urdf"}}}}).dump());
  expectSimulateError({scene}, dir, {scene, "robot.urdf", "file not found", dir.file("robots/missing.urdf")});
}

// The RoboSimian scenes refer to ../shared/robots from models/scenes; copied where no ../shared
// exists, they say which file and which absent folder.
TEST(SimulateCli, RoboSimianScenesSayWhenSharedIsAbsent) {
  TempDir dir;
  for (const char* name : {"robosimian_walk_planar.json", "robosimian_jump_planar.json"}) {
    const std::string scene = dir.write(std::string("project/models/scenes/") + name, readText(sceneFile(name)));
    expectSimulateError({scene}, dir,
                        {scene, "robot.urdf", "file not found",
                         dir.file("shared/robots/robosimian/robosimian_caesar_new_all_active.urdf"),
                         "(the folder " + dir.file("shared") + " does not exist)"});
  }
}

TEST(SimulateCli, ContactLinkThatDoesNotExist) {
  TempDir dir;
  const std::string scene =
      writeScene(dir, "link.json", {{"contacts", {{"points", json::array({{{"link", "FL_fot"}, {"radius", 0.02}}})}}}});
  expectSimulateError({scene}, dir, {scene, "contacts.points", "FL_fot", "did you mean 'FL_foot'"});
}

TEST(SimulateCli, UnknownJointInGains) {
  TempDir dir;
  const std::string scene = writeScene(dir, "kp.json", {{"controller", {{"kp", {{"FL_hip_jont", 30.0}}}}}});
  expectSimulateError({scene}, dir, {scene, "controller.kp", "FL_hip_jont", "did you mean 'FL_hip_joint'"});
}

TEST(SimulateCli, MalformedSet) {
  TempDir dir;
  const std::string scene = writeScene(dir, "set.json");
  expectSimulateError({scene, "--set", "integrator.dt"}, dir, {"--set", "key.path=value"});
  expectSimulateError({scene, "--set", "=0.01"}, dir, {"--set", "empty key"});
  expectSimulateError({scene, "--set", "integrator..dt=0.01"}, dir, {"--set", "empty key"});
  expectSimulateError({scene, "--set", "duration.x=1"}, dir, {"--set", "'duration'", "not an object"});
  expectSimulateError({scene, "--set"}, dir, {"--set needs a value"});
}

TEST(SimulateCli, UnknownCommandLineOption) {
  TempDir dir;
  const std::string scene = writeScene(dir, "opt.json");
  expectSimulateError({scene, "--frobnicate"}, dir, {"unknown option '--frobnicate'"});
  expectSimulateError({scene, scene}, dir, {"one scene file expected"});
  expectSimulateError({}, dir, {"scene file is required"});
}

// ---- 5. determinism -----------------------------------------------------------------------------

TEST(SimulateCli, SameRunTwiceIsBitIdentical) {
  TempDir dir;
  const std::vector<std::string> args = {trotScene(), "--set", "duration=0.5", "--quiet"};
  runComplete(args, dir, dir.file("a.h5"));
  runComplete(args, dir, dir.file("b.h5"));
  for (const char* name : {"/time", "/q", "/qdot", "/contacts/wrench"}) {
    const Dataset a = readDataset(dir.file("a.h5"), name), b = readDataset(dir.file("b.h5"), name);
    ASSERT_TRUE(a.ok && b.ok) << name;
    ASSERT_EQ(a.dims, b.dims) << name;
    EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(double)), 0)
        << name << " differs between two identical runs (max |diff| " << maxAbsDifference(a.values, b.values) << ")";
  }
}

// Starts args[0] with args in a child process, stdin and stdout on /dev/null and stderr into
// `stderr_path`; returns its pid (negative if fork failed).
pid_t spawn(const std::vector<std::string>& args, const std::string& stderr_path) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int null = ::open("/dev/null", O_RDWR);
  const int e = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(null, 0);
  ::dup2(null, 1);
  ::dup2(e, 2);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  ::execv(argv[0], argv.data());
  ::_exit(127);
}

// ---- 6. SIGKILL half-way ------------------------------------------------------------------------

TEST(SimulateCli, RunKilledHalfWayLeavesAReadableFile) {
  TempDir dir;
  const std::string out = dir.file("killed.h5");
  const std::string err = dir.file("killed_stderr.txt");
  const std::vector<std::string> args = {NMDP_BINARY, "simulate", trotScene(), "--set", "duration=1000",
                                         "--set", "integrator.dt=0.05", "--out", out, "--quiet"};
  const pid_t pid = spawn(args, err);
  ASSERT_GE(pid, 0);
  // The file appears (renamed from its temporary name) once every dataset exists; the writer then commits
  // every step (flush_every = 1). Wait for the file, then long enough for some steps.
  const auto start = std::chrono::steady_clock::now();
  bool appeared = false, exited_early = false;
  int status = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited_early = true;
      break;
    }
    if (fs::exists(out)) {
      appeared = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (appeared) std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  if (!exited_early) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited_early = true;
    } else {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
    }
  }
  ASSERT_FALSE(exited_early) << "nmdp simulate ended before the kill (exit "
                             << (WIFEXITED(status) ? WEXITSTATUS(status) : -1) << "): " << readText(err);
  ASSERT_TRUE(appeared) << "the output file did not appear within 20 s; stderr: " << readText(err);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);

  // The killed file opens, says "running" and holds complete, finite rows.
  EXPECT_EQ(statusOf(out), "running");
  const long rows = completeRows(out);
  EXPECT_GE(rows, 1) << "no complete row survived 2.5 s of running";
  if (rows < 1) return;
  std::cout << "killed after " << rows << " complete rows (" << (fs::exists(out) ? fs::file_size(out) : 0) << " bytes)\n";
  const Dataset time = readDataset(out, "/time");
  ASSERT_TRUE(time.ok);
  ASSERT_GE(time.rows(), rows);
  for (long i = 0; i < rows; ++i) EXPECT_NEAR(time.values[i], 0.05 * i, 1e-9) << "row " << i;
  for (const auto& [name, shape] : kNumericDatasets) {
    const Dataset d = readDataset(out, name);
    ASSERT_TRUE(d.ok) << name << " is unreadable in the killed file";
    ASSERT_GE(d.rows(), rows) << name << " is shorter than the complete-row count";
    EXPECT_TRUE(allFinite(d.values, static_cast<size_t>(rows) * d.rowSize())) << name << " has a non-finite complete row";
  }
  const Dataset conv = readDataset(out, "/stats/converged");
  for (long i = 0; i < rows; ++i) EXPECT_EQ(conv.values[i], 1.0) << "row " << i;
  EXPECT_TRUE(configOf(out).is_object());
}

// The resolved config records the file the run was written to (--out), not the scene's default.
TEST(SimulateCli, ConfigRecordsTheOutputFileOfOut) {
  TempDir dir;
  const std::string out = dir.file("elsewhere.h5");
  runComplete({trotScene(), "--set", "duration=0.1", "--quiet"}, dir, out);
  ASSERT_TRUE(fs::exists(out));
  const json config = configOf(out);
  ASSERT_TRUE(config.contains("output") && config["output"].contains("file")) << config.dump(2);
  EXPECT_EQ(config["output"]["file"], out) << "config.output.file does not name the written file";
}

// ---- 7. --quiet ---------------------------------------------------------------------------------

TEST(SimulateCli, QuietPrintsNothingAndOtherwiseOneSummaryLine) {
  TempDir dir;
  const std::string quiet_out = dir.file("quiet.h5");
  const CliResult quiet = runComplete({trotScene(), "--set", "duration=0.5", "--quiet"}, dir, quiet_out);
  EXPECT_TRUE(quiet.out.empty()) << "--quiet printed on stdout:\n" << quiet.out;
  EXPECT_TRUE(quiet.err.empty()) << "--quiet printed on stderr:\n" << quiet.err;

  const std::string loud_out = dir.file("loud.h5");
  const CliResult loud = runComplete({trotScene(), "--set", "duration=0.5"}, dir, loud_out);
  ASSERT_NO_FATAL_FAILURE(expectOneLine(loud.out, "stdout"));
  EXPECT_NE(loud.out.find(loud_out), std::string::npos) << loud.out;
  EXPECT_NE(loud.out.find("10 steps"), std::string::npos) << loud.out;
  EXPECT_NE(loud.out.find("ne-pgm"), std::string::npos) << loud.out;
  EXPECT_TRUE(loud.err.empty()) << "no progress bar when stderr is not a terminal:\n" << loud.err;
}

}  // namespace
}  // namespace nmdp::test
