// `nmdp simulate` on bad input (DESIGN.md 11): a missing or malformed scene, unknown keys, wrong
// types, out-of-range values, missing files and bad command-line options each give one line on
// stderr naming the file and the key, exit code 1 and no output file.
#include <nlohmann/json.hpp>

#include "command_line.hpp"
#include "simulate_run.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

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

}  // namespace
}  // namespace nmdp::test
