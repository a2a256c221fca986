// Nothing the user owns is overwritten (io/output_path.hpp), end to end: `nmdp simulate`, `fit`
// and `gen-rft` refuse an output that is one of their inputs (however the path is spelled: the same
// path, "./", a symbolic or a hard link) or an existing file nmdp did not write, with exit 1, one
// line naming the output and what it would replace, and the file untouched; `gen-rft` refuses a
// folder holding files it did not write (the user's own sand samples) and writes again into one it
// wrote; an nmdp output that is not an input is replaced. Every input is a copy in a temporary
// folder, so that a regression overwrites nothing of the repository.
#include <filesystem>
#include <fstream>

#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;

// `nmdp ARGS` must exit 1 with one stderr line holding every string of `expect`, and leave every
// file of `untouched` as it was.
void expectRefused(const std::vector<std::string>& args, const TempDir& dir, const std::vector<std::string>& expect,
                   const std::vector<std::string>& untouched) {
  std::vector<std::string> before;
  for (const std::string& f : untouched) before.push_back(readText(f));
  const CliResult r = runNmdp(args, dir);
  ASSERT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
  EXPECT_NE(r.err.find("refusing to write the output of"), std::string::npos) << r.err;
  for (const std::string& e : expect) EXPECT_NE(r.err.find(e), std::string::npos) << "'" << e << "' not in: " << r.err;
  for (size_t i = 0; i < untouched.size(); ++i) EXPECT_EQ(readText(untouched[i]), before[i]) << untouched[i] << " changed";
  for (const auto& entry : fs::recursive_directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().string().find(".partial"), std::string::npos) << "temporary file left: " << entry.path();
}

// A scene in `dir` whose robot (a copy of the project's quadruped) and, as given, contact model and
// terrain are files in `dir` too.
std::string writeScene(const TempDir& dir, const std::string& contacts_model, const std::string& terrain) {
  dir.write("robot.urdf", readText(quadrupedUrdf()));
  return dir.write("scene.json", R"({"robot": {"urdf": "robot.urdf"}, "contacts": {"model": )" + contacts_model +
                                     R"(}, "terrain": )" + terrain + R"(, "duration": 0.1})");
}

TEST(OutputCli, SimulateNeverReplacesItsInputs) {
  TempDir dir;
  fs::copy_file(sourcePath("data/granular/handmade_sand_rbf.h5"), dir.file("sand.h5"));
  fs::copy_file(sourcePath("models/terrain/gentle_bumps.csv"), dir.file("bumps.csv"));
  const std::string scene = writeScene(dir, R"({"type": "rbf", "file": "sand.h5"})",
                                       R"({"type": "heightfield", "file": "bumps.csv", "origin": [-2.4, -2.4], "spacing": [0.2, 0.2]})");
  const std::vector<std::string> inputs = {scene, dir.file("robot.urdf"), dir.file("sand.h5"), dir.file("bumps.csv")};
  auto simulate = [&](const std::string& out) {
    return std::vector<std::string>{"simulate", scene, "--out", out, "--quiet"};
  };
  expectRefused(simulate(scene), dir, {scene, "it is the scene of this run"}, inputs);
  expectRefused(simulate(dir.dir() + "/./scene.json"), dir, {"the scene"}, inputs);
  fs::create_symlink(scene, dir.file("link.json"));
  expectRefused(simulate(dir.file("link.json")), dir, {"the scene"}, inputs);
  fs::create_hard_link(scene, dir.file("hard.json"));
  expectRefused(simulate(dir.file("hard.json")), dir, {"the scene"}, inputs);
  expectRefused(simulate(dir.file("robot.urdf")), dir, {"it is the URDF of this run"}, inputs);
  // The model file is an nmdp output, but this run reads it.
  expectRefused(simulate(dir.file("sand.h5")), dir, {"it is a contact-model file (file) of this run"}, inputs);
  expectRefused(simulate(dir.file("bumps.csv")), dir, {"it is the terrain file (file) of this run"}, inputs);
  // The scene's own output.file naming the scene.
  const std::string self = dir.write("self.json", R"({"robot": {"urdf": "robot.urdf"}, "output": {"file": "self.json"}})");
  expectRefused({"simulate", self, "--quiet"}, dir, {self + ": output.file", "it is the scene"}, {self});
}

