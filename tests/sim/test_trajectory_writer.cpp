// TrajectoryWriter: the layout of DESIGN.md 11 read back with the project's reader, the HDF5 C API
// and h5py; failure status, overwriting and bad paths, growth by one chunk at a time, commits by
// count and by time, and no byte outside raw data changing between growths. The space checks:
// test_trajectory_writer_space.cpp; SIGKILL at random moments: test_trajectory_writer_kill.cpp.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "io/hdf5_file.hpp"
#include "run_files.hpp"
#include "sim/trajectory_writer.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

TEST(TrajectoryWriter, WritesTheLayoutOfDesign11) {
  TempDir dir;
  const std::string path = dir.file("run.h5");
  {
    TrajectoryWriter w(path, quadrupedLayout());  // one chunk of 100 rows allocated, 50 used: finish() shrinks
    EXPECT_EQ(w.allocatedRows(), 100);
    Step s;
    for (long i = 0; i < 50; ++i) {
      makeStep(i, s);
      appendStep(w, s);
    }
    EXPECT_EQ(w.rows(), 50);
    EXPECT_EQ(w.committedRows(), 50);  // flush_every = 1 by default: nothing pending
    EXPECT_EQ(w.allocatedRows(), 100);
    expectSteps(path, 50, Extent::kReserved);  // while running: /steps rows, NaN after
    w.finish();
    EXPECT_FALSE(w.isOpen());
    EXPECT_THROW(appendStep(w, s), std::logic_error);
  }
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"run.h5"});  // no temporary file left
  expectSteps(path, 50);
  EXPECT_EQ(TrajectoryWriter::readStatus(path), "complete");

  const h5::File file = h5::File::openRead(path);
  const TrajectoryLayout layout = quadrupedLayout();
  EXPECT_EQ(file.readStrings("/joint_names"), layout.joint_names);
  EXPECT_EQ(file.readStrings("/contacts/names"), layout.contact_names);
  EXPECT_EQ(file.readStringAttribute("/", "config"), layout.config_json);
  EXPECT_EQ(file.readStringAttribute("/", "robot"), "quadruped");
  EXPECT_EQ(file.readStringAttribute("/", "method"), "ne-pgm");
  EXPECT_EQ(file.readDoubleAttribute("/", "dt"), 0.0005);

  // Shapes and stored types.
  auto expectDataset = [&](const std::string& name, std::vector<hsize_t> dims, H5T_class_t cls, size_t size) {
    const DatasetInfo info = datasetInfo(path, name);
    EXPECT_EQ(info.dims, dims) << name;
    EXPECT_EQ(info.type_class, cls) << name;
    EXPECT_EQ(info.type_size, size) << name;
  };
  expectDataset("/time", {50}, H5T_FLOAT, 8);
  expectDataset("/q", {50, kDof}, H5T_FLOAT, 8);
  expectDataset("/qdot", {50, kDof}, H5T_FLOAT, 8);
  expectDataset("/base/position", {50, 3}, H5T_FLOAT, 8);
  expectDataset("/base/rpy", {50, 3}, H5T_FLOAT, 8);
  expectDataset("/contacts/wrench", {50, kContacts, 6}, H5T_FLOAT, 8);
  expectDataset("/stats/outer_iterations", {50}, H5T_INTEGER, 4);
  expectDataset("/stats/g_evaluations", {50}, H5T_INTEGER, 4);
  expectDataset("/stats/substeps", {50}, H5T_INTEGER, 4);
  expectDataset("/stats/min_substep", {50}, H5T_FLOAT, 8);
  expectDataset("/stats/wall_time", {50}, H5T_FLOAT, 8);
  expectDataset("/stats/converged", {50}, H5T_INTEGER, 1);
  EXPECT_EQ(datasetInfo(path, "/stats/converged").sign, H5T_SGN_NONE);
  expectDataset("/steps", {}, H5T_INTEGER, 8);
  EXPECT_EQ(datasetInfo(path, "/steps").sign, H5T_SGN_2);
  expectDataset("/joint_names", {kDof}, H5T_STRING, sizeof(char*));
  expectDataset("/contacts/names", {kContacts}, H5T_STRING, sizeof(char*));

  const std::string python = pythonWithH5py();
  if (python.empty())
    std::cout << "python3 with h5py not found: skipping the h5py cross-check\n";
  else
    EXPECT_EQ(checkWithH5py(python, dir, path, "complete", 50), 0);
}

