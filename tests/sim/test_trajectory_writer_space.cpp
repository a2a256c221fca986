// TrajectoryWriter and a full disk, with the file size limit (`ulimit -f`) standing in for it: a run
// whose first chunk does not fit is refused and leaves nothing; a chunk that does not fit later
// ends the run with every step kept, readable with h5py.
#include <sys/resource.h>

#include <csignal>
#include <string>

#include "sim/trajectory_writer.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

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
  layout.chunk_rows = 1000;  // 1.5 MB
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
  layout.chunk_rows = 200;  // 307 kB
  long appended = 0;
  std::string reason;
  {
    FileSizeLimit limit(TrajectoryWriter::kSpaceReserve + 1500 * 1024);  // a few chunks
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
    EXPECT_EQ(w.rows(), appended);  // the step that did not fit was not appended
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

}  // namespace
}  // namespace nmdp::test
