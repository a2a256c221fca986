// io/output_path: an output never replaces an input of its run (compared by file identity: the
// same path spelled differently, a symbolic link, a hard link) nor a file nmdp did not write
// (recognised by the marker every nmdp output carries, and the markers of older files); an output
// folder receives files only if it is new, empty or holds only what nmdp wrote there; temporary
// names are unique and in the destination folder; files are written atomically.
// tests/CMakeLists.txt gives tests no HDF5 include folder (nmdp_io links HDF5 privately); Debian
// installs the serial headers under hdf5/serial.
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif
#include <unistd.h>

#include <filesystem>
#include <set>

#include "io/hdf5_file.hpp"
#include "io/output_path.hpp"
#include "sim/trajectory_writer.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;

std::string refusal(const std::string& output, const std::vector<RunInput>& inputs) {
  return inputErrorMessage([&] { checkOutputFile(output, inputs, "--out"); });
}

void expectRefused(const std::string& output, const std::vector<RunInput>& inputs, std::vector<std::string> words) {
  const std::string message = refusal(output, inputs);
  words.push_back(output);
  words.push_back("refusing to write the output of --out there");
  for (const std::string& w : words) EXPECT_NE(message.find(w), std::string::npos) << "'" << w << "' not in: " << message;
}

// An HDF5 file with the given root string attributes and datasets (scalars), written with the C API
// so that it carries no marker but these.
void writeHdf5(const std::string& path, const std::vector<std::string>& attributes, const std::vector<std::string>& datasets) {
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t space = H5Screate(H5S_SCALAR);
  for (const std::string& name : attributes) {
    const hid_t a = H5Acreate2(f, name.c_str(), H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT);
    const int one = 1;
    H5Awrite(a, H5T_NATIVE_INT, &one);
    H5Aclose(a);
  }
  for (const std::string& name : datasets) {
    const hid_t d = H5Dcreate2(f, name.c_str(), H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dclose(d);
  }
  H5Sclose(space);
  H5Fclose(f);
}

TEST(OutputPath, AnInputIsRefusedHoweverItIsSpelled) {
  TempDir dir;
  const std::string scene = dir.write("scene.json", "{}");
  const std::vector<RunInput> inputs = {{scene, "the scene"}};
  expectRefused(scene, inputs, {"it is the scene of this run", scene});
  // Another spelling of the same path, a symbolic link, a hard link.
  // Through a folder that does not exist the path names no file (the kernel resolves "sub/.." only
  // when sub exists): refused as such, and the scene stays untouched.
  expectRefused(dir.dir() + "/./sub/../scene.json", inputs, {"does not exist"});
  fs::create_directory(dir.file("sub"));
  expectRefused(dir.dir() + "/sub/../scene.json", inputs, {"the scene"});
  fs::create_symlink(scene, dir.file("link.json"));
  expectRefused(dir.file("link.json"), inputs, {"the scene"});
  fs::create_hard_link(scene, dir.file("hard.json"));
  expectRefused(dir.file("hard.json"), inputs, {"the scene"});
  // The input given through a relative path from the current folder.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir.path());
  expectRefused("scene.json", {{"./scene.json", "the scene"}}, {"the scene", "./scene.json"});
  fs::current_path(cwd);
  EXPECT_EQ(readText(scene), "{}");
}

TEST(OutputPath, AnInputThatIsAnNmdpOutputIsRefusedToo) {
  TempDir dir;
  const std::string model = dir.file("model.h5");
  {
    h5::File f = h5::File::createAtomic(model);
    f.writeStringAttribute("/", "nmdp_model", "rbf");
    f.commit();
  }
  EXPECT_TRUE(isNmdpOutputFile(model));
  EXPECT_NO_THROW(checkOutputFile(model, {}, "--out"));  // an nmdp output may be replaced...
  expectRefused(model, {{model, "a contact-model file (file)"}}, {"a contact-model file"});  // ...unless it is read
}

TEST(OutputPath, AFileNmdpDidNotWriteIsRefused) {
  TempDir dir;
  expectRefused(dir.write("notes.txt", "mine"), {}, {"not one nmdp wrote", "no nmdp marker"});
  writeHdf5(dir.file("foreign.h5"), {"author"}, {"/data"});  // HDF5, but not nmdp's
  expectRefused(dir.file("foreign.h5"), {}, {"not one nmdp wrote"});
  writeHdf5(dir.file("config_only.h5"), {"config"}, {"/data"});  // half a trajectory's markers
  expectRefused(dir.file("config_only.h5"), {}, {"not one nmdp wrote"});
  EXPECT_EQ(readText(dir.file("notes.txt")), "mine");
}

TEST(OutputPath, NmdpOutputsOldAndNewAreRecognised) {
  TempDir dir;
  writeHdf5(dir.file("model.h5"), {"nmdp_model"}, {});
  writeHdf5(dir.file("dataset.h5"), {"nmdp_dataset"}, {});
  writeHdf5(dir.file("trajectory.h5"), {"config"}, {"/status"});  // a trajectory before the marker
  writeHdf5(dir.file("marked.h5"), {"nmdp_output"}, {});
  for (const char* name : {"model.h5", "dataset.h5", "trajectory.h5", "marked.h5"}) {
    EXPECT_TRUE(isNmdpOutputFile(dir.file(name))) << name;
    EXPECT_NO_THROW(checkOutputFile(dir.file(name), {}, "--out")) << name;
  }
  // Every HDF5 file nmdp writes carries the marker: h5::File and the trajectory writer.
  {
    h5::File f = h5::File::createAtomic(dir.file("file.h5"));
    f.commit();
  }
  EXPECT_EQ(h5::File::openRead(dir.file("file.h5")).readStringAttribute("/", "nmdp_output"), "nmdp");
  TrajectoryLayout layout;
  layout.joint_names = {"a"};
  layout.config_json = "{}";
  TrajectoryWriter(dir.file("run.h5"), layout).finish();
  EXPECT_EQ(h5::File::openRead(dir.file("run.h5")).readStringAttribute("/", "nmdp_output"), "trajectory");
  EXPECT_TRUE(isNmdpOutputFile(dir.file("run.h5")));
  // A killed trajectory (still marked open by its SWMR writer) is recognised as well.
  const pid_t pid = ::fork();
  if (pid == 0) {
    TrajectoryWriter w(dir.file("killed.h5"), layout);
    ::_exit(0);  // no destructor: the file stays as a killed run leaves it
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(isNmdpOutputFile(dir.file("killed.h5")));
  EXPECT_EQ(TrajectoryWriter::readStatus(dir.file("killed.h5")), "running");
}

TEST(OutputPath, WhatIsNotARegularFileIsRefused) {
  TempDir dir;
  fs::create_directory(dir.file("folder.h5"));
  expectRefused(dir.file("folder.h5"), {}, {"it is a folder"});
  if (fs::exists("/dev/null")) expectRefused("/dev/null", {}, {"not a regular file"});
  expectRefused(dir.file("missing/run.h5"), {}, {"does not exist"});
  fs::create_symlink(dir.file("nowhere.h5"), dir.file("dangling.h5"));
  expectRefused(dir.file("dangling.h5"), {}, {"symbolic link"});
  EXPECT_NO_THROW(checkOutputFile(dir.file("new.h5"), {}, "--out"));
}

TEST(OutputPath, AFolderReceivesFilesOnlyIfNmdpWroteWhatItHolds) {
  TempDir dir;
  const std::vector<std::string> names = {"features.csv", "wrench_samples.csv", "scalars.txt"};
  auto refusal = [&](const std::string& folder, const std::vector<RunInput>& inputs) {
    return inputErrorMessage([&] { checkOutputFolder(folder, names, inputs, "--out"); });
  };
  EXPECT_NO_THROW(checkOutputFolder(dir.file("new"), names, {}, "--out"));
  fs::create_directory(dir.file("empty"));
  EXPECT_NO_THROW(checkOutputFolder(dir.file("empty"), names, {}, "--out"));
  // The user's own data in the layout nmdp writes: refused, whichever file is met first.
  dir.write("user/features.csv", "depth,theta\n");
  dir.write("user/wrench_samples.csv", "x\n");
  std::string message = refusal(dir.file("user"), {});
  EXPECT_NE(message.find("which nmdp did not write there"), std::string::npos) << message;
  EXPECT_NE(message.find(dir.file("user")), std::string::npos) << message;
  // A folder nmdp wrote (its marker lists the files) may be written again...
  dir.write("ours/features.csv", "a\n");
  writeFolderMarker(dir.file("ours"), "gen-rft", names);
  EXPECT_NO_THROW(checkOutputFolder(dir.file("ours"), names, {}, "--out"));
  // ...but not when something else was put there, nor when one of its files is read by the run.
  dir.write("ours/mine.txt", "x");
  message = refusal(dir.file("ours"), {});
  EXPECT_NE(message.find("mine.txt"), std::string::npos) << message;
  fs::remove(dir.file("ours/mine.txt"));
  message = refusal(dir.file("ours"), {{dir.dir() + "/ours/./features.csv", "the --config file"}});
  EXPECT_NE(message.find("features.csv is the --config file of this run"), std::string::npos) << message;
  dir.write("plain", "x");
  EXPECT_NE(refusal(dir.file("plain"), {}).find("not a folder"), std::string::npos);
}

TEST(OutputPath, TemporaryNamesAreUniqueAndBesideTheOutput) {
  TempDir dir;
  std::set<std::string> seen;
  for (int i = 0; i < 100; ++i) {
    const std::string t = temporaryPathFor(dir.file("run.h5"));
    EXPECT_EQ(fs::path(t).parent_path(), dir.path());
    EXPECT_EQ(fs::path(t).filename().string().rfind("run.h5.", 0), 0u) << t;
    EXPECT_EQ(t.substr(t.size() - 8), ".partial");
    EXPECT_TRUE(seen.insert(t).second) << t;
  }
  const std::string long_name(250, 'x');
  EXPECT_LE(fs::path(temporaryPathFor(dir.file(long_name))).filename().string().size(), 255u);
  // Atomic writing: the content arrives whole, an existing file is replaced, nothing else is left.
  writeFileAtomically(dir.file("a.txt"), "first");
  writeFileAtomically(dir.file("a.txt"), "second");
  EXPECT_EQ(readText(dir.file("a.txt")), "second");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace nmdp::test
