// Writes a simulation run to HDF5 step by step, in the layout of DESIGN.md 11, growing the file as
// the run goes, so that a run that is killed (SIGKILL, out of memory, power cut of the process)
// still leaves a file HDF5 opens, holding every committed step.
//
// Layout: the table kColumns in trajectory_writer.cpp (every per-row dataset with its shape, units,
// description and frame, written as the attributes `units`, `column_units` where the columns
// differ, `description` and `frame`), plus the names (/joint_names, /contacts/names, /links/names),
// /model/*, /terrain/description, /status, /rows and /steps; README "Usage" lists them all.
//   /rows    int64 scalar — THE row count: read /rows rows. len(/time) equals it for every run that
//            ended (finish(), fail() or the destructor); a killed run keeps R ≥ /rows rows, NaN (0
//            in integer datasets) after /rows
//   /steps   int64 scalar — the time steps of dt the committed rows cover (TrajectoryRow::step of
//            the last committed row): 1000 for a run of 1000 steps, whose 1001 rows include t = 0
//   /status  scalar fixed-length string (kStatusBytes, NUL-terminated): "running" while writing,
//            "complete" after finish(), "failed: <reason>" after fail(), "interrupted <how>" after
//            interrupt(); a dataset because it is rewritten in place during the run
//   root attributes: `config` (UTF-8 JSON text of the resolved scene), `nmdp_output` = "trajectory"
//   (the marker of io/output_path.hpp) and the layout's extra attributes.
// Reading (h5py):  n = int(f["rows"][()]); t = f["time"][:n]; q = f["q"][:n]; ...
// (files without /rows, older than this layout, count their rows in /steps; files without either
// hold exactly len(/time) rows).
//
// Opening: a run that ended (finish(), fail(), interrupt() or the destructor: every way but a kill) closes its
// file, which then opens like any HDF5 file (h5py.File(path)). While the writer runs, and after it
// is killed, the file is marked as open by a SWMR writer, and opens only as a SWMR reader:
// h5py.File(path, "r", swmr=True) (or H5F_ACC_SWMR_READ; `h5clear -s path` from hdf5-tools clears
// the mark for good). nmdp's own readers (readStatus, readRows, readSteps, h5::File::openRead) try both.
// The file format is HDF5 1.10's (superblock 3, extensible-array chunk index): HDF5 ≥ 1.10 reads it.
//
// Crash safety: HDF5's single-writer/multiple-reader mode (SWMR, H5Fstart_swmr_write after every
// object exists). In it, HDF5 writes metadata in dependency order (a chunk index before the extent
// that uses it, checksummed), so the file in the page cache is a valid file at every instant, and a
// SWMR reader opens it whenever the writer stops. The per-step datasets are chunked (chunk_rows rows)
// and grow by one chunk at a time: when a step needs a row beyond the R allocated, every per-step
// dataset is extended by chunk_rows rows, allocated and filled with NaN (float64) or 0 (integers) at
// once (H5D_ALLOC_TIME_EARLY), and flushed before any row is written there. A step only writes
// already-allocated bytes in place (raw data; the chunk cache is disabled), and so do /steps and
// /status (contiguous, allocated at creation). A commit is ordered:
//   1. the new rows of every dataset, then H5Fflush;
//   2. /rows = number of complete rows and /steps = the step of the last of them, then H5Fflush.
// A kill at any instant therefore leaves /rows ≤ the rows really on disk (the rows after /rows, at
// most one commit's worth, may hold data, later ones are NaN/0) and each row < /rows complete.
// Verified by the test RepeatedSigkillsAtRandomMoments (random SIGKILLs, the datasets growing
// throughout). Steps after the last commit are lost (at most flush_every − 1 steps and
// flush_interval seconds, see TrajectoryLayout; with the default flush_every = 1 nothing that
// append() returned from). Flushing is write(2) to the page cache, no fsync: it protects against the
// process dying, not the machine. A file killed mid-run keeps /status = "running".
// The end: finish(), fail() and the destructor shrink every per-step dataset to the rows written
// (H5Dset_extent, still in SWMR mode, so a kill then leaves a SWMR-readable file too) so that a run
// that ended has exactly the DESIGN.md 11 layout; the rows and /rows are committed before, /status
// is written after the shrink, and closing the file clears the SWMR mark.
//
// Disk space: the file holds at most one chunk of rows beyond the steps written, about
// chunk_rows times the bytes of a row (the sum over kColumns; 1.45 MB for n = 18, C = 4,
// 13 links and chunk_rows = 512). Before each
// growth (and before creating the file, for its first chunk) the free space of the file system and
// the file size limit (RLIMIT_FSIZE) are checked against the chunk plus kSpaceReserve, the room the
// end of the run needs: a chunk that does not fit throws OutOfSpace from append() before anything is
// written (the file and the writer stay as they were, so fail() then ends the run with every step
// appended before), and from the constructor before the file exists.
//
// Creation: the file is built under a unique temporary name in the destination folder
// (io/output_path.hpp) and renamed onto `path` once every dataset exists and the first chunk is
// allocated, so an existing file is replaced only by a valid new one; a failed creation removes
// it. Errors throw InputError naming the file. append() allocates nothing in this class once
// constructed (HDF5 itself may), and nothing is ever printed.
#pragma once
#include <Eigen/Core>
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "multibody/spatial.hpp"
#include "solver/step_stats.hpp"

