// A run file that lacks something still gives a page that opens and says what is missing: no URDF
// (the trunk as a box), a run killed by SIGKILL (its committed rows, "cut short"), a robot whose
// meshes are absent (Solo-12: collision shapes or inertia boxes, each named), and a robot whose
// meshes are present (RoboSimian: the STL bytes inlined as they are on disk).
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "child_process.hpp"
#include "run_file_edits.hpp"
#include "run_files.hpp"
#include "simulate_run.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"
#include "view_page.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

json viewPayload(const std::vector<std::string>& runs, const TempDir& dir, const std::string& page, CliResult* result = nullptr) {
  std::vector<std::string> args = runs;
  args.insert(args.end(), {"--out", page});
  const CliResult r = runView(args, dir);
  if (result) *result = r;
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return json();
  return payloadOf(readText(page));
}

TEST(ViewFallbacks, RunWithoutItsUrdfDrawsTheTrunkAsABoxAndSaysSo) {
  TempDir dir;
  useStandInBundle(dir);
  const std::string run = dir.file("no_urdf.h5");
  runComplete({trotScene(), "--set", "duration=0.2", "--quiet"}, dir, run);
  {
    EditedRun edit(run);
    edit.remove("/model/urdf");
    json config = configOf(run);
    config["robot"]["urdf"] = dir.file("gone/a1.urdf");
    edit.setRootString("config", config.dump());
  }
  CliResult r;
  const json p = viewPayload({run}, dir, dir.file("no_urdf.html"), &r);
  ASSERT_TRUE(p.is_object());
  const json& R = p["runs"][0];
  EXPECT_TRUE(hasWarning(R["warnings"], {"no_urdf.h5 has no /model/urdf", dir.file("gone/a1.urdf") + " is not found", "box"})) << R["warnings"];
  EXPECT_NE(r.err.find("nmdp view: warning: no_urdf.h5 has no /model/urdf"), std::string::npos) << r.err;
  ASSERT_EQ(R["links"].size(), 1u);
  const json& box = R["links"][0]["visuals"][0];
  EXPECT_EQ(box["type"], "box");
  EXPECT_EQ(box["size"], json({0.3, 0.2, 0.1}));
  const PayloadArray poses = decodeArray(R["link_poses"]);
  const PayloadArray base = decodeArray(R["base"]["position"]);
  ASSERT_EQ(poses.shape[0], static_cast<size_t>(R["frames"].get<long>()));
  for (size_t i = 0; i < poses.shape[0]; ++i)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(poses.values[7 * i + a], base.values[3 * i + a]) << "the box is at /base";

  // --quiet: the warnings stay on the page only.
  const CliResult quiet = runView({run, "--out", dir.file("no_urdf.html"), "--quiet"}, dir);
  EXPECT_EQ(quiet.exit_code, 0);
  EXPECT_EQ(quiet.out + quiet.err, "");
}

TEST(ViewFallbacks, RunKilledBySigkillShowsItsCommittedRowsAndSaysItWasCutShort) {
  TempDir dir;
  useStandInBundle(dir);
  const std::string run = dir.file("killed.h5");
  const pid_t pid = startProcess({NMDP_BINARY, "simulate", trotScene(), "--set", "duration=1000", "--set", "integrator.dt=0.05",
                                  "--out", run, "--quiet"},
                                 dir.file("killed_stderr.txt"));
  ASSERT_GE(pid, 0);
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  bool exited = false;
  while (!fs::exists(run) && std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!exited) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  ASSERT_FALSE(exited) << "nmdp simulate ended before the kill: " << readText(dir.file("killed_stderr.txt"));
  ASSERT_TRUE(fs::exists(run)) << "the run file did not appear within 20 s";
  ASSERT_EQ(statusOf(run), "running");
  const long rows = completeRows(run);
  ASSERT_GE(rows, 1) << "no row was committed in 1.5 s";

  const json p = viewPayload({run}, dir, dir.file("killed.html"));
  ASSERT_TRUE(p.is_object());
  const json& R = p["runs"][0];
  EXPECT_EQ(R["status"], "running");
  EXPECT_EQ(R["frames"], rows);
  EXPECT_EQ(decodeArray(R["time"]).values.size(), static_cast<size_t>(rows));
  EXPECT_TRUE(hasWarning(R["warnings"], {"killed.h5 was cut short (status 'running'): " + std::to_string(rows) + " committed rows of 20001 scheduled"}))
      << R["warnings"];
}

