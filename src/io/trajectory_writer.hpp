// Writes a simulation run to HDF5 step by step, in the layout of DESIGN.md 11, so that a run that is
// killed (SIGKILL, out of memory, power cut of the process) still leaves a file h5py opens.
//
// Layout (N steps, n = dof, C = contacts, R = reserved rows, see below):
//   /steps                  int64 scalar       — THE step count: read /steps rows. len(/time) equals
//                                                it for every run that ended (finish(), fail() or the
//                                                destructor); a killed run keeps R ≥ /steps rows,
//                                                NaN (0 in integer datasets) after /steps
//   /time                   float64 (N)
//   /q, /qdot               float64 (N × n)
//   /joint_names            variable-length UTF-8 strings (n)
//   /base/position          float64 (N × 3)    — world frame
//   /base/rpy               float64 (N × 3)
//   /contacts/wrench        float64 (N × C × 6) — [torque; force] per contact, world
//   /contacts/names         variable-length UTF-8 strings (C)
//   /stats/outer_iterations, /stats/g_evaluations, /stats/substeps   int32 (N)
//   /stats/min_substep, /stats/wall_time                             float64 (N), seconds
//   /stats/converged                                                  uint8 (N), 0 or 1
//   /status                 scalar fixed-length string (kStatusBytes, NUL-terminated): "running" while
//                           writing, "complete" after finish(), "failed: <reason>" after fail();
//                           a dataset because it is rewritten in place during the run
//   root attribute `config` (UTF-8 JSON text of the resolved scene) and the layout's extra attributes.
// Reading (h5py):  n = int(f["steps"][()]); t = f["time"][:n]; q = f["q"][:n]; ...
// (files without /steps, older than this writer, hold exactly len(/time) rows).
//
// Crash safety: NO metadata changes while the run goes. The constructor reserves
// R = TrajectoryLayout::capacity rows in every per-step dataset: full extent R from the start, all
// storage allocated at creation (chunked, H5D_ALLOC_TIME_EARLY) and filled with NaN (float64) or 0
// (integers). From then on a step only overwrites already-allocated bytes in place (raw data; the
// chunk cache is disabled so each row goes straight to its place in the file), and so do /steps and
// /status (contiguous, allocated at creation). A commit is ordered:
//   1. the new rows of every dataset, then H5Fflush;
//   2. /steps = number of complete rows, then H5Fflush.
// A kill at any instant therefore leaves the file's metadata exactly as the constructor flushed it
// (valid, checksummed, 1.8 format: superblock v2 without status flags, so plain h5py.File(path) opens
// it — no SWMR, no h5clear), /steps ≤ the rows really on disk (the rows after /steps, at most one
// commit's worth, may hold data, later ones are NaN/0), and each row < /steps complete. The metadata
// cache never evicts, so no metadata is written outside our flushes at all. Verified by the tests:
// after many appends every changed byte of the file lies in raw data (NoMetadataChangesWhileRunning),
// and random SIGKILLs (RepeatedSigkillsAtRandomMoments).
// Steps after the last commit are lost (at most flush_every − 1 steps and flush_interval seconds,
// see TrajectoryLayout; with the default flush_every = 1 nothing that append() returned from).
// Flushing is write(2) to the page cache, no fsync: it protects against the process dying, not the
// machine. A file killed mid-run keeps /status = "running".
//
// The two places metadata does change, both documented windows where a kill is NOT guaranteed safe:
//  - growth: if more than `capacity` steps are appended, the datasets are extended (by
//    max(chunk_rows, extent / 2) rows, allocated and filled at once, then flushed before any row
//    uses them) — the only mid-run metadata change; give a capacity with a margin to avoid it;
//  - the end: finish(), fail() and the destructor shrink every per-step dataset to the rows written
//    (H5Dset_extent) so a run that ended has exactly the DESIGN.md 11 layout; the rows and /steps are
//    committed before, /status is written after the shrink.
// Cost: the file holds R rows from the start (~ (16 n + 48 C + 61) bytes per row), written once as
// fill at creation. Space freed by the final shrink is not always returned to the file system
// (h5repack compacts a file).
//
// Creation: the file is built as `path + ".partial"` and renamed onto `path` only once every dataset
// exists, so an existing file is replaced only by a valid new one. Errors throw InputError naming
// the file. append() allocates nothing in this class once constructed (HDF5 itself may), and nothing
// is ever printed.
#pragma once
#include <Eigen/Core>
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "multibody/spatial.hpp"
#include "solver/integrator_types.hpp"