namespace nmdp {

struct TrajectoryLayout {
  std::vector<std::string> joint_names;    // n: the q columns' names
  // Per q column: "m" (a prismatic coordinate) or "rad"; empty: "1" for every column (unknown).
  std::vector<std::string> coordinate_units;
  std::vector<std::string> contact_names;  // C
  // F ≥ 1 columns of /contacts/features (ContactModel::featureInfo()); the default is the base class's.
  std::vector<std::string> feature_names = {"depth"}, feature_units = {"m"},
                           feature_descriptions = {"signed distance of the foot sphere to the terrain"};
  std::vector<std::string> link_names;     // L
  std::string config_json;                 // root attribute `config`
  std::map<std::string, std::string> string_attributes;  // extra root attributes, e.g. robot, method
  std::map<std::string, double> number_attributes;       // e.g. dt
  // Scalar strings written once under /model and /terrain (README "Usage"); empty: not written.
  std::string urdf_text, urdf_path, terrain_description;
  std::vector<std::string> mesh_files, mesh_paths;  // /model/mesh_files, /model/mesh_paths (M each)
  // A step reaches the disk when k = flush_every steps are pending or flush_interval seconds (wall
  // clock) passed since the last flush, whichever comes first: a kill loses at most k − 1 steps and
  // at most flush_interval seconds of work. The default 1 loses nothing that append() returned
  // from, for about 30 µs per step (n = 18, C = 4; test AppendCost), against a step of 0.5 ms or
  // more.
  int flush_every = 1;
  double flush_interval = 1.0;
  // Rows per HDF5 chunk, and the rows by which the per-step datasets grow when full.
  int chunk_rows = 512;
};

// One row of the file: the state after `step` completed time steps and what the step applied.
// Sized by resize(layout) (every value NaN); append() checks the sizes.
struct TrajectoryRow {
  template <int Cols>
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, Cols, Eigen::RowMajor>;
  double time = 0.0;  // s
  long step = 0;      // time steps of dt completed (0 for the initial state)
  Eigen::VectorXd q, qdot;                      // n
  Vec3 base_position = Vec3::Zero(), base_rpy = Vec3::Zero();
  Vec4 base_quaternion = Vec4(0, 0, 0, 1);      // x, y, z, w: the trunk's world orientation
  Vec4 base_chart = Vec4(0, 0, 0, 1);           // x, y, z, w of the chart C (multibody/base_chart.hpp)
  Rows<6> wrench;                               // C × 6
  Rows<3> foot_point;                           // C × 3
  Eigen::VectorXd signed_distance;              // C
  Rows<Eigen::Dynamic> features;                // C × F
  Eigen::VectorXd torque, torque_pd, torque_feedforward, q_target, qdot_target;  // n
  double kinetic_energy = 0.0, potential_energy = 0.0;  // J
  Rows<3> link_position;                        // L × 3
  Rows<4> link_quaternion;                      // L × 4
  StepStats stats;
  void resize(const TrajectoryLayout& layout);  // every entry NaN
};

class TrajectoryWriter {
 public:
  static constexpr int kStatusBytes = 512;  // longer failure reasons are truncated
  // Free space kept for the end of the run (its last commit, the final shrink, /status and the
  // closing metadata write a few kB) beyond each chunk: a chunk is added only if the file system
  // keeps at least this much afterwards.
  static constexpr long long kSpaceReserve = 1 << 20;

  // The next chunk does not fit on the disk (or under the file size limit); what() says so with the
  // numbers. Nothing was written: the writer can still finish() or fail().
  struct OutOfSpace : InputError {
    using InputError::InputError;
  };

