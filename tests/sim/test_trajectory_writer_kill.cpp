// TrajectoryWriter's crash safety: a child process writing a trajectory (growing every row or
// every 16 rows) is SIGKILLed at random moments; the file must open as a SWMR reader (h5py
// swmr=True) and hold every reported step in its first /steps rows. NMDP_KILL_TRIALS=1000 runs
// more kills than the default 200. And the cost of append() against a 0.5 ms step.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <random>
#include <stdexcept>
#include <thread>

#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

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
        const long committed = w.committedRows();  // steps guaranteed on disk
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

TEST(TrajectoryWriter, SigkillLeavesAReadableFileWithEveryCommittedStep) {
  TempDir dir;
  const std::string path = dir.file("killed.h5");
  constexpr int chunk_rows = 16;
  const long reported = runAndKill(path, 1, chunk_rows, 25, 3000);
  ASSERT_GE(reported, 25);
  EXPECT_EQ(TrajectoryWriter::readStatus(path), "running");
  const long rows = TrajectoryWriter::readRows(path);
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
      const long rows = TrajectoryWriter::readRows(path);
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

// Many appends at every flush interval all reach the file: the datasets grow 39 times past the default
// chunk, and the last partial block is written by finish(). (Their cost: bench/bench_trajectory_writer.)
TEST(TrajectoryWriter, ManyAppendsAtEveryFlushIntervalAreAllStored) {
  TempDir dir;
  Step s;
  makeStep(1, s);
  for (int flush_every : {1, 10, 50, 100}) {
    const int steps = 20000;
    TrajectoryLayout layout;  // the default chunk_rows
    layout.joint_names = quadrupedLayout().joint_names;
    layout.contact_names = quadrupedLayout().contact_names;
    layout.flush_every = flush_every;
    const std::string path = dir.file("many" + std::to_string(flush_every) + ".h5");
    TrajectoryWriter w(path, layout);
    for (int i = 0; i < steps; ++i) {
      s.time = i;
      appendStep(w, s);
    }
    w.finish();
    const Dataset time = readDataset(path, "/time");
    ASSERT_TRUE(time.ok) << flush_every;
    ASSERT_EQ(time.rows(), steps) << flush_every;
    EXPECT_EQ(time.values.back(), steps - 1.0) << flush_every;
    EXPECT_EQ(statusOf(path), "complete") << flush_every;
  }
}

}  // namespace
}  // namespace nmdp::test
