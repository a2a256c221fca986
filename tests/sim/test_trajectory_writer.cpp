// TrajectoryWriter: the layout of DESIGN.md 11 read back with the project's reader and the HDF5 C API,
// failure status, overwriting and bad paths, growth by one chunk at a time, the space checks, and
// crash safety: no byte outside raw data changes between growths, and a child process writing a
// trajectory (growing every 16 rows) is SIGKILLed at random moments; the file must open as a SWMR
// reader (h5py swmr=True) and hold every reported step in its first /steps rows, and every file
// that ended must open with plain h5py.File. NMDP_KILL_TRIALS=1000 runs more kills than the
// default 200.
#include <fcntl.h>
// tests/CMakeLists.txt gives tests no HDF5 include folder (nmdp_io links HDF5 privately); Debian
// installs the serial headers under hdf5/serial.
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <random>
#include <thread>

#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

constexpr int kDof = 18, kContacts = 4;

TrajectoryLayout quadrupedLayout() {
  TrajectoryLayout layout;
  for (int j = 0; j < kDof; ++j) layout.joint_names.push_back("joint_" + std::to_string(j));
  layout.contact_names = {"FL_foot", "FR_foot", "RL_foot", "RR_foot"};
  layout.config_json = R"({"robot": {"urdf": "robots/q.urdf"}, "integrator": {"method": "ne-pgm", "dt": 0.0005}})";
  layout.string_attributes = {{"robot", "quadruped"}, {"method", "ne-pgm"}};
  layout.number_attributes = {{"dt", 0.0005}};
  layout.chunk_rows = 100;
  return layout;
}

// The synthetic step i (every value a function of i, so a reader can check any row).
struct Step {
  double time;
  Eigen::VectorXd q, qd;
  Vec3 pos, rpy;
  std::vector<Vec6> wrench;
  StepStats stats;
};
void makeStep(long i, Step& s) {
  s.time = 0.0005 * static_cast<double>(i);
  s.q.resize(kDof);
  s.qd.resize(kDof);
  for (int j = 0; j < kDof; ++j) {
    s.q[j] = static_cast<double>(i) + 0.001 * j;
    s.qd[j] = -static_cast<double>(i) - 0.001 * j;
  }
  s.pos = Vec3(0.5 * i, 1.0 * i, 1.5 * i);
  s.rpy = Vec3(0.1 * i, 0.2 * i, 0.3 * i);
  s.wrench.resize(kContacts);
  for (int c = 0; c < kContacts; ++c)
    for (int k = 0; k < 6; ++k) s.wrench[c][k] = 1000.0 * c + k + 0.25 * static_cast<double>(i);
  s.stats.outer_iterations = static_cast<int>(i % 7);
  s.stats.g_evaluations = static_cast<int>(3 * i);
  s.stats.substeps = static_cast<int>(1 + i % 3);
  s.stats.min_substep = 1e-3 / static_cast<double>(1 + i % 3);
  s.stats.wall_time = 1e-4 * static_cast<double>(i);
  s.stats.converged = i % 5 != 0;
}
void appendStep(TrajectoryWriter& w, const Step& s) { w.append(s.time, s.q, s.qd, s.pos, s.rpy, s.wrench, s.stats); }

// Opens a file read-only as nmdp's readers do: plainly, or as a SWMR reader (a killed writer's file).
hid_t openFile(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f >= 0) return f;
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_metadata_read_attempts(fapl, 12);  // a damaged file fails instead of hanging
  const hid_t swmr = H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl);
  H5Pclose(fapl);
  return swmr;
}