TEST(TrajectoryWriter, FailKeepsTheCompletedStepsAndSaysWhy) {
  TempDir dir;
  const std::string path = dir.file("failed.h5");
  TrajectoryWriter w(path, quadrupedLayout());
  Step s;
  for (long i = 0; i < 7; ++i) {
    makeStep(i, s);
    appendStep(w, s);
  }
  w.fail("projection diverged at t = 0.0035 s");
  EXPECT_THROW(w.finish(), std::logic_error);
  expectSteps(path, 7);
  EXPECT_EQ(TrajectoryWriter::readStatus(path), "failed: projection diverged at t = 0.0035 s");
  // Very long reasons are truncated to fit /status.
  TrajectoryWriter w2(dir.file("long.h5"), quadrupedLayout());
  w2.fail(std::string(2000, 'x'));
  EXPECT_EQ(TrajectoryWriter::readStatus(dir.file("long.h5")).size(), size_t(TrajectoryWriter::kStatusBytes - 1));
}

TEST(TrajectoryWriter, UnfinishedWriterLeavesRunningWithEveryStep) {
  TempDir dir;
  const std::string path = dir.file("abandoned.h5");
  {
    TrajectoryLayout layout = quadrupedLayout();
    layout.flush_every = 4;  // the destructor commits the 2 pending steps
    layout.chunk_rows = 3;   // several chunks
    TrajectoryWriter w(path, layout);
    Step s;
    for (long i = 0; i < 10; ++i) {
      makeStep(i, s);
      appendStep(w, s);
    }
    expectSteps(path, 8, Extent::kReserved);
  }
  expectSteps(path, 10);  // the destructor also shrinks to the steps
  EXPECT_EQ(TrajectoryWriter::readStatus(path), "running");
}

TEST(TrajectoryWriter, EmptyRunAndNoContacts) {
  TempDir dir;
  TrajectoryLayout layout;
  layout.joint_names = {"a", "b"};
  layout.config_json = "{}";
  layout.chunk_rows = 5;
  const std::string path = dir.file("empty.h5");
  {
    TrajectoryWriter w(path, layout);
    EXPECT_EQ(datasetInfo(path, "/time").dims, std::vector<hsize_t>{5});  // the first chunk
    EXPECT_EQ(datasetInfo(path, "/contacts/wrench").dims, (std::vector<hsize_t>{5, 0, 6}));
    w.finish();
  }
  EXPECT_EQ(datasetInfo(path, "/time").dims, std::vector<hsize_t>{0});
  EXPECT_EQ(datasetInfo(path, "/contacts/wrench").dims, (std::vector<hsize_t>{0, 0, 6}));
  EXPECT_EQ(TrajectoryWriter::readRows(path), 0);
  layout.chunk_rows = 3;
  TrajectoryWriter w(dir.file("nocontact.h5"), layout);
  StepStats stats;
  w.append(0.1, Eigen::Vector2d(1, 2), Eigen::Vector2d(3, 4), Vec3::Zero(), Vec3::Zero(), {}, stats);
  EXPECT_THROW(w.append(0.2, Eigen::Vector3d(1, 2, 3), Eigen::Vector2d(3, 4), Vec3::Zero(), Vec3::Zero(), {}, stats),
               std::invalid_argument);
  w.finish();
  EXPECT_EQ(datasetInfo(dir.file("nocontact.h5"), "/contacts/wrench").dims, (std::vector<hsize_t>{1, 0, 6}));
  EXPECT_EQ(h5::File::openRead(dir.file("nocontact.h5")).readMatrix("/q"), Eigen::RowVector2d(1, 2));
}