namespace nmdp {

struct TrajectoryLayout {
  std::vector<std::string> joint_names;    // n
  std::vector<std::string> contact_names;  // C
  std::string config_json;                 // root attribute `config`
  std::map<std::string, std::string> string_attributes;  // extra root attributes, e.g. robot, method
  std::map<std::string, double> number_attributes;       // e.g. dt
  // Rows reserved in every per-step dataset at creation (see the header comment). Set it to the
  // number of rows the run will append (a margin is cheap): appending more grows the datasets, the
  // only mid-run metadata change. 0 reserves nothing (every chunk is then added by growth).
  long capacity = 0;
  // A step reaches the disk when k = flush_every steps are pending or flush_interval seconds (wall
  // clock) passed since the last flush, whichever comes first: a kill loses at most k − 1 steps and
  // at most flush_interval seconds of work. Measured for n = 18, C = 4 (test AppendCost, ext4):
  // flush_every = 1 costs ~20 µs per step (12 in-place row writes, 2 H5Fflush with nothing but raw
  // data to write; it was ~100 µs when each flush grew the datasets), 10 ~2.5 µs, 50 ~0.7 µs. The
  // default 1 loses nothing that append() returned from.
  int flush_every = 1;
  double flush_interval = 1.0;
  int chunk_rows = 512;  // rows per HDF5 chunk
};

class TrajectoryWriter {
 public:
  static constexpr int kStatusBytes = 512;  // longer failure reasons are truncated

  // Creates the file (see above) with status "running". Throws InputError naming `path`.
  TrajectoryWriter(const std::string& path, const TrajectoryLayout& layout);
  ~TrajectoryWriter();  // commits pending rows, shrinks to them and closes; status stays as it is
                        // ("running" if neither finish() nor fail() was called: the run did not finish)
  TrajectoryWriter(const TrajectoryWriter&) = delete;
  TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;

  // Appends one step. Sizes must match the layout (std::invalid_argument otherwise); HDF5 failures
  // throw InputError. Throws std::logic_error after finish() or fail(). Past `capacity` steps the
  // datasets grow (a metadata change: see the header comment).
  void append(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot, const Vec3& base_position,
              const Vec3& base_rpy, const std::vector<Vec6>& contact_wrench, const StepStats& stats);
  void finish();                           // commit, shrink to the rows written, status "complete", close
  void fail(const std::string& reason);    // commit, shrink, status "failed: <reason>", close
  bool isOpen() const { return file_ >= 0; }
  long steps() const { return rows_; }     // steps appended so far
  long committedSteps() const { return rows_ - pending_; }  // steps on disk (the value of /steps)
  long reservedRows() const { return extent_; }             // current extent of the per-step datasets
  const std::string& path() const { return path_; }

  // The /status text of a trajectory file (InputError if it cannot be read).
  static std::string readStatus(const std::string& path);
  // The number of complete steps of a trajectory file: /steps, or len(/time) for files without it.
  static long readSteps(const std::string& path);

 private:
  struct Column {
    long long dataset = -1;   // hid_t
    long long memspace = -1;  // flush_every rows
    long long filespace = -1; // the dataset's dataspace (kept in step with its extent)
    unsigned long long memspace_rows = ~0ull;  // rows selected in memspace
    long long memtype = -1;   // native type (not owned)
    int rank = 1;
    unsigned long long dims[3] = {0, 0, 0};  // dims[0] = extent_
    size_t row_bytes = 0;
    std::vector<unsigned char> rows;  // flush_every rows not yet written
  };
  enum Col { kTime, kQ, kQd, kBasePos, kBaseRpy, kWrench, kOuter, kGEval, kSub, kMinSub, kWall, kConv, kNumData };

  void stage(Column& c, const void* row);  // copy into the pending rows
  void writeRows(Column& c);              // write the pending rows in place
  void setExtent(long rows);              // every per-step dataset (metadata change)
  void commitPending();  // [grow, flush,] rows, flush, /steps, flush
  void end(const std::string& status);  // commit, shrink, flush, status, flush, close
  void flushFile();
  void writeStatus(const std::string& status);
  void writeSteps(long steps);
  void closeAll() noexcept;
  [[noreturn]] void error(const std::string& what) const;

  std::string path_;
  long long file_ = -1;  // hid_t
  int n_ = 0, C_ = 0;
  int flush_every_ = 1;
  double flush_interval_ = 1.0;
  std::chrono::steady_clock::time_point last_commit_;
  int chunk_rows_ = 512;
  Column data_[kNumData];
  long long status_dataset_ = -1, status_type_ = -1, steps_dataset_ = -1;
  long rows_ = 0;     // steps appended
  int pending_ = 0;   // appended steps not yet written
  long extent_ = 0;   // rows of every per-step dataset (reserved)
  std::vector<double> wrench_buffer_;  // C × 6
  std::vector<char> status_buffer_;    // kStatusBytes
};

}  // namespace nmdp