// Dimensions and HDF5 type class/size of a dataset (C API).
struct DatasetInfo {
  std::vector<hsize_t> dims;
  H5T_class_t type_class;
  size_t type_size;
  H5T_sign_t sign;
};
DatasetInfo datasetInfo(const std::string& path, const std::string& name) {
  const hid_t f = openFile(path);
  EXPECT_GE(f, 0);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(d, 0) << name;
  const hid_t space = H5Dget_space(d), type = H5Dget_type(d);
  DatasetInfo info;
  info.dims.resize(H5Sget_simple_extent_ndims(space));
  H5Sget_simple_extent_dims(space, info.dims.data(), nullptr);
  info.type_class = H5Tget_class(type);
  info.type_size = H5Tget_size(type);
  info.sign = info.type_class == H5T_INTEGER ? H5Tget_sign(type) : H5T_SGN_ERROR;
  H5Tclose(type);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return info;
}
// Every element of a numeric dataset as double, row-major (any rank).
std::vector<double> readAll(const std::string& path, const std::string& name) {
  const hid_t f = openFile(path);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  const hssize_t count = H5Sget_simple_extent_npoints(space);
  std::vector<double> out(static_cast<size_t>(count));
  if (count > 0) {
    EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), 0) << name;
  }
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return out;
}

// How long the per-step datasets of a file must be.
enum class Extent {
  kExact,     // a run that ended: len(every per-step dataset) == /steps
  kReserved,  // a running or killed run: at least /steps rows, and the rows from /steps + slack on
              // are the fill values (NaN, integers 0): the rows after /steps are visibly not data.
              // A kill during a growth may leave some datasets grown and others not yet: their
              // extents may differ (each is a valid dataset; HDF5 flushes one object at a time).
};

// Checks that /steps == rows, rows [0, rows) of every dataset against makeStep, and the extent.
// `slack`: rows after /steps that may hold data already (written by a commit /steps does not count yet).
void expectSteps(const std::string& path, long rows, Extent extent = Extent::kExact, long slack = 0) {
  ASSERT_EQ(TrajectoryWriter::readSteps(path), rows);
  const h5::File file = h5::File::openRead(path);
  const Eigen::MatrixXd time = file.readMatrix("/time");
  const Eigen::MatrixXd q = file.readMatrix("/q"), qd = file.readMatrix("/qdot");
  const Eigen::MatrixXd pos = file.readMatrix("/base/position"), rpy = file.readMatrix("/base/rpy");
  const Eigen::MatrixXd outer = file.readMatrix("/stats/outer_iterations"), geval = file.readMatrix("/stats/g_evaluations");
  const Eigen::MatrixXd sub = file.readMatrix("/stats/substeps"), minsub = file.readMatrix("/stats/min_substep");
  const Eigen::MatrixXd wall = file.readMatrix("/stats/wall_time"), conv = file.readMatrix("/stats/converged");
  const std::vector<double> wrench = readAll(path, "/contacts/wrench");
  ASSERT_EQ(wrench.size() % (kContacts * 6), 0u);
  const long wrench_rows = static_cast<long>(wrench.size()) / (kContacts * 6);
  for (const Eigen::MatrixXd* m : {&time, &q, &qd, &pos, &rpy, &outer, &geval, &sub, &minsub, &wall, &conv}) {
    if (extent == Extent::kExact)
      ASSERT_EQ(m->rows(), rows);
    else
      ASSERT_GE(m->rows(), rows);
  }
  if (extent == Extent::kExact)
    ASSERT_EQ(wrench_rows, rows);
  else
    ASSERT_GE(wrench_rows, rows);
  // Fill values after the committed rows, in each dataset as far as it reaches.
  for (long i = rows + slack; i < time.rows(); ++i) ASSERT_TRUE(std::isnan(time(i, 0))) << "row " << i;
  for (long i = rows + slack; i < q.rows(); ++i) ASSERT_TRUE(q.row(i).array().isNaN().all()) << "row " << i;
  for (long i = rows + slack; i < qd.rows(); ++i) ASSERT_TRUE(qd.row(i).array().isNaN().all()) << "row " << i;
  for (long i = rows + slack; i < pos.rows(); ++i) ASSERT_TRUE(pos.row(i).array().isNaN().all()) << "row " << i;
  for (long i = rows + slack; i < rpy.rows(); ++i) ASSERT_TRUE(rpy.row(i).array().isNaN().all()) << "row " << i;
  for (long i = rows + slack; i < minsub.rows(); ++i) ASSERT_TRUE(std::isnan(minsub(i, 0))) << "row " << i;
  for (long i = rows + slack; i < wall.rows(); ++i) ASSERT_TRUE(std::isnan(wall(i, 0))) << "row " << i;
  for (const Eigen::MatrixXd* m : {&outer, &geval, &sub, &conv})
    for (long i = rows + slack; i < m->rows(); ++i) ASSERT_EQ((*m)(i, 0), 0.0) << "row " << i;
  for (long i = rows + slack; i < wrench_rows; ++i)
    for (int k = 0; k < kContacts * 6; ++k) ASSERT_TRUE(std::isnan(wrench[i * kContacts * 6 + k])) << "row " << i;
  ASSERT_EQ(q.cols(), kDof);
  ASSERT_EQ(pos.cols(), 3);
  Step s;
  for (long i = 0; i < rows; ++i) {
    makeStep(i, s);
    ASSERT_EQ(time(i, 0), s.time) << "row " << i;
    ASSERT_EQ(Eigen::VectorXd(q.row(i).transpose()), s.q) << "row " << i;
    ASSERT_EQ(Eigen::VectorXd(qd.row(i).transpose()), s.qd) << "row " << i;
    ASSERT_EQ(Vec3(pos.row(i).transpose()), s.pos) << "row " << i;
    ASSERT_EQ(Vec3(rpy.row(i).transpose()), s.rpy) << "row " << i;
    for (int c = 0; c < kContacts; ++c)
      for (int k = 0; k < 6; ++k) ASSERT_EQ(wrench[(i * kContacts + c) * 6 + k], s.wrench[c][k]) << "row " << i;
    ASSERT_EQ(outer(i, 0), s.stats.outer_iterations);
    ASSERT_EQ(geval(i, 0), s.stats.g_evaluations);
    ASSERT_EQ(sub(i, 0), s.stats.substeps);
    ASSERT_EQ(minsub(i, 0), s.stats.min_substep);
    ASSERT_EQ(wall(i, 0), s.stats.wall_time);
    ASSERT_EQ(conv(i, 0), s.stats.converged ? 1.0 : 0.0);
  }
}

