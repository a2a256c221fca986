// How `nmdp simulate` ends when it does not complete, and what its file holds then: only completed
// steps, each what the solver converged to (/time strictly increasing, /steps = len(/time), every
// row converged and finite), /status and stderr saying why, exit code 4. Cases: a failed step
// (ne-mdp at dt 0.05), a diverged one (Solo-12 ne-mdp at dt 0.02, the issue's run: it must stop
// before the torso flies off), SIGTERM and SIGINT while stepping, SIGINT before the file exists
// (nothing is left), storage that grows with the run instead of being reserved for its duration
// (the issue's 10^14-step run starts at once and stops on SIGINT), and a full disk, before the
// first chunk (refused, nothing left) and in the middle of the run (the file size limit of
// `ulimit -f` and, where a private tmpfs can be mounted, a real small file system).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <thread>

#include "child_process.hpp"
#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;

std::string sceneFile(const std::string& name) { return sourcePath("models/scenes/" + name); }

// What an ended run's file must be: exactly /steps rows, each a converged, finite, completed step,
// time strictly increasing. Returns /time.
Eigen::VectorXd expectOnlyCompletedSteps(const std::string& path) {
  const long steps = TrajectoryWriter::readRows(path);
  const h5::File file = h5::File::openRead(path);
  const Eigen::VectorXd time = file.readMatrix("/time").col(0);
  EXPECT_EQ(time.size(), steps) << "a run that ended holds exactly /steps rows";
  EXPECT_GE(steps, 1) << "the initial state is always a row";
  for (Eigen::Index i = 1; i < time.size(); ++i) EXPECT_GT(time[i], time[i - 1]) << "row " << i << ": /time repeats";
  const Eigen::MatrixXd converged = file.readMatrix("/stats/converged");
  for (Eigen::Index i = 0; i < converged.rows(); ++i) EXPECT_EQ(converged(i, 0), 1.0) << "row " << i;
  for (const char* name : {"/time", "/q", "/qdot", "/base/position", "/base/rpy", "/stats/min_substep"}) {
    const Eigen::MatrixXd m = file.readMatrix(name);
    EXPECT_EQ(m.rows(), steps) << name;
    EXPECT_TRUE(m.allFinite()) << name << " has a non-finite row";
  }
  return time;
}

// Only `names` in the folder (no temporary file left).
void expectFolderHolds(const TempDir& dir, std::set<std::string> names) {
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("stdout_", 0) == 0 || name.rfind("stderr_", 0) == 0 || name.rfind("err_", 0) == 0) continue;
    EXPECT_TRUE(names.count(name)) << "unexpected file left: " << name;
  }
}

// A running `nmdp simulate`: its pid, stderr in a file.
struct Child {
  pid_t pid = -1;
  std::string err;
};
Child spawn(const std::vector<std::string>& args, const std::string& err) { return Child{startProcess(args, err), err}; }
bool waitFor(const std::function<bool()>& condition, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  while (!condition()) {
    if (std::chrono::steady_clock::now() - start > std::chrono::duration<double>(seconds)) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}
// Exit status after at most `seconds`; SIGKILLs and fails if the process is still running.
int exitStatus(const Child& c, double seconds) {
  int status = 0;
  if (!waitFor([&] { return ::waitpid(c.pid, &status, WNOHANG) == c.pid; }, seconds)) {
    ::kill(c.pid, SIGKILL);
    ::waitpid(c.pid, &status, 0);
    ADD_FAILURE() << "nmdp simulate did not end within " << seconds << " s; stderr: " << readText(c.err);
    return -1;
  }
  EXPECT_TRUE(WIFEXITED(status)) << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0)
                                 << " instead of stopping cleanly; stderr: " << readText(c.err);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
// Whether the process catches `signal` (its handler is installed), from /proc.
bool catches(pid_t pid, int signal) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (signal - 1)) & 1;
  return false;
}