TEST(OutputCli, SimulateReplacesOnlyWhatNmdpWrote) {
  TempDir dir;
  const std::string scene = writeScene(dir, R"({"type": "coulomb"})", R"({"type": "plane"})");
  const std::string notes = dir.write("notes.h5", "my notes");
  expectRefused({"simulate", scene, "--out", notes, "--quiet"}, dir, {notes, "not one nmdp wrote"}, {notes});
  const std::string run = dir.file("run.h5");
  for (int i = 0; i < 2; ++i) {  // the second run replaces the first one's trajectory
    const CliResult r = runNmdp({"simulate", scene, "--out", run, "--quiet"}, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(TrajectoryWriter::readStatus(run), "complete");
  }
}

TEST(OutputCli, FitNeverReplacesItsDataOrConfiguration) {
  TempDir dir;
  const std::string data = dir.file("data.h5"), csv = dir.file("csv");
  ASSERT_EQ(runNmdp({"gen-rft", "--out", data}, dir).exit_code, 0);
  ASSERT_EQ(runNmdp({"gen-rft", "--out", csv}, dir).exit_code, 0);
  const std::string config = dir.write("fit.json", "{}");
  expectRefused({"fit", "--data", data, "--model", "rbf", "--out", data}, dir, {"it is the --data file of this run"},
                {data});
  expectRefused({"fit", "--data", data, "--model", "rbf", "--config", config, "--out", config}, dir,
                {"it is the --config file of this run"}, {config});
  expectRefused({"fit", "--import-csv", csv, "--out", csv + "/features.csv"}, dir,
                {"a file of --import-csv's folder"}, {csv + "/features.csv"});
  expectRefused({"fit", "--data", csv, "--model", "rbf", "--out", csv + "/./wrench_samples.csv"}, dir,
                {"a file of --data's folder"}, {csv + "/wrench_samples.csv"});
  const std::string notes = dir.write("notes.h5", "mine");
  expectRefused({"fit", "--data", data, "--model", "rbf", "--out", notes}, dir, {"not one nmdp wrote"}, {notes});
  const CliResult ok = runNmdp({"fit", "--data", data, "--model", "rbf", "--out", dir.file("model.h5"), "--quiet"}, dir);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(h5::File::openRead(dir.file("model.h5")).readStringAttribute("/", "nmdp_output"), "nmdp");
}

TEST(OutputCli, GenRftWritesOnlyIntoFoldersItWrote) {
  TempDir dir;
  // The user's own samples, in the layout gen-rft writes.
  const std::string user = dir.dir() + "/sand_samples";
  dir.write("sand_samples/features.csv", "depth,theta\n0.01,0\n");
  dir.write("sand_samples/wrench_samples.csv", "depth,theta,vel_index,fx,fz,wy\n");
  dir.write("sand_samples/scalars.txt", "Ntheta 1\nNvel 1\n");
  expectRefused({"gen-rft", "--out", user}, dir, {user, "which nmdp did not write there"},
                {user + "/features.csv", user + "/wrench_samples.csv", user + "/scalars.txt"});
  EXPECT_FALSE(fs::exists(user + "/rft_config.json"));
  // A new folder, then the same folder again: its marker lists what gen-rft wrote.
  const std::string out = dir.file("rft");
  ASSERT_EQ(runNmdp({"gen-rft", "--out", out}, dir).exit_code, 0);
  EXPECT_TRUE(fs::exists(out + "/nmdp_output.json"));
  const CliResult again = runNmdp({"gen-rft", "--config", R"({"medium": {"zeta": 2}})", "--out", out}, dir);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  // ...but not from its own configuration file, which the run reads.
  expectRefused({"gen-rft", "--config", out + "/rft_config.json", "--out", out}, dir,
                {"rft_config.json is the --config file of this run"}, {out + "/rft_config.json"});
  const std::string notes = dir.write("notes.h5", "mine");
  expectRefused({"gen-rft", "--out", notes}, dir, {"not one nmdp wrote"}, {notes});
}

}  // namespace
}  // namespace nmdp::test