// Solo-12's URDF names its meshes package://example-robot-data/...: in place they are found (and
// inlined); a copy of the URDF alone finds none, so each link falls back, the mesh named.
TEST(ViewFallbacks, Solo12WithoutItsMeshesIsDrawnFromItsOtherShapes) {
  const std::string scene = sourcePath("models/scenes/evaluation/solo12_trot_flat.json");
  const std::string urdf = sharedPath("robots/solo12/urdf/solo12.urdf");
  if (!fs::exists(urdf)) GTEST_SKIP() << "../shared/robots/solo12 is absent";
  TempDir dir;
  useStandInBundle(dir);
  const std::string lone_urdf = dir.file("solo12.urdf");
  fs::copy_file(urdf, lone_urdf);
  const std::string run = dir.file("solo.h5");
  runComplete({scene, "--set", "robot.urdf=" + lone_urdf, "--set", "duration=0.1", "--quiet"}, dir, run);
  const json p = viewPayload({run}, dir, dir.file("solo.html"));
  ASSERT_TRUE(p.is_object());
  const json& R = p["runs"][0];
  // The trunk's mesh (visual and collision) is named, the link drawn as its inertia box.
  EXPECT_TRUE(hasWarning(R["warnings"], {"mesh package://example-robot-data/robots/solo_description/meshes/stl/solo12/solo_12_base.stl is not found",
                                         "link base_link is drawn as the box of its mass and inertia"}))
      << R["warnings"];
  int meshes = 0, boxes = 0;
  for (const json& link : R["links"])
    for (const json& v : link["visuals"]) {
      meshes += v["type"] == "mesh";
      if (v["source"] == "inertia") {
        ++boxes;
        EXPECT_EQ(v["type"], "box");
        for (int k = 0; k < 3; ++k) EXPECT_GT(v["size"][k].get<double>(), 0.0);
      }
    }
  EXPECT_EQ(meshes, 0) << "no mesh of the lone URDF can be found";
  EXPECT_GT(boxes, 0);

  // In place, the same robot's meshes that exist are inlined.
  const std::string in_place = dir.file("solo_in_place.h5");
  runComplete({scene, "--set", "duration=0.1", "--quiet"}, dir, in_place);
  const json q = viewPayload({in_place}, dir, dir.file("solo_in_place.html"));
  ASSERT_TRUE(q.is_object());
  const std::string base_mesh = sharedPath("robots/solo12/urdf/meshes/stl/solo12/solo_12_base.stl");
  if (!fs::exists(base_mesh)) return;
  json trunk;
  for (const json& link : q["runs"][0]["links"])
    if (link["name"] == "base_link") trunk = link;
  ASSERT_TRUE(trunk.is_object()) << "no link base_link";
  ASSERT_FALSE(trunk["visuals"].empty());
  EXPECT_EQ(trunk["visuals"][0]["type"], "mesh");
  EXPECT_EQ(decodeArray(trunk["visuals"][0]["data"]).values.size(), fs::file_size(base_mesh));
}

TEST(ViewFallbacks, RoboSimianStlMeshesAreInlinedAsTheyAreOnDisk) {
  const std::string scene = sceneFile("robosimian_walk_planar.json");
  if (!fs::exists(sharedPath("robots/robosimian"))) GTEST_SKIP() << "../shared/robots/robosimian is absent";
  TempDir dir;
  useStandInBundle(dir);
  const std::string run = dir.file("robosimian.h5");
  runComplete({scene, "--set", "duration=0.1", "--quiet"}, dir, run);
  const json p = viewPayload({run}, dir, dir.file("robosimian.html"));
  ASSERT_TRUE(p.is_object());
  const std::string chassis = readText(sharedPath("robots/robosimian/stl_0_3/robosim_chassis.stl"));
  ASSERT_FALSE(chassis.empty());
  int meshes = 0;
  bool chassis_found = false;
  for (const json& link : p["runs"][0]["links"])
    for (const json& v : link["visuals"]) {
      if (v["type"] != "mesh") continue;
      ++meshes;
      EXPECT_EQ(v["format"], "stl");
      EXPECT_EQ(v["source"], "visual");
      const PayloadArray bytes = decodeArray(v["data"]);
      if (bytes.values.size() == chassis.size()) {
        bool same = true;
        for (size_t k = 0; same && k < chassis.size(); ++k) same = bytes.values[k] == static_cast<unsigned char>(chassis[k]);
        chassis_found = chassis_found || same;
      }
    }
  EXPECT_GT(meshes, 0);
  EXPECT_TRUE(chassis_found) << "robosim_chassis.stl is not inlined byte for byte";
}

}  // namespace
}  // namespace nmdp::test