TEST(SimulateEnding, AFailedStepEndsTheRunWithOnlyTheCompletedSteps) {
  // NE-MDP is the explicit baseline DESIGN.md 6 shows blowing up beyond ~7 ms: at dt 0.05 it fails
  // within the first second on flat ground (non-finite, or diverged by the energy check).
  TempDir dir;
  const std::string out = dir.file("failed.h5");
  const CliResult r = runNmdp({"simulate", sceneFile("quadruped_stand_flat.json"), "--set", "duration=1", "--set",
                               "integrator.method=ne-mdp", "--out", out, "--quiet"},
                              dir);
  ASSERT_TRUE(r.exited);
  ASSERT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
  EXPECT_NE(r.err.find(out), std::string::npos) << r.err;
  const std::string status = TrajectoryWriter::readStatus(out);
  EXPECT_EQ(status.rfind("failed: step ", 0), 0u) << status;
  EXPECT_NE(r.err.find(status.substr(8)), std::string::npos) << "stderr and /status give the same reason: " << r.err;
  expectOnlyCompletedSteps(out);
  expectFolderHolds(dir, {"failed.h5"});
}

// The issue's run: Solo-12 trotting with ne-mdp at dt = 0.02. From t = 0.04 the explicit method has
// blown up (torso at 0.78 m, then 8.2 m, −4147 m, each row marked converged): the energy check stops
// the run at its first unphysical step, and the file holds only the physical steps before it.
TEST(SimulateEnding, ADivergedStepIsNeverWrittenAsAConvergedRow) {
  NMDP_REQUIRE_SHARED("robots/solo12/urdf/solo12.urdf");
  TempDir dir;
  const std::string scene = dir.write("solo.json", R"({"robot": {"urdf": ")" +
                                                       sharedPath("robots/solo12/urdf/solo12.urdf") +
                                                       R"("}, "controller": {"gait": {"type": "trot"}}, "duration": 1.0})");
  const std::string out = dir.file("o.h5");
  const CliResult r = runNmdp({"simulate", scene, "--set", "integrator.method=ne-mdp", "--set", "integrator.dt=0.02",
                               "--out", out, "--quiet"},
                              dir);
  ASSERT_TRUE(r.exited);
  ASSERT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("diverged: its energy rose by"), std::string::npos) << r.err;
  const std::string status = TrajectoryWriter::readStatus(out);
  EXPECT_EQ(status.rfind("failed: step ", 0), 0u) << status;
  EXPECT_NE(status.find("diverged"), std::string::npos) << status;
  const Eigen::VectorXd time = expectOnlyCompletedSteps(out);
  EXPECT_LE(time[time.size() - 1], 0.02 + 1e-12) << "the step to t = 0.04 is not physical and must not be a row";
  const Eigen::MatrixXd position = h5::File::openRead(out).readMatrix("/base/position");
  for (Eigen::Index i = 0; i < position.rows(); ++i)
    EXPECT_LT(std::abs(position(i, 2) - position(0, 2)), 0.05) << "row " << i << ": the torso height jumped";
  std::cout << "stopped after " << time.size() << " rows: " << status << "\n";
}

TEST(SimulateEnding, SigtermWhileSteppingKeepsTheCompletedStepsUnderTheFinalName) {
  TempDir dir;
  const std::string out = dir.file("term.h5");
  const Child c = spawn({NMDP_BINARY, "simulate", sceneFile("quadruped_trot_flat.json"), "--set", "duration=1000",
                         "--out", out, "--quiet"},
                        dir.file("err_term.txt"));
  ASSERT_TRUE(waitFor([&] { return fs::exists(out); }, 20)) << readText(c.err);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(c.pid, SIGTERM);
  EXPECT_EQ(exitStatus(c, 20), 4);
  const std::string err = readText(c.err);
  ASSERT_NO_FATAL_FAILURE(expectOneLine(err, "stderr"));
  EXPECT_NE(err.find("interrupted by SIGTERM at t = "), std::string::npos) << err;
  const std::string status = TrajectoryWriter::readStatus(out);
  EXPECT_EQ(status.rfind("interrupted by SIGTERM at t = ", 0), 0u) << status;
  const Eigen::VectorXd time = expectOnlyCompletedSteps(out);
  EXPECT_GE(time.size(), 2);
  for (Eigen::Index i = 0; i < time.size(); ++i) EXPECT_NEAR(time[i], 0.05 * i, 1e-9);
  expectFolderHolds(dir, {"term.h5"});
}