// A python3 with h5py, or "" (Debian's python3-h5py lives under /usr/bin/python3).
std::string pythonWithH5py() {
  for (const char* py : {"/usr/bin/python3", "python3"})
    if (std::system((std::string(py) + " -c 'import h5py' >/dev/null 2>&1").c_str()) == 0) return py;
  return "";
}

// Runs a python script checking the file with h5py: a run that ended (status not "running") opens
// with plain h5py.File(path); a killed one as the README says, h5py.File(path, "r", swmr=True).
// Status, at least min_rows complete steps in /steps, every per-step dataset /steps rows long for a
// run that ended and at least that otherwise, values of every row below /steps.
int checkWithH5py(const std::string& python, const TempDir& dir, const std::string& path, const std::string& status,
                  long min_rows) {
  const std::string script = dir.write("check.py", R"(import sys, h5py, numpy as np
path, status, min_rows = sys.argv[1], sys.argv[2], int(sys.argv[3])
with h5py.File(path, "r", swmr=(status == "running")) as f:
    got = f["status"][()].decode()
    assert got == status, got
    n = int(f["steps"][()])
    assert f["steps"].shape == () and f["steps"].dtype == np.int64
    assert n >= min_rows, (n, min_rows)
    for name in ["time", "q", "qdot", "base/position", "base/rpy", "contacts/wrench", "stats/outer_iterations",
                 "stats/g_evaluations", "stats/substeps", "stats/min_substep", "stats/wall_time", "stats/converged"]:
        rows = f[name].shape[0]
        assert rows == n if status != "running" else rows >= n, (name, rows, n, status)
    i = np.arange(n)
    assert np.array_equal(f["time"][:n], 0.0005 * i)
    assert np.array_equal(f["q"][:n], i[:, None] + 0.001 * np.arange(18)[None, :])
    assert np.array_equal(f["contacts/wrench"][:n], 1000.0 * np.arange(4)[None, :, None] + np.arange(6)[None, None, :] + 0.25 * i[:, None, None])
    assert np.array_equal(f["stats/converged"][:n], (i % 5 != 0).astype(np.uint8))
    assert f["stats/g_evaluations"].dtype == np.int32 and f["stats/converged"].dtype == np.uint8
    assert [s.decode() for s in f["joint_names"][:]] == ["joint_%d" % j for j in range(18)]
    assert [s.decode() for s in f["contacts/names"][:]] == ["FL_foot", "FR_foot", "RL_foot", "RR_foot"]
    assert "ne-pgm" in f.attrs["config"] and f.attrs["dt"] == 0.0005 and f.attrs["robot"] == "quadruped"
    assert f.attrs["nmdp_output"] == "trajectory"
print("h5py ok", n)
)");
  return std::system((python + " " + script + " " + path + " '" + status + "' " + std::to_string(min_rows)).c_str());
}