// Storage grows as the run goes: one chunk at creation, one more chunk each time the rows are used
// up, whatever the run will append; the rows after /steps are fill values throughout.
TEST(TrajectoryWriter, GrowsByOneChunkWhenFull) {
  TempDir dir;
  for (int flush_every : {1, 4}) {
    const std::string path = dir.file("grow" + std::to_string(flush_every) + ".h5");
    TrajectoryLayout layout = quadrupedLayout();
    layout.chunk_rows = 4;
    layout.flush_every = flush_every;
    layout.flush_interval = 1e9;
    TrajectoryWriter w(path, layout);
    EXPECT_EQ(w.allocatedRows(), 4);
    Step s;
    for (long i = 0; i < 30; ++i) {
      makeStep(i, s);
      appendStep(w, s);
      EXPECT_EQ(w.allocatedRows(), 4 * (i / 4 + 1)) << "after " << i + 1 << " steps";
    }
    EXPECT_EQ(w.committedRows(), flush_every == 1 ? 30 : 28);
    expectSteps(path, w.committedRows(), Extent::kReserved, flush_every);
    makeStep(30, s);
    appendStep(w, s);  // e.g. the app's final partial step
    w.finish();
    expectSteps(path, 31);
  }
  // The file holds what was written, not what a run might write: 20 rows cost a chunk of 100 rows
  // (about 150 kB: 1.5 kB a row for n = 18, C = 4, no links) and the metadata.
  TrajectoryLayout layout = quadrupedLayout();
  TrajectoryWriter small(dir.file("small.h5"), layout);
  Step s;
  for (long i = 0; i < 20; ++i) {
    makeStep(i, s);
    appendStep(small, s);
  }
  EXPECT_LT(std::filesystem::file_size(dir.file("small.h5")), 250u * 1024);
  small.finish();
  EXPECT_LT(std::filesystem::file_size(dir.file("small.h5")), 250u * 1024);
}

// Between growths a commit writes raw data only, checked byte by byte: while the rows fit in the
// allocated chunk, every byte of the file that changes lies in the raw data of a per-step dataset,
// /steps or /status, and the file does not grow.
std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
TEST(TrajectoryWriter, NoMetadataChangesWhileRunning) {
  TempDir dir;
  const std::string path = dir.file("bytes.h5");
  const long appended = 700;
  for (int flush_every : {1, 7}) {
    TrajectoryLayout layout = quadrupedLayout();
    layout.chunk_rows = 1000;
    layout.flush_every = flush_every;
    TrajectoryWriter w(path, layout);
    const std::string before = fileBytes(path);
    Step s;
    for (long i = 0; i < appended; ++i) {
      makeStep(i, s);
      appendStep(w, s);
    }
    const std::string after = fileBytes(path);
    EXPECT_EQ(TrajectoryWriter::readRows(path), appended);
    w.fail("stopped by the test");  // shrinking to 700 rows keeps the chunks holding them in place
    ASSERT_EQ(after.size(), before.size()) << "the file grew while running";

    // The byte ranges of raw data: chunks of the per-step datasets, storage of /steps and /status.
    std::vector<std::pair<haddr_t, hsize_t>> raw;
    const hid_t f = openFile(path);
    ASSERT_GE(f, 0);
    for (const std::string& name_text : perRowDatasets(path)) {
      const char* name = name_text.c_str();
      if (readDataset(path, name_text).rowSize() == 0) continue;  // no links in this layout: no chunk
      const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
      const hid_t space = H5Dget_space(d);
      hsize_t chunks = 0;
      ASSERT_GE(H5Dget_num_chunks(d, space, &chunks), 0);
      EXPECT_EQ(chunks, hsize_t(1)) << name;
      for (hsize_t k = 0; k < chunks; ++k) {
        hsize_t offset[3];
        unsigned mask = 0;
        haddr_t address = 0;
        hsize_t size = 0;
        ASSERT_GE(H5Dget_chunk_info(d, space, k, offset, &mask, &address, &size), 0);
        raw.emplace_back(address, size);
      }
      H5Sclose(space);
      H5Dclose(d);
    }
    for (const char* name : {"/rows", "/steps", "/status"}) {
      const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
      raw.emplace_back(H5Dget_offset(d), H5Dget_storage_size(d));
      H5Dclose(d);
    }
    H5Fclose(f);
    long changed = 0, outside = 0;
    for (size_t b = 0; b < before.size(); ++b) {
      if (before[b] == after[b]) continue;
      ++changed;
      bool in_raw = false;
      for (const auto& [address, size] : raw) in_raw = in_raw || (b >= address && b < address + size);
      if (!in_raw && outside++ < 5) ADD_FAILURE() << "byte " << b << " changed outside raw data (flush_every " << flush_every << ")";
    }
    EXPECT_GT(changed, appended * 8);  // the rows were written...
    EXPECT_EQ(outside, 0);             // ...and nothing else
  }
}

