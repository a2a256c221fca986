// What `nmdp simulate` writes (DESIGN.md 11): the documented layout, whose first row is the
// initial state; swapping the method or the contact model with --set is a configuration change
// only, and the stored config reruns the same run; runs are deterministic; a run killed with
// SIGKILL leaves a readable file (SWMR reading); --quiet. How a run ends early:
// test_simulate_ending.cpp.
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "child_process.hpp"
#include "contact_models/coulomb_model.hpp"
#include "io/hdf5_file.hpp"
#include "run_files.hpp"
#include "simulate_run.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// ---- output layout ------------------------------------------------------------------------------

TEST(SimulateCli, OutputLayoutIsDesign11AndTheFirstRowIsTheInitialState) {
  TempDir dir;
  const std::string out = dir.file("layout.h5");
  runComplete({trotScene(), "--set", "duration=0.5", "--quiet"}, dir, out);
  ASSERT_TRUE(fs::exists(out));

  // Exactly the documented datasets.
  std::set<std::string> expected_names = {"/joint_names", "/contacts/names", "/links/names", "/status", "/rows",
                                          "/steps", "/joints/q_target", "/joints/qdot_target", "/model/urdf",
                                          "/model/urdf_path", "/model/mesh_files", "/model/mesh_paths",
                                          "/terrain/description"};
  for (const auto& [name, shape] : kNumericDatasets) expected_names.insert(name);
  std::set<std::string> names = datasetNames(out);
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
    const long L = static_cast<long>(file.readStrings("/links/names").size());
    for (long s : shape) want.push_back(static_cast<hsize_t>(s == kN ? n : s == kC ? C : s == kL ? L : s == kF ? 1 : s));
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

// ---- swapping the method or the contact model ---------------------------------------------------

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

// The file records which nmdp wrote it, as `nmdp --version` prints it, and every dataset its units
// and a description.
TEST(SimulateCli, OutputRecordsTheVersionAndDescribesEveryDataset) {
  TempDir dir;
  const std::string out = dir.file("version.h5");
  runComplete({trotScene(), "--set", "duration=0.1", "--quiet"}, dir, out);
  const CliResult version = runNmdp({"--version"}, dir);
  ASSERT_EQ(version.exit_code, 0);
  const h5::File file = h5::File::openRead(out);
  const std::string v = file.readStringAttribute("/", "nmdp_version"), commit = file.readStringAttribute("/", "nmdp_commit");
  EXPECT_EQ(version.out, "nmdp " + v + " (commit " + commit + ")\n");
  for (const std::string& name : datasetNames(out)) {
    EXPECT_TRUE(file.hasAttribute(name, "units") && !file.readStringAttribute(name, "units").empty()) << name;
    EXPECT_TRUE(file.hasAttribute(name, "description") && !file.readStringAttribute(name, "description").empty()) << name;
  }
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

// ---- determinism --------------------------------------------------------------------------------

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

pid_t spawn(const std::vector<std::string>& args, const std::string& stderr_path) { return startProcess(args, stderr_path); }

// ---- SIGKILL half-way ---------------------------------------------------------------------------

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

// ---- --quiet ------------------------------------------------------------------------------------

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