  // Creates the file (see above) with status "running". Throws InputError naming `path`.
  TrajectoryWriter(const std::string& path, const TrajectoryLayout& layout);
  ~TrajectoryWriter();  // commits pending rows, shrinks to them and closes; status stays as it is
                        // ("running" if neither finish() nor fail() was called: the run did not finish)
  TrajectoryWriter(const TrajectoryWriter&) = delete;
  TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;

  // Appends one row. Sizes must match the layout (std::invalid_argument otherwise); HDF5 failures
  // throw InputError. Throws std::logic_error after finish() or fail(). When the allocated rows are
  // used up the datasets grow by a chunk first, or OutOfSpace is thrown (the row is not appended).
  void append(const TrajectoryRow& row);
  // The same for a row of which only these are known (the rest NaN), at step = the rows before it.
  void append(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot, const Vec3& base_position,
              const Vec3& base_rpy, const std::vector<Vec6>& contact_wrench, const StepStats& stats);
  void finish();                           // commit, shrink to the rows written, status "complete", close
  void fail(const std::string& reason);    // commit, shrink, status "failed: <reason>", close
  void interrupt(const std::string& how);  // commit, shrink, status "interrupted <how>", close
  bool isOpen() const { return file_ >= 0; }
  long rows() const { return rows_; }      // rows appended so far
  long committedRows() const { return rows_ - pending_; }  // rows on disk (the value of /rows)
  long allocatedRows() const { return extent_; }            // current extent of the per-step datasets
  const std::string& path() const { return path_; }

  // The /status text of a trajectory file (InputError if it cannot be read). Both readers open a
  // file that ended and one whose writer was killed (see "Opening" above).
  static std::string readStatus(const std::string& path);
  // The number of complete rows of a trajectory file: /rows; /steps for files without /rows (older
  // files counted rows there); len(/time) for files without either.
  static long readRows(const std::string& path);
  // The time steps the complete rows cover: /steps of a file with /rows; for older files
  // readRows − 1 (their rows were every step from t = 0 unless output.every > 1).
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
    const void* (*source)(const TrajectoryRow&) = nullptr;  // the row's bytes of this column
  };

  // The constructor's steps: the folder and the room for the first chunk; the file under a temporary
  // name (returned); the per-step datasets; names and attributes; /status, /rows and /steps.
  void prepareFolder(const TrajectoryLayout& layout);
  std::string createPartialFile();
  void createColumn(Column& c, const char* name, long long file_type, long long mem_type, int rank,
                    unsigned long long d1, unsigned long long d2);  // hid_t, hsize_t
  void createColumns(const TrajectoryLayout& layout);
  void writeDescription(const TrajectoryLayout& layout);
  void createStatusDatasets();
  void stage(Column& c, const void* row);  // copy into the pending rows
  void writeRows(Column& c);              // write the pending rows in place
  void setExtent(long rows);              // every per-step dataset (metadata change)
  void grow();           // check the space, extend by chunk_rows, flush
  void commitPending();  // rows, flush, /rows and /steps, flush
  void end(const std::string& status);  // commit, shrink, flush, status, flush, close
  // end(status) once: std::logic_error(too_late) if the run already ended; the file is closed after.
  void endOnce(const std::string& status, const char* too_late);
  void flushFile();
  void writeStatus(const std::string& status);
  void writeCounters(long rows, long steps);
  void closeAll() noexcept;
  [[noreturn]] void error(const std::string& what) const;

  std::string path_;
  std::string folder_;   // absolute, for the free-space checks
  long long file_ = -1;  // hid_t
  int n_ = 0, C_ = 0, F_ = 1, L_ = 0;
  int flush_every_ = 1;
  double flush_interval_ = 1.0;
  std::chrono::steady_clock::time_point last_commit_;
  int chunk_rows_ = 512;
  std::vector<Column> data_;  // one per entry of kColumns
  long long status_dataset_ = -1, status_type_ = -1, rows_dataset_ = -1, steps_dataset_ = -1;
  long rows_ = 0;        // rows appended
  long last_step_ = 0;   // TrajectoryRow::step of the last row appended
  int pending_ = 0;      // appended rows not yet written
  long extent_ = 0;      // rows of every per-step dataset (allocated)
  long long chunk_bytes_ = 0;  // file space of one chunk of every per-step dataset
  TrajectoryRow partial_row_;          // the short append()'s row
  std::vector<char> status_buffer_;    // kStatusBytes
};

}  // namespace nmdp