TEST(TrajectoryWriter, ReplacesAnExistingFileOnlyWithAValidOne) {
  TempDir dir;
  const std::string path = dir.write("old.h5", "previous contents");
  // Creation fails after the temporary file exists (an attribute HDF5 cannot create): the old file
  // stays and no temporary file is left.
  TrajectoryLayout bad = quadrupedLayout();
  bad.string_attributes[""] = "x";
  EXPECT_THROW(TrajectoryWriter(path, bad), InputError);
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"old.h5"});
  bad = quadrupedLayout();
  bad.string_attributes["nmdp_output"] = "x";  // reserved names are refused before anything exists
  EXPECT_THROW(TrajectoryWriter(path, bad), std::invalid_argument);
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"old.h5"});
  {
    std::ifstream in(path);
    std::string text;
    std::getline(in, text);
    EXPECT_EQ(text, "previous contents");
  }
  {
    TrajectoryWriter w(path, quadrupedLayout());
    Step s;
    makeStep(0, s);
    appendStep(w, s);
    w.finish();
  }
  expectSteps(path, 1);
}

TEST(TrajectoryWriter, UnwritablePathsThrowInputErrorNamingThePath) {
  TempDir dir;
  const std::string missing = dir.file("no_such_folder/run.h5");
  EXPECT_NE(inputErrorMessage([&] { TrajectoryWriter(missing, quadrupedLayout()); }).find(missing), std::string::npos);
  const std::string under_file = dir.write("plain.txt", "x") + "/run.h5";
  EXPECT_NE(inputErrorMessage([&] { TrajectoryWriter(under_file, quadrupedLayout()); }).find(under_file), std::string::npos);
  std::filesystem::create_directory(dir.file("folder.h5"));
  const std::string folder = dir.file("folder.h5");
  EXPECT_NE(inputErrorMessage([&] { TrajectoryWriter(folder, quadrupedLayout()); }).find(folder), std::string::npos);
  if (::geteuid() != 0) {  // root ignores permissions
    std::filesystem::create_directory(dir.file("ro"));
    std::filesystem::permissions(dir.file("ro"), std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    const std::string ro = dir.file("ro/run.h5");
    const std::string message = inputErrorMessage([&] { TrajectoryWriter(ro, quadrupedLayout()); });
    EXPECT_NE(message.find(ro), std::string::npos) << message;
    std::filesystem::permissions(dir.file("ro"), std::filesystem::perms::owner_all);
  } else {
    std::cout << "running as root: skipping the read-only folder case\n";
  }
}

TEST(TrajectoryWriter, TimeBoundCommitsAStepWithoutWaitingForTheBatch) {
  TempDir dir;
  TrajectoryLayout layout = quadrupedLayout();
  layout.flush_every = 1000;
  layout.flush_interval = 0.0;  // every append is older than the bound: flush each step
  TrajectoryWriter w(dir.file("t.h5"), layout);
  Step s;
  makeStep(0, s);
  appendStep(w, s);
  EXPECT_EQ(w.committedRows(), 1);
  expectSteps(dir.file("t.h5"), 1, Extent::kReserved);
  TrajectoryLayout batched = quadrupedLayout();
  batched.flush_every = 1000;
  batched.flush_interval = 1e9;
  TrajectoryWriter b(dir.file("b.h5"), batched);
  appendStep(b, s);
  EXPECT_EQ(b.committedRows(), 0);
  expectSteps(dir.file("b.h5"), 0, Extent::kReserved);
  b.finish();
  expectSteps(dir.file("b.h5"), 1);
}

}  // namespace
}  // namespace nmdp::test