// The names in a folder, sorted.
std::vector<std::string> filesIn(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

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
    EXPECT_EQ(w.steps(), 50);
    EXPECT_EQ(w.committedSteps(), 50);  // flush_every = 1 by default: nothing pending
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
  EXPECT_EQ(TrajectoryWriter::readSteps(path), 0);
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
    EXPECT_EQ(w.committedSteps(), flush_every == 1 ? 30 : 28);
    expectSteps(path, w.committedSteps(), Extent::kReserved, flush_every);
    makeStep(30, s);
    appendStep(w, s);  // e.g. the app's final partial step
    w.finish();
    expectSteps(path, 31);
  }
  // The file holds what was written, not what a run might write: 2000 rows of 4 cost ~1 MB, 20 rows
  // a chunk of 100 rows (54 kB) and the metadata.
  TrajectoryLayout layout = quadrupedLayout();
  TrajectoryWriter small(dir.file("small.h5"), layout);
  Step s;
  for (long i = 0; i < 20; ++i) {
    makeStep(i, s);
    appendStep(small, s);
  }
  EXPECT_LT(std::filesystem::file_size(dir.file("small.h5")), 200u * 1024);
  small.finish();
  EXPECT_LT(std::filesystem::file_size(dir.file("small.h5")), 200u * 1024);
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
    EXPECT_EQ(TrajectoryWriter::readSteps(path), appended);
    w.fail("stopped by the test");  // shrinking to 700 rows keeps the chunks holding them in place
    ASSERT_EQ(after.size(), before.size()) << "the file grew while running";

    // The byte ranges of raw data: chunks of the per-step datasets, storage of /steps and /status.
    std::vector<std::pair<haddr_t, hsize_t>> raw;
    const hid_t f = openFile(path);
    ASSERT_GE(f, 0);
    for (const char* name : {"/time", "/q", "/qdot", "/base/position", "/base/rpy", "/contacts/wrench",
                             "/stats/outer_iterations", "/stats/g_evaluations", "/stats/substeps",
                             "/stats/min_substep", "/stats/wall_time", "/stats/converged", "/stats/error_estimate"}) {
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
    for (const char* name : {"/steps", "/status"}) {
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

// The file size limit (RLIMIT_FSIZE, `ulimit -f`) stands in for a full disk: the writer checks it
// as it checks the free space. Sets the soft limit for the scope (the test runs single-threaded).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    struct rlimit limit = saved_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);  // a write past the limit fails instead of killing
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  struct rlimit saved_;
  void (*previous_handler_)(int);
};

TEST(TrajectoryWriter, RefusesToStartWhenTheFirstChunkDoesNotFit) {
  TempDir dir;
  TrajectoryLayout layout = quadrupedLayout();
  layout.chunk_rows = 1000;  // 541 kB
  std::string message;
  {
    FileSizeLimit limit(1 << 20);  // less than the chunk and the reserve kept for ending a run
    message = inputErrorMessage([&] { TrajectoryWriter(dir.file("run.h5"), layout); });
  }
  EXPECT_NE(message.find("cannot start the run"), std::string::npos) << message;
  EXPECT_NE(message.find("file size limit"), std::string::npos) << message;
  EXPECT_NE(message.find(dir.file("run.h5")), std::string::npos) << message;
  EXPECT_TRUE(filesIn(dir).empty());  // nothing left behind
}

TEST(TrajectoryWriter, AChunkThatDoesNotFitEndsTheRunWithEveryStepKept) {
  TempDir dir;
  const std::string path = dir.file("run.h5");
  TrajectoryLayout layout = quadrupedLayout();
  layout.chunk_rows = 200;  // 108 kB
  long appended = 0;
  std::string reason;
  {
    FileSizeLimit limit(TrajectoryWriter::kSpaceReserve + 600 * 1024);  // a few chunks
    TrajectoryWriter w(path, layout);
    Step s;
    try {
      for (; appended < 100000; ++appended) {
        makeStep(appended, s);
        appendStep(w, s);
      }
    } catch (const TrajectoryWriter::OutOfSpace& e) {
      reason = e.what();
    }
    EXPECT_EQ(w.steps(), appended);  // the step that did not fit was not appended
    w.fail(reason);
  }
  EXPECT_NE(reason.find("file size limit"), std::string::npos) << reason;
  EXPECT_GE(appended, 400);  // grew at least twice before the limit
  EXPECT_EQ(appended % 200, 0);  // every allocated row was used
  EXPECT_LT(appended, 100000);
  expectSteps(path, appended);
  EXPECT_EQ(TrajectoryWriter::readStatus(path).rfind("failed: " + path + ": the file size limit", 0), 0u)
      << TrajectoryWriter::readStatus(path);
  const std::string python = pythonWithH5py();
  if (!python.empty()) {
    TempDir scripts;
    EXPECT_EQ(checkWithH5py(python, scripts, path, TrajectoryWriter::readStatus(path), appended), 0);
  }
}

// Forks a child that appends up to kKillSteps steps (flush_every given; then it waits) and reports
// each completed append on a pipe; SIGKILLs it once `min_steps` were reported (plus
// `extra_delay_us`), and returns the count. The child's datasets grow every chunk_rows rows, so
// kills land in growths as well as in commits (with chunk_rows = 1 every append grows them).
constexpr long kKillSteps = 5000;  // more than a child appends before its kill (~30 µs per step)
long runAndKill(const std::string& path, int flush_every, int chunk_rows, long min_steps, int extra_delay_us) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe");
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork");
  if (pid == 0) {  // child: no gtest, no return
    ::close(fds[0]);
    ::fcntl(fds[1], F_SETFL, O_NONBLOCK);
    try {
      TrajectoryLayout layout = quadrupedLayout();
      layout.flush_every = flush_every;
      layout.flush_interval = flush_every == 1 ? 1.0 : 0.002;  // also exercise the time bound
      layout.chunk_rows = chunk_rows;
      TrajectoryWriter w(path, layout);
      Step s;
      for (long i = 0; i < kKillSteps; ++i) {
        makeStep(i, s);
        appendStep(w, s);
        const long committed = w.committedSteps();  // steps guaranteed on disk
        if (::write(fds[1], &committed, sizeof committed) < 0) {
        }  // a full pipe just drops reports
      }
      for (;;) ::pause();  // wait for the kill
    } catch (...) {
      ::_exit(3);
    }
  }
  ::close(fds[1]);
  long reported = 0, value = 0;
  while (reported < min_steps) {
    const ssize_t r = ::read(fds[0], &value, sizeof value);
    if (r != static_cast<ssize_t>(sizeof value)) break;  // child died
    reported = value;
  }
  if (extra_delay_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(extra_delay_us));
  // Drain what the child reported before the kill (it cannot report after).
  ::kill(pid, SIGKILL);
  ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
  while (::read(fds[0], &value, sizeof value) == static_cast<ssize_t>(sizeof value)) reported = value;
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(fds[0]);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the child did not run until killed";
  return reported;
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
  EXPECT_EQ(w.committedSteps(), 1);
  expectSteps(dir.file("t.h5"), 1, Extent::kReserved);
  TrajectoryLayout batched = quadrupedLayout();
  batched.flush_every = 1000;
  batched.flush_interval = 1e9;
  TrajectoryWriter b(dir.file("b.h5"), batched);
  appendStep(b, s);
  EXPECT_EQ(b.committedSteps(), 0);
  expectSteps(dir.file("b.h5"), 0, Extent::kReserved);
  b.finish();
  expectSteps(dir.file("b.h5"), 1);
}

