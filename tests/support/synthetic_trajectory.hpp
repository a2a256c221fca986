// A synthetic trajectory for the TrajectoryWriter tests: a quadruped-sized layout (n = 18, C = 4),
// step i whose every value is a function of i, and the checks of a written file against it, with
// the project's reader, the HDF5 C API and (where python3 has h5py) h5py as the README reads it.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "run_files.hpp"
#include "sim/trajectory_writer.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {

inline constexpr int kDof = 18, kContacts = 4;

inline TrajectoryLayout quadrupedLayout() {
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
inline void makeStep(long i, Step& s) {
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
inline void appendStep(TrajectoryWriter& w, const Step& s) { w.append(s.time, s.q, s.qd, s.pos, s.rpy, s.wrench, s.stats); }

// Dimensions and HDF5 type class/size of a dataset (C API).
using DatasetInfo = Dataset;
inline DatasetInfo datasetInfo(const std::string& path, const std::string& name) {
  const Dataset d = readDataset(path, name);
  EXPECT_TRUE(d.ok) << name;
  return d;
}
// Every element of a numeric dataset as double, row-major (any rank).
inline std::vector<double> readAll(const std::string& path, const std::string& name) {
  return datasetInfo(path, name).values;
}

// How long the per-step datasets of a file must be.
enum class Extent {
  kExact,     // a run that ended: len(every per-step dataset) == /steps
  kReserved,  // a running or killed run: at least /steps rows, and the rows from /steps + slack on
              // are the fill values (NaN, integers 0): the rows after /steps are visibly not data.
              // A kill during a growth may leave some datasets grown and others not yet: their
              // extents may differ (each is a valid dataset; HDF5 flushes one object at a time).
};

// Checks that /rows == rows (and /steps == rows - 1), rows [0, rows) of every dataset against makeStep, and the extent.
// `slack`: rows after /steps that may hold data already (written by a commit /steps does not count yet).
inline void expectSteps(const std::string& path, long rows, Extent extent = Extent::kExact, long slack = 0) {
  ASSERT_EQ(TrajectoryWriter::readRows(path), rows);
  // appendStep's rows are steps 0, 1, ...: the rows cover rows - 1 steps. (A kill between the
  // writes of /rows and /steps may leave /steps one commit behind.)
  if (extent == Extent::kExact)
    ASSERT_EQ(TrajectoryWriter::readSteps(path), std::max(rows - 1, 0L));
  else
    ASSERT_LE(TrajectoryWriter::readSteps(path), std::max(rows - 1, 0L));
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
inline std::string pythonWithH5py() {
  for (const char* py : {"/usr/bin/python3", "python3"})
    if (std::system((std::string(py) + " -c 'import h5py' >/dev/null 2>&1").c_str()) == 0) return py;
  return "";
}

// Runs a python script checking the file with h5py: a run that ended (status not "running") opens
// with plain h5py.File(path); a killed one as the README says, h5py.File(path, "r", swmr=True).
// Status, at least min_rows complete steps in /steps, every per-step dataset /steps rows long for a
// run that ended and at least that otherwise, values of every row below /steps.
inline int checkWithH5py(const std::string& python, const TempDir& dir, const std::string& path, const std::string& status,
                  long min_rows) {
  const std::string script = dir.write("check.py", R"(import sys, h5py, numpy as np
path, status, min_rows = sys.argv[1], sys.argv[2], int(sys.argv[3])
with h5py.File(path, "r", swmr=(status == "running")) as f:
    got = f["status"][()].decode()
    assert got == status, got
    n = int(f["rows"][()])
    assert f["rows"].shape == () and f["rows"].dtype == np.int64 and f["steps"].dtype == np.int64
    assert int(f["steps"][()]) == max(n - 1, 0), (int(f["steps"][()]), n)
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
inline std::vector<std::string> filesIn(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace nmdp::test
