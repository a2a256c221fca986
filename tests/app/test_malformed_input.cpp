// Malformed and absurd inputs through the CLI, as a user or a fuzzer hands them over: each gives one
// line on stderr naming the file and the field, exit status 1, within a time limit and (outside
// sanitizer builds, which reserve terabytes of address space) a memory limit. These are the cases
// that crashed, hung, exhausted memory or were accepted silently before the readers were bounded
// (a cycle or a 10 000-link chain in a URDF, JSON nested 10^5 deep, /dev/urandom as a URDF, a
// duration of 1e308, dt = 1e-300, 1e309 in --set, 10 000 contact points, a 100 000-character path,
// a model-file attribute of the wrong shape).
#include <gtest/gtest.h>

#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "multibody/urdf_loader.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

using json = nlohmann::json;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

// `nmdp ARGS` killed after `seconds` and, outside sanitizer builds, with 2 GiB of address space
// (libtorch and the robot need about 0.5).
CliResult runBounded(const std::vector<std::string>& args, const TempDir& dir, int seconds = 20) {
  const std::string limit = kSanitized ? "" : "ulimit -v 2097152; ";
  return runNmdp(args, dir, limit + "exec timeout -s KILL " + std::to_string(seconds));
}

// Exit status 1 (137 would be the timeout's SIGKILL), one line "nmdp <command>: error: ..." holding
// every fragment of `expect`.
void expectInputError(const std::vector<std::string>& args, const TempDir& dir, const std::vector<std::string>& expect) {
  const CliResult r = runBounded(args, dir);
  ASSERT_TRUE(r.exited) << "nmdp was killed by a signal; stderr: " << r.err.substr(0, 2000);
  EXPECT_EQ(r.exit_code, 1) << "(137: killed after 20 s or out of memory) stderr: " << r.err.substr(0, 2000);
  ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
  EXPECT_EQ(r.err.rfind("nmdp " + args[0] + ": error: ", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 2000u) << "a message a user can read";
  for (const std::string& e : expect) EXPECT_NE(r.err.find(e), std::string::npos) << "missing '" << e << "' in: " << r.err;
}

std::string linkXml(const std::string& name) {
  return "  <link name=\"" + name + "\"><inertial><mass value=\"1\"/>"
         "<inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n";
}
std::string jointXml(const std::string& name, const std::string& parent, const std::string& child) {
  return "  <joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><origin xyz=\"0 0 -0.1\"/><axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
}

// A serial chain of `links` links.
std::string chainUrdf(int links) {
  std::string xml = "<?xml version=\"1.0\"?>\n<robot name=\"chain\">\n";
  for (int i = 0; i < links; ++i) xml += linkXml("l" + std::to_string(i));
  for (int i = 1; i < links; ++i) xml += jointXml("j" + std::to_string(i), "l" + std::to_string(i - 1), "l" + std::to_string(i));
  return xml + "</robot>\n";
}

// A scene for the project's quadruped with the keys of `extra` merged in.
std::string sceneWith(const TempDir& dir, const json& extra = json::object()) {
  json scene = {{"robot", {{"urdf", sourcePath("models/quadruped/quadruped.urdf")}}}, {"duration", 0.1}};
  scene.merge_patch(extra);
  return dir.write("scene.json", scene.dump());
}

TEST(MalformedUrdf, JointsFormingACycleUnderTheRootAreRefused) {
  const TempDir dir;
  // base → a → b, and a joint b → a: link a has two parent joints.
  const std::string urdf = dir.write("cycle.urdf", "<?xml version=\"1.0\"?>\n<robot name=\"cycle\">\n" + linkXml("base") +
                                                        linkXml("a") + linkXml("b") + jointXml("j1", "base", "a") +
                                                        jointXml("j2", "a", "b") + jointXml("j3", "b", "a") + "</robot>\n");
  expectInputError({"inspect", urdf}, dir, {urdf, "link 'a' is the child of two joints", "j1", "j3"});
  // A cycle apart from the root is not reached from it: named as such.
  const std::string apart = dir.write("apart.urdf", "<?xml version=\"1.0\"?>\n<robot name=\"apart\">\n" + linkXml("base") +
                                                         linkXml("a") + linkXml("b") + jointXml("j1", "a", "b") +
                                                         jointXml("j2", "b", "a") + "</robot>\n");
  expectInputError({"inspect", apart}, dir, {apart, "the joints form a cycle", "'a' <- 'b'"});
}

TEST(MalformedUrdf, ChainsBeyondTheLinkLimitAreRefusedAndChainsWithinItLoad) {
  const TempDir dir;
  const std::string huge = dir.write("chain10000.urdf", chainUrdf(10000));
  expectInputError({"inspect", huge}, dir, {huge, "10000 links", "more than the 1000 links"});
  // The loader walks the tree with its own stack: a chain as long as the limit loads.
  const Model m = loadUrdf(dir.write("chain1000.urdf", chainUrdf(1000)), UrdfOptions{BaseType::Fixed});
  EXPECT_EQ(m.nq, 999);
  EXPECT_EQ(m.bodies.back().parent, 997);
}

TEST(MalformedUrdf, DeeplyNestedXmlIsRefusedBeforeParsing) {
  const TempDir dir;
  std::string xml = "<robot name=\"deep\">";
  for (int i = 0; i < 100000; ++i) xml += "<a>";
  for (int i = 0; i < 100000; ++i) xml += "</a>";
  const std::string urdf = dir.write("deep.urdf", xml + "</robot>\n");
  expectInputError({"inspect", urdf}, dir, {urdf + ":1:", "nested more than 64 levels deep"});
}

TEST(MalformedUrdf, DevicesAndFoldersAreRefusedBeforeReading) {
  const TempDir dir;
  for (const char* device : {"/dev/urandom", "/dev/zero"}) {
    expectInputError({"inspect", device}, dir, {device, "not a regular file"});
    const std::string scene = sceneWith(dir, {{"robot", {{"urdf", device}}}});
    expectInputError({"simulate", scene}, dir, {scene, "robot.urdf", device, "not a regular file"});
  }
  expectInputError({"simulate", sceneWith(dir, {{"robot", {{"urdf", dir.dir()}}}})}, dir, {"robot.urdf", "it is a folder"});
}

TEST(MalformedScene, KeyframeJsonNestedDeepIsRefused) {
  const TempDir dir;
  const int n = 100000;
  dir.write("deep.json", "{\"times\": [0, 1], \"joints\": {\"FL_knee_joint\": " + std::string(n, '[') + std::string(n, ']') + "}}");
  const std::string scene = sceneWith(dir, {{"controller", {{"gait", {{"type", "keyframes"}, {"file", "deep.json"}}}}}});
  expectInputError({"simulate", scene}, dir, {scene, "controller.gait.file", "deep.json:1:", "nested more than 64 levels deep"});
}

TEST(MalformedScene, DurationsWhoseStepsCannotBeCountedNameDurationAndDt) {
  const TempDir dir;
  const std::string scene = sceneWith(dir, {{"duration", 1e308}});
  expectInputError({"simulate", scene}, dir, {scene, "duration 1e+308 s at integrator.dt 0.05 s", "more than the 1e+15"});
  expectInputError({"simulate", sceneWith(dir), "--set", "duration=1e308"}, dir, {"duration", "integrator.dt"});
}

TEST(MalformedScene, AStepTooSmallToAdvanceTheClockIsRefused) {
  const TempDir dir;
  const std::string scene = sceneWith(dir);
  expectInputError({"simulate", scene, "--set", "integrator.dt=1e-300"}, dir,
                   {scene, "integrator.dt: must be in [1e-06, 1], got 1e-300"});
  expectInputError({"simulate", scene, "--set", "integrator.min_substep=1e-300"}, dir,
                   {"integrator.min_substep: must be at least dt / 2^20"});
}

TEST(MalformedScene, NumbersBeyondADoubleInSetAreInputErrors) {
  const TempDir dir;
  const std::string scene = sceneWith(dir);
  expectInputError({"simulate", scene, "--set", "duration=1e309"}, dir, {scene, "--set duration=1e309", "number overflow"});
  expectInputError({"simulate", scene, "--set", "controller.kp=-1e400"}, dir, {"--set controller.kp=-1e400", "number overflow"});
}

TEST(MalformedScene, MessagesStayOneReadableLine) {
  const TempDir dir;
  // An unknown key with a newline and a control character in it, echoed in the message.
  const std::string scene = dir.write("keys.json", "{\"robot\": {\"urdf\": \"x.urdf\"}, \"dura\\ntion\\u0007\": 1}");
  expectInputError({"simulate", scene}, dir, {scene, "dura\\x0ation\\x07", "unknown key"});
  // An unknown key of 100 000 characters: the message is cut to a readable length.
  const std::string long_key = dir.write("long.json", "{\"" + std::string(100000, 'k') + "\": 1}");
  const CliResult r = runBounded({"simulate", long_key}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_LT(r.err.size(), 4200u);
  expectInputError({"simulate", dir.write("twice.json", "{\"duration\": 1, \"duration\": 2}")}, dir, {"\"duration\" appears twice"});
}

TEST(MalformedScene, TenThousandContactPointsAreRefused) {
  const TempDir dir;
  json points = json::array();
  for (int i = 0; i < 10000; ++i) points.push_back({{"link", "FL_foot"}, {"radius", 0.02}});
  const std::string scene = sceneWith(dir, {{"contacts", {{"points", points}}}});
  expectInputError({"simulate", scene}, dir, {scene, "contacts.points", "10000 contact points, more than the 64"});
}

TEST(MalformedPaths, AHundredThousandCharacterPathGivesOneShortMessage) {
  const TempDir dir;
  const std::string path = dir.dir() + "/" + std::string(100000, 'p') + ".json";
  expectInputError({"simulate", path}, dir, {"cannot read the scene file", "characters)..."});
  expectInputError({"inspect", path}, dir, {"cannot read the URDF file"});
  expectInputError({"simulate", sceneWith(dir, {{"robot", {{"urdf", path}}}})}, dir, {"robot.urdf", "not a usable path"});
  expectInputError({"simulate", sceneWith(dir), "--set", "output.file=" + path}, dir, {"output.file", "not a usable path"});
  expectInputError({"wrench", "--model", path}, dir, {"cannot read the JSON file of --model"});
  expectInputError({"fit", "--data", path, "--model", "rbf", "--out", dir.file("m.h5")}, dir, {"characters)..."});
  expectInputError({"fit", "--import-csv", path, "--out", dir.file("d.h5")}, dir, {"characters)..."});
  expectInputError({"gen-rft", "--config", path, "--out", dir.file("rft")}, dir, {"cannot read the JSON file of --config"});
}

// Rewrites a double attribute of `object` in an HDF5 file as an array of three.
void replaceWithArrayAttribute(const std::string& file, const std::string& object, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  ASSERT_GE(H5Adelete_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT), 0);
  const hsize_t dims[1] = {3};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t a = H5Acreate_by_name(f, object.c_str(), name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const double values[3] = {0.1, 0.2, 0.3};
  ASSERT_GE(H5Awrite(a, H5T_NATIVE_DOUBLE, values), 0);
  H5Aclose(a);
  H5Sclose(space);
  H5Fclose(f);
}

TEST(MalformedModelFile, AttributesOfTheWrongShapeAreRefused) {
  const TempDir dir;
  const std::string model = dir.file("sand.h5");
  std::filesystem::copy_file(sourcePath("data/granular/handmade_sand_rbf.h5"), model);
  ASSERT_NO_FATAL_FAILURE(replaceWithArrayAttribute(model, "/rbf", "cutoff"));
  const json config = {{"type", "rbf"}, {"file", model}};
  expectInputError({"wrench", "--model", config.dump()}, dir, {model, "attribute 'cutoff' of '/rbf' must be one number, it holds 3"});
  const std::string scene = sceneWith(dir, {{"contacts", {{"model", config}}}});
  expectInputError({"simulate", scene}, dir, {scene, "contacts.model.file", "'cutoff'", "must be one number"});
}

}  // namespace
}  // namespace nmdp::test