// With output.every = 7 the last completed step is usually not a row yet when the run is
// interrupted: it becomes the last row, so the file ends where the run did.
TEST(SimulateEnding, SigintKeepsTheLastCompletedStepWhenRowsAreSparse) {
  TempDir dir;
  const std::string out = dir.file("int.h5");
  const Child c = spawn({NMDP_BINARY, "simulate", sceneFile("quadruped_trot_flat.json"), "--set", "duration=1000",
                         "--set", "output.every=7", "--out", out, "--quiet"},
                        dir.file("err_int.txt"));
  ASSERT_TRUE(waitFor([&] { return fs::exists(out); }, 20)) << readText(c.err);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  ::kill(c.pid, SIGINT);
  EXPECT_EQ(exitStatus(c, 20), 4);
  const std::string status = TrajectoryWriter::readStatus(out);
  ASSERT_EQ(status.rfind("interrupted by SIGINT at t = ", 0), 0u) << status;
  const Eigen::VectorXd time = expectOnlyCompletedSteps(out);
  ASSERT_GE(time.size(), 2);
  const double stopped = std::stod(status.substr(std::string("interrupted by SIGINT at t = ").size()));
  EXPECT_NEAR(time[time.size() - 1], stopped, 1e-6) << "the last row is the last completed step";
  for (Eigen::Index i = 0; i + 1 < time.size(); ++i) EXPECT_NEAR(time[i], 0.35 * i, 1e-9);
}

// A signal that arrives before the output exists ends the command at the next phase with nothing
// written. The process is stopped as soon as its handler is installed (it is then loading the
// scene or the robot), signalled, and continued.
TEST(SimulateEnding, SigintBeforeTheFileExistsLeavesNothing) {
  TempDir dir;
  const std::string out = dir.file("early.h5");
  int before_file = 0;
  for (int attempt = 0; attempt < 5 && before_file == 0; ++attempt) {
    const Child c = spawn({NMDP_BINARY, "simulate", sceneFile("robosimian_walk_planar.json"), "--out", out, "--quiet"},
                          dir.file("err_early.txt"));
    if (!waitFor([&] { return catches(c.pid, SIGINT); }, 20)) {
      ::kill(c.pid, SIGKILL);
      ::waitpid(c.pid, nullptr, 0);
      GTEST_SKIP() << "cannot see the process's signal handlers in /proc";
    }
    ::kill(c.pid, SIGSTOP);
    const bool file_exists = fs::exists(out);
    ::kill(c.pid, SIGINT);
    ::kill(c.pid, SIGCONT);
    EXPECT_EQ(exitStatus(c, 20), 4);
    const std::string err = readText(c.err);
    if (!file_exists && !fs::exists(out)) {
      ++before_file;
      EXPECT_NE(err.find("interrupted by SIGINT while "), std::string::npos) << err;
      EXPECT_NE(err.find("nothing was written"), std::string::npos) << err;
      expectFolderHolds(dir, {});
    } else {  // the run had started: an interrupted run's file
      EXPECT_EQ(TrajectoryWriter::readStatus(out).rfind("interrupted by SIGINT", 0), 0u);
      expectOnlyCompletedSteps(out);
      fs::remove(out);
    }
  }
  EXPECT_GE(before_file, 1) << "never caught the command before its file existed";
}