TEST(TrajectoryWriter, SigkillLeavesAReadableFileWithEveryCommittedStep) {
  TempDir dir;
  const std::string path = dir.file("killed.h5");
  constexpr int chunk_rows = 16;
  const long reported = runAndKill(path, 1, chunk_rows, 25, 3000);
  ASSERT_GE(reported, 25);
  EXPECT_EQ(TrajectoryWriter::readStatus(path), "running");
  const long rows = TrajectoryWriter::readSteps(path);
  EXPECT_GE(rows, reported);
  // The file grew with the run: at most the chunk being filled and the one a growth was adding.
  const long extent = h5::File::openRead(path).readMatrix("/time").rows();
  EXPECT_GE(extent, rows);
  EXPECT_LE(extent, rows + 2 * chunk_rows);
  expectSteps(path, rows, Extent::kReserved, 1);
  const std::string python = pythonWithH5py();
  if (python.empty())
    std::cout << "python3 with h5py not found: skipping the h5py cross-check\n";
  else
    EXPECT_EQ(checkWithH5py(python, dir, path, "running", reported), 0);
}

// Many kills at random moments, with and without batching, while the datasets grow every row or
// every 16 rows: every file opens (as a SWMR reader) and is consistent. NMDP_KILL_TRIALS overrides
// the number of kills (default 200); every failing trial is counted, and so are the growths the
// killed runs made.
TEST(TrajectoryWriter, RepeatedSigkillsAtRandomMoments) {
  TempDir dir;
  const char* env = std::getenv("NMDP_KILL_TRIALS");
  const int trials = env ? std::atoi(env) : 200;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> delay(0, 20000);
  int failures = 0, files_that_grew = 0;
  long growths = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const std::string path = dir.file("kill" + std::to_string(trial) + ".h5");
    const int flush_every = trial % 3 == 2 ? 50 : 1;
    const int chunk_rows = trial % 2 == 0 ? 1 : 16;
    const int parts_before = ::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count();
    const long reported = runAndKill(path, flush_every, chunk_rows, 10, delay(rng));
    [&] {
      ASSERT_GE(reported, 10);
      ASSERT_EQ(TrajectoryWriter::readStatus(path), "running");
      const long rows = TrajectoryWriter::readSteps(path);
      ASSERT_GE(rows, reported);
      expectSteps(path, rows, Extent::kReserved, flush_every);
      const long extent = datasetInfo(path, "/time").dims.at(0);
      growths += extent / chunk_rows - 1;
      files_that_grew += extent > chunk_rows;
    }();
    if (::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count() != parts_before) {
      ++failures;
      ADD_FAILURE() << "trial " << trial << " (flush_every " << flush_every << ", chunk_rows " << chunk_rows
                    << ") left a bad file";
      if (failures >= 5) break;
    }
    std::filesystem::remove(path);
  }
  std::cout << trials << " kills, " << failures << " bad files; " << files_that_grew << " files had grown, "
            << growths << " growths in all\n";
  RecordProperty("kills", trials);
  RecordProperty("bad_files", failures);
  RecordProperty("growths", static_cast<int>(growths));
  EXPECT_EQ(failures, 0);
  EXPECT_GE(files_that_grew, trials * 3 / 4);  // kills after 10 steps may precede a 16-row growth
}

// The cost of append() for the quadruped sizes (n = 18, C = 4), against a 0.5 ms step.
TEST(TrajectoryWriter, AppendCost) {
  TempDir dir;
  Step s;
  makeStep(1, s);
  for (int flush_every : {1, 10, 50, 100}) {
    const int steps = 20000;
    TrajectoryLayout layout;  // the default chunk_rows: the datasets grow 39 times
    layout.joint_names = quadrupedLayout().joint_names;
    layout.contact_names = quadrupedLayout().contact_names;
    layout.flush_every = flush_every;
    TrajectoryWriter w(dir.file("cost" + std::to_string(flush_every) + ".h5"), layout);
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < steps; ++i) {
      s.time = i;
      appendStep(w, s);
    }
    w.finish();
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / steps;
    std::cout << "append() with flush_every = " << flush_every << ": " << us << " us per step\n";
    RecordProperty("append_us_flush_every_" + std::to_string(flush_every), std::to_string(us));
    EXPECT_LT(us, 500.0);
  }
}

}  // namespace
}  // namespace nmdp::test