// The issue's run of 10^14 steps (duration 1e9 s at dt 1e-5) used to reserve a row for every step
// before the first one (54 PB: the disk filled, SIGINT went unheard, a .partial file stayed). Now the
// file starts with one chunk, grows with the run, and SIGINT ends the run at once.
TEST(SimulateEnding, StorageGrowsWithTheRunAndAHugeRunStopsOnSigint) {
  TempDir dir;
  const std::string out = dir.file("huge.h5");
  const Child c = spawn({NMDP_BINARY, "simulate", sceneFile("quadruped_trot_flat.json"), "--set", "duration=1e9",
                         "--set", "integrator.dt=1e-5", "--out", out, "--quiet"},
                        dir.file("err_huge.txt"));
  const bool appeared = waitFor([&] { return fs::exists(out); }, 10);
  if (!appeared) {
    ::kill(c.pid, SIGKILL);
    ::waitpid(c.pid, nullptr, 0);
    FAIL() << "the output did not appear within 10 s (storage reserved up front?); stderr: " << readText(c.err);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  // A chunk is 512 rows of 2.83 kB for the quadruped (1.45 MB): a few chunks, not 54 PB.
  EXPECT_LT(fs::file_size(out), 16u << 20) << "the file holds more than its first chunks";
  ::kill(c.pid, SIGINT);
  EXPECT_EQ(exitStatus(c, 10), 4);
  EXPECT_EQ(TrajectoryWriter::readStatus(out).rfind("interrupted by SIGINT", 0), 0u);
  expectOnlyCompletedSteps(out);
  expectFolderHolds(dir, {"huge.h5"});

  // A run of 200 000 steps (570 MB of rows of 2.83 kB) holds its rows and a few chunks (512 rows,
  // 1.45 MB each) after its first steps.
  const std::string long_out = dir.file("long.h5");
  const Child l = spawn({NMDP_BINARY, "simulate", sceneFile("quadruped_trot_flat.json"), "--set", "duration=10000",
                         "--out", long_out, "--quiet"},
                        dir.file("err_long.txt"));
  ASSERT_TRUE(waitFor([&] { return fs::exists(long_out); }, 20)) << readText(l.err);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const auto size = fs::file_size(long_out);
  ::kill(l.pid, SIGTERM);
  EXPECT_EQ(exitStatus(l, 20), 4);
  const long rows = TrajectoryWriter::readRows(long_out);
  std::cout << rows << " rows after 0.5 s, file " << size << " bytes while running, " << fs::file_size(long_out)
            << " after\n";
  EXPECT_LT(size, static_cast<std::uintmax_t>(3000 * rows + (4 << 20))) << "storage was reserved ahead of the run";
}

// `ulimit -f` (in 512-byte blocks) limits the file's size like a full disk: the writer checks both.
std::vector<std::string> underFileSizeLimit(long blocks, const std::vector<std::string>& args) {
  std::vector<std::string> full = {"/bin/sh", "-c", "ulimit -f " + std::to_string(blocks) + " && exec \"$0\" \"$@\"",
                                   NMDP_BINARY};
  full.insert(full.end(), args.begin(), args.end());
  return full;
}

TEST(SimulateEnding, ADiskThatCannotHoldTheFirstChunkRefusesTheRun) {
  TempDir dir;
  const std::string out = dir.file("run.h5");
  const Child c = spawn(underFileSizeLimit(1024, {"simulate", sceneFile("quadruped_trot_flat.json"), "--set",
                                                   "duration=1", "--out", out, "--quiet"}),
                        dir.file("err_small.txt"));  // 512 kB
  EXPECT_EQ(exitStatus(c, 20), 1);
  const std::string err = readText(c.err);
  ASSERT_NO_FATAL_FAILURE(expectOneLine(err, "stderr"));
  EXPECT_NE(err.find("cannot start the run"), std::string::npos) << err;
  EXPECT_NE(err.find("file size limit"), std::string::npos) << err;
  EXPECT_NE(err.find(out), std::string::npos) << err;
  expectFolderHolds(dir, {});
}

TEST(SimulateEnding, ADiskThatFillsEndsTheRunWithTheCompletedSteps) {
  TempDir dir;
  const std::string out = dir.file("run.h5");
  // 6 MB: the reserve of 1 MiB kept for the end, the first chunk (512 rows of 2.83 kB) and a
  // couple more.
  const Child c = spawn(underFileSizeLimit(12000, {"simulate", sceneFile("quadruped_trot_flat.json"), "--set",
                                                   "duration=100000", "--out", out, "--quiet"}),
                        dir.file("err_full.txt"));
  EXPECT_EQ(exitStatus(c, 120), 4);
  const std::string err = readText(c.err);
  ASSERT_NO_FATAL_FAILURE(expectOneLine(err, "stderr"));
  EXPECT_NE(err.find("the disk being full"), std::string::npos) << err;
  const std::string status = TrajectoryWriter::readStatus(out);
  EXPECT_EQ(status.rfind("failed: stopped at t = ", 0), 0u) << status;
  EXPECT_NE(status.find("file size limit"), std::string::npos) << status;
  const Eigen::VectorXd time = expectOnlyCompletedSteps(out);
  EXPECT_GE(time.size(), 1024) << "the run stopped before filling the room it had";
  expectFolderHolds(dir, {"run.h5"});
}

// The same with a real file system that fills: an 8 MB tmpfs in a private mount namespace
// (`unshare -rm`), where the free space the writer checks is the file system's own.
TEST(SimulateEnding, ASmallFileSystemFillsAndTheRunEndsCleanly) {
  if (std::system("unshare -rm true >/dev/null 2>&1") != 0) GTEST_SKIP() << "unshare -rm is not available here";
  TempDir dir;
  const std::string mount = dir.file("mnt");
  fs::create_directory(mount);
  const std::string script = dir.write(
      "run.sh", "mount -t tmpfs -o size=8m none " + shellQuote(mount) + " || exit 90\n" + shellQuote(NMDP_BINARY) +
                    " simulate " + shellQuote(sceneFile("quadruped_trot_flat.json")) +
                    " --set duration=100000 --out " + shellQuote(mount + "/run.h5") + " --quiet 2>" +
                    shellQuote(dir.file("err.txt")) + "\necho $? >" + shellQuote(dir.file("code.txt")) + "\n" +
                    // The file system lives as long as the namespace: read what a user would, here.
                    "/usr/bin/python3 -c 'import h5py,sys; f=h5py.File(sys.argv[1]); n=int(f[\"rows\"][()]); "
                    "t=f[\"time\"][:]; print(n, len(t), f[\"status\"][()].decode(), bool((t[1:]>t[:-1]).all()))' " +
                    shellQuote(mount + "/run.h5") + " >" + shellQuote(dir.file("read.txt")) + " 2>&1\n" +
                    "ls -a " + shellQuote(mount) + " >" + shellQuote(dir.file("ls.txt")) + "\n");
  const int rc = std::system(("timeout 300 unshare -rm sh " + shellQuote(script)).c_str());
  if (WIFEXITED(rc) && WEXITSTATUS(rc) == 90) GTEST_SKIP() << "cannot mount a tmpfs here";
  EXPECT_EQ(readText(dir.file("code.txt")), "4\n") << readText(dir.file("err.txt"));
  const std::string err = readText(dir.file("err.txt"));
  EXPECT_NE(err.find("the disk being full"), std::string::npos) << err;
  EXPECT_NE(err.find("free"), std::string::npos) << err;
  const std::string read = readText(dir.file("read.txt"));
  std::cout << "h5py on the full tmpfs: " << read;
  if (read.find("No module named") == std::string::npos) {
    std::istringstream in(read);
    long counted = 0, rows = 0;
    std::string word, monotonic;
    in >> counted >> rows >> word;
    EXPECT_EQ(counted, rows) << read;
    EXPECT_GT(rows, 1000) << read;
    EXPECT_EQ(word, "failed:") << read;
    EXPECT_NE(read.find("True"), std::string::npos) << read;
  }
  EXPECT_EQ(readText(dir.file("ls.txt")), ".\n..\nrun.h5\n") << "a temporary file was left";
}

}  // namespace
}  // namespace nmdp::test
