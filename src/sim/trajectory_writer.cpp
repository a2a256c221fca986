#include "sim/trajectory_writer.hpp"

#include <sys/resource.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "common/input_file.hpp"
#include "io/hdf5_handle.hpp"
#include "io/output_path.hpp"

namespace nmdp {

namespace {
using h5::Handle;
using h5::silenceHdf5;

hid_t variableString() {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  return type;
}

std::string megabytes(long long bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g MB", static_cast<double>(bytes) * 1e-6);
  return text;
}

// Why `bytes` more do not fit in the file `path` (now `file_size` bytes) in `folder`, or "" if they
// do with kSpaceReserve to spare: the file system's free space for unprivileged users, and the
// process's file size limit (RLIMIT_FSIZE, `ulimit -f`).
std::string spaceShortage(const std::string& folder, long long file_size, long long bytes, long long reserve) {
  struct statvfs fs;
  if (::statvfs(folder.c_str(), &fs) == 0) {
    const long long free_bytes = static_cast<long long>(fs.f_bavail) * static_cast<long long>(fs.f_frsize);
    if (free_bytes < bytes + reserve)
      return "the disk holding " + displayPath(folder) + " has " + megabytes(free_bytes) + " free, and the next " +
             megabytes(bytes) + " of the trajectory need " + megabytes(bytes + reserve) + " with the " +
             megabytes(reserve) + " kept for ending the run";
  }
  struct rlimit limit;
  if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
      static_cast<long long>(limit.rlim_cur) < file_size + bytes + reserve)
    return "the file size limit (ulimit -f) is " + megabytes(static_cast<long long>(limit.rlim_cur)) +
           ", and the file of " + megabytes(file_size) + " needs " + megabytes(bytes + reserve) + " more";
  return "";
}
}  // namespace

void TrajectoryWriter::error(const std::string& what) const { throw InputError(path_ + ": " + what); }

namespace {
// A layout the writer cannot honour is a programming error, not bad input.
void checkLayout(const TrajectoryLayout& layout) {
  if (layout.flush_every < 1) throw std::invalid_argument("TrajectoryLayout::flush_every must be >= 1");
  if (layout.chunk_rows < 1) throw std::invalid_argument("TrajectoryLayout::chunk_rows must be >= 1");
  for (const auto& [name, value] : layout.string_attributes)
    if (name == "config" || name == "nmdp_output")
      throw std::invalid_argument("TrajectoryLayout: the attribute '" + name + "' is reserved");
  for (const auto& [name, value] : layout.number_attributes)
    if (name == "config" || name == "nmdp_output" || layout.string_attributes.count(name))
      throw std::invalid_argument("TrajectoryLayout: duplicate root attribute '" + name + "'");
}
}  // namespace

TrajectoryWriter::TrajectoryWriter(const std::string& path, const TrajectoryLayout& layout)
    : path_(path),
      n_(static_cast<int>(layout.joint_names.size())),
      C_(static_cast<int>(layout.contact_names.size())),
      flush_every_(layout.flush_every),
      flush_interval_(layout.flush_interval),
      chunk_rows_(layout.chunk_rows) {
  checkLayout(layout);
  prepareFolder(layout);
  const std::string partial = createPartialFile();
  try {
    createColumns();
    extent_ = layout.chunk_rows;
    writeDescription(layout);
    createStatusDatasets();
    writeStatus("running");
    writeSteps(0);
    // From here on HDF5 orders its metadata writes so that the file is valid whenever it stops
    // (the header comment); it flushes everything first.
    if (H5Fstart_swmr_write(file_) < 0) error("cannot start writing in SWMR mode (disk full?)");
    flushFile();
    last_commit_ = std::chrono::steady_clock::now();
  } catch (...) {
    closeAll();
    std::remove(partial.c_str());
    throw;
  }
  // Replace an existing file only now that the new one is complete (the open descriptor follows the
  // rename).
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) {
    closeAll();
    std::remove(partial.c_str());
    error("cannot move the new trajectory file into place: " + ec.message());
  }
}

void TrajectoryWriter::prepareFolder(const TrajectoryLayout& layout) {
  silenceHdf5();
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path parent = fs::absolute(fs::path(path_), ec).parent_path();
  if (ec || !fs::is_directory(parent, ec))
    error("cannot create the trajectory file: the folder " + parent.string() + " does not exist");
  if (fs::is_directory(path_, ec)) error("cannot create the trajectory file: a folder of that name exists");
  folder_ = parent.string();
  // One chunk of every per-step dataset: time, q, qdot, base position and rpy, wrench, 3 int32
  // stats, 2 float64 stats, converged.
  chunk_bytes_ = static_cast<long long>(chunk_rows_) * (8 + 16LL * n_ + 48 + 48LL * C_ + 12 + 16 + 1);
  // The metadata written with the first chunk (groups, names, attributes, the chunk indexes): a
  // generous bound, so that a file that starts always ends.
  const long long first_metadata = 64 * 1024 + 2 * static_cast<long long>(layout.config_json.size());
  if (const std::string shortage = spaceShortage(folder_, 0, chunk_bytes_ + first_metadata, kSpaceReserve);
      !shortage.empty())
    throw OutOfSpace(path_ + ": cannot start the run: " + shortage);

}

std::string TrajectoryWriter::createPartialFile() {
  // The latest format, which SWMR needs; file locking where the file system offers it. No chunk
  // cache, for every dataset (H5Fstart_swmr_write reopens the datasets with the file's default): a
  // row goes straight to its allocated place, and a flush writes the rows, not whole chunks.
  Handle fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  H5Pset_libver_bounds(fapl.id, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
  H5Pset_file_locking(fapl.id, 1, 1);
  if (H5Pset_cache(fapl.id, 0, 0, 0, 1.0) < 0) error("cannot configure the HDF5 chunk cache");
  // Paged file space: every metadata block smaller than a page lies within one 4 kB page.
  Handle fcpl{H5Pcreate(H5P_FILE_CREATE), H5Pclose};
  H5Pset_file_space_strategy(fcpl.id, H5F_FSPACE_STRATEGY_PAGE, 0, 1);
  H5Pset_file_space_page_size(fcpl.id, 4096);
  std::string partial;
  for (int attempt = 0; file_ < 0; ++attempt) {
    partial = temporaryPathFor(path_);
    file_ = H5Fcreate(partial.c_str(), H5F_ACC_EXCL, fcpl.id, fapl.id);
    if (file_ < 0 && !(pathExists(partial) && attempt < 100))
      error("cannot create the trajectory file (is the folder writable?)");
  }
  return partial;
}

void TrajectoryWriter::createColumn(Column& c, const char* name, long long file_type, long long mem_type, int rank,
                                    unsigned long long d1, unsigned long long d2) {
  const hsize_t chunk_rows = static_cast<hsize_t>(chunk_rows_);
  // Every per-step dataset: chunked, rows unlimited; its first chunk allocated and filled now (NaN
  // for float64, 0 for integers), and so is every chunk growth adds.
  Handle dapl{H5Pcreate(H5P_DATASET_ACCESS), H5Pclose};
  if (H5Pset_chunk_cache(dapl.id, 0, 0, 1.0) < 0) error("cannot configure the HDF5 chunk cache");
  c.rank = rank;
  c.memtype = mem_type;
  c.dims[0] = chunk_rows;
  c.dims[1] = d1;
  c.dims[2] = d2;
  hsize_t maxdims[3] = {H5S_UNLIMITED, d1, d2}, chunk[3] = {chunk_rows, std::max<hsize_t>(d1, 1), std::max<hsize_t>(d2, 1)};
  for (int i = 1; i < rank; ++i)
    if (c.dims[i] == 0) maxdims[i] = H5S_UNLIMITED;  // a zero-size fixed dimension cannot be chunked
  Handle space{H5Screate_simple(rank, c.dims, maxdims), H5Sclose};
  Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  H5Pset_chunk(dcpl.id, rank, chunk);
  H5Pset_alloc_time(dcpl.id, H5D_ALLOC_TIME_EARLY);
  H5Pset_fill_time(dcpl.id, H5D_FILL_TIME_ALLOC);
  H5Pset_obj_track_times(dcpl.id, 0);  // no modification time to update
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const long long zero = 0;
  if (H5Tget_class(file_type) == H5T_FLOAT ? H5Pset_fill_value(dcpl.id, H5T_NATIVE_DOUBLE, &nan) < 0
                                            : H5Pset_fill_value(dcpl.id, H5T_NATIVE_LLONG, &zero) < 0)
    error(std::string("cannot set the fill value of '") + name + "'");
  c.dataset = H5Dcreate2(file_, name, file_type, space.id, H5P_DEFAULT, dcpl.id, dapl.id);
  if (c.dataset < 0) error(std::string("cannot create dataset '") + name + "' (disk full?)");
  c.filespace = H5Dget_space(c.dataset);
  hsize_t block[3] = {static_cast<hsize_t>(flush_every_), d1, d2};
  c.memspace = H5Screate_simple(rank, block, nullptr);
  c.row_bytes = H5Tget_size(mem_type) * (rank > 1 ? d1 : 1) * (rank > 2 ? d2 : 1);
  c.rows.assign(c.row_bytes * static_cast<size_t>(flush_every_), 0);
}

void TrajectoryWriter::createColumns() {
  for (const char* g : {"/base", "/contacts", "/stats"}) {
    Handle group{H5Gcreate2(file_, g, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    if (group.id < 0) error(std::string("cannot create group '") + g + "'");
  }
  createColumn(data_[kQ], "/q", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, n_, 0);
  createColumn(data_[kQd], "/qdot", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, n_, 0);
  createColumn(data_[kBasePos], "/base/position", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, 3, 0);
  createColumn(data_[kBaseRpy], "/base/rpy", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, 3, 0);
  createColumn(data_[kWrench], "/contacts/wrench", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 3, C_, 6);
  createColumn(data_[kOuter], "/stats/outer_iterations", H5T_STD_I32LE, H5T_NATIVE_INT, 1, 0, 0);
  createColumn(data_[kGEval], "/stats/g_evaluations", H5T_STD_I32LE, H5T_NATIVE_INT, 1, 0, 0);
  createColumn(data_[kSub], "/stats/substeps", H5T_STD_I32LE, H5T_NATIVE_INT, 1, 0, 0);
  createColumn(data_[kMinSub], "/stats/min_substep", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, 0, 0);
  createColumn(data_[kWall], "/stats/wall_time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, 0, 0);
  createColumn(data_[kErr], "/stats/error_estimate", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, 0, 0);
  createColumn(data_[kConv], "/stats/converged", H5T_STD_U8LE, H5T_NATIVE_UINT8, 1, 0, 0);
  createColumn(data_[kTime], "/time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, 0, 0);

}

void TrajectoryWriter::writeDescription(const TrajectoryLayout& layout) {
  auto writeNames = [&](const char* name, const std::vector<std::string>& values) {
    const hsize_t dims[1] = {values.size()};
    Handle space{H5Screate_simple(1, dims, nullptr), H5Sclose};
    Handle type{variableString(), H5Tclose};
    std::vector<const char*> raw;
    for (const std::string& s : values) raw.push_back(s.c_str());
    Handle d{H5Dcreate2(file_, name, type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
    if (d.id < 0 || (!raw.empty() && H5Dwrite(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0))
      error(std::string("cannot write dataset '") + name + "'");
  };
  writeNames("/joint_names", layout.joint_names);
  writeNames("/contacts/names", layout.contact_names);

  auto stringAttribute = [&](const std::string& name, const std::string& value) {
    Handle type{variableString(), H5Tclose};
    Handle space{H5Screate(H5S_SCALAR), H5Sclose};
    Handle a{H5Acreate2(file_, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    const char* raw = value.c_str();
    if (a.id < 0 || H5Awrite(a.id, type.id, &raw) < 0) error("cannot write root attribute '" + name + "'");
  };
  stringAttribute("config", layout.config_json);
  stringAttribute("nmdp_output", "trajectory");
  for (const auto& [name, value] : layout.string_attributes) stringAttribute(name, value);
  for (const auto& [name, value] : layout.number_attributes) {
    Handle space{H5Screate(H5S_SCALAR), H5Sclose};
    Handle a{H5Acreate2(file_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    if (a.id < 0 || H5Awrite(a.id, H5T_NATIVE_DOUBLE, &value) < 0) error("cannot write root attribute '" + name + "'");
  }
}

void TrajectoryWriter::createStatusDatasets() {
  // /status and /steps: contiguous and allocated now, so each update rewrites the same bytes in place.
  status_type_ = H5Tcopy(H5T_C_S1);
  H5Tset_size(status_type_, kStatusBytes);
  H5Tset_strpad(status_type_, H5T_STR_NULLTERM);
  H5Tset_cset(status_type_, H5T_CSET_UTF8);
  {
    Handle space{H5Screate(H5S_SCALAR), H5Sclose};
    Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    H5Pset_layout(dcpl.id, H5D_CONTIGUOUS);
    H5Pset_alloc_time(dcpl.id, H5D_ALLOC_TIME_EARLY);
    H5Pset_obj_track_times(dcpl.id, 0);
    status_dataset_ = H5Dcreate2(file_, "/status", status_type_, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT);
    if (status_dataset_ < 0) error("cannot create dataset '/status'");
    steps_dataset_ = H5Dcreate2(file_, "/steps", H5T_STD_I64LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT);
    if (steps_dataset_ < 0) error("cannot create dataset '/steps'");
  }
  status_buffer_.assign(kStatusBytes, '\0');
  wrench_buffer_.assign(static_cast<size_t>(C_) * 6, 0.0);
}

TrajectoryWriter::~TrajectoryWriter() {
  if (file_ < 0) return;
  try {
    end("");  // status stays "running": the run did not finish
  } catch (...) {
  }
  closeAll();
}

void TrajectoryWriter::closeAll() noexcept {
  for (Column& c : data_) {
    if (c.dataset >= 0) H5Dclose(c.dataset);
    if (c.memspace >= 0) H5Sclose(c.memspace);
    if (c.filespace >= 0) H5Sclose(c.filespace);
    c.dataset = c.memspace = c.filespace = -1;
  }
  if (status_dataset_ >= 0) H5Dclose(status_dataset_);
  if (steps_dataset_ >= 0) H5Dclose(steps_dataset_);
  if (status_type_ >= 0) H5Tclose(status_type_);
  status_dataset_ = steps_dataset_ = status_type_ = -1;
  if (file_ >= 0) H5Fclose(file_);
  file_ = -1;
}

void TrajectoryWriter::flushFile() {
  if (H5Fflush(file_, H5F_SCOPE_LOCAL) < 0) error("cannot flush the trajectory file (disk full?)");
}

void TrajectoryWriter::stage(Column& c, const void* row) {
  if (c.row_bytes == 0) return;  // e.g. no contacts: row is then an empty vector's null data()
  std::memcpy(c.rows.data() + static_cast<size_t>(pending_) * c.row_bytes, row, c.row_bytes);
}

void TrajectoryWriter::writeRows(Column& c) {
  const hsize_t first = static_cast<hsize_t>(rows_ - pending_), count_rows = static_cast<hsize_t>(pending_);
  const hsize_t start[3] = {first, 0, 0}, zero[3] = {0, 0, 0}, count[3] = {count_rows, c.dims[1], c.dims[2]};
  herr_t status = H5Sselect_hyperslab(c.filespace, H5S_SELECT_SET, start, nullptr, count, nullptr);
  if (status >= 0 && count_rows != c.memspace_rows) {  // the memory selection changes only with the count
    status = H5Sselect_hyperslab(c.memspace, H5S_SELECT_SET, zero, nullptr, count, nullptr);
    c.memspace_rows = count_rows;
  }
  if (status >= 0 && count_rows * c.row_bytes > 0)
    status = H5Dwrite(c.dataset, c.memtype, c.memspace, c.filespace, H5P_DEFAULT, c.rows.data());
  if (status < 0) error("cannot write a trajectory row (disk full?)");
}

void TrajectoryWriter::append(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot,
                              const Vec3& base_position, const Vec3& base_rpy, const std::vector<Vec6>& contact_wrench,
                              const StepStats& stats) {
  if (file_ < 0) throw std::logic_error("TrajectoryWriter::append after finish() or fail()");
  if (q.size() != n_ || qdot.size() != n_ || static_cast<int>(contact_wrench.size()) != C_)
    throw std::invalid_argument("TrajectoryWriter::append: q, qdot must have " + std::to_string(n_) +
                                " entries and contact_wrench " + std::to_string(C_));
  if (rows_ == extent_) grow();  // before anything of this step is staged: OutOfSpace leaves no trace
  for (int c = 0; c < C_; ++c) std::copy(contact_wrench[c].data(), contact_wrench[c].data() + 6, &wrench_buffer_[6 * c]);
  const unsigned char converged = stats.converged ? 1 : 0;
  stage(data_[kQ], q.data());
  stage(data_[kQd], qdot.data());
  stage(data_[kBasePos], base_position.data());
  stage(data_[kBaseRpy], base_rpy.data());
  stage(data_[kWrench], wrench_buffer_.data());
  stage(data_[kOuter], &stats.outer_iterations);
  stage(data_[kGEval], &stats.g_evaluations);
  stage(data_[kSub], &stats.substeps);
  stage(data_[kMinSub], &stats.min_substep);
  stage(data_[kWall], &stats.wall_time);
  stage(data_[kErr], &stats.error_estimate);
  stage(data_[kConv], &converged);
  stage(data_[kTime], &time);
  ++rows_;
  if (++pending_ == flush_every_ ||
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_commit_).count() >= flush_interval_)
    commitPending();
}

void TrajectoryWriter::setExtent(long rows) {
  for (Column& c : data_) {
    c.dims[0] = static_cast<hsize_t>(rows);
    if (H5Dset_extent(c.dataset, c.dims) < 0) error("cannot resize a trajectory dataset (disk full?)");
    if (H5Sset_extent_simple(c.filespace, c.rank, c.dims, nullptr) < 0) error("cannot resize a dataspace");
  }
  extent_ = rows;
}

void TrajectoryWriter::grow() {
  haddr_t end_of_file = 0;
  H5Fget_eoa(file_, &end_of_file);
  if (const std::string shortage = spaceShortage(folder_, static_cast<long long>(end_of_file), chunk_bytes_, kSpaceReserve);
      !shortage.empty())
    throw OutOfSpace(path_ + ": " + shortage);
  // A chunk of every dataset, allocated and filled at once, its index and extent flushed (in SWMR
  // order) before any row is written there.
  setExtent(extent_ + chunk_rows_);
  flushFile();
}

void TrajectoryWriter::commitPending() {
  for (Column& c : data_) writeRows(c);
  flushFile();  // 1: the rows are on disk before /steps announces them
  writeSteps(rows_);
  pending_ = 0;
  flushFile();  // 2: the steps are committed
  last_commit_ = std::chrono::steady_clock::now();
}

void TrajectoryWriter::writeSteps(long steps) {
  const long long value = steps;
  if (H5Dwrite(steps_dataset_, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0)
    error("cannot write dataset '/steps'");
}

void TrajectoryWriter::end(const std::string& status) {
  if (pending_ > 0) commitPending();
  if (extent_ != rows_) {
    setExtent(rows_);  // the DESIGN.md 11 layout: len(/time) == /steps
    flushFile();
  }
  if (!status.empty()) {
    writeStatus(status);  // only after every step is on disk
    flushFile();
  }
}

void TrajectoryWriter::writeStatus(const std::string& status) {
  std::fill(status_buffer_.begin(), status_buffer_.end(), '\0');
  std::memcpy(status_buffer_.data(), status.data(), std::min<size_t>(status.size(), kStatusBytes - 1));
  if (H5Dwrite(status_dataset_, status_type_, H5S_ALL, H5S_ALL, H5P_DEFAULT, status_buffer_.data()) < 0)
    error("cannot write dataset '/status'");
}

void TrajectoryWriter::endOnce(const std::string& status, const char* too_late) {
  if (file_ < 0) throw std::logic_error(too_late);
  try {
    end(status);
  } catch (...) {
    closeAll();
    throw;
  }
  closeAll();
}

void TrajectoryWriter::finish() { endOnce("complete", "TrajectoryWriter::finish after finish() or fail()"); }

void TrajectoryWriter::fail(const std::string& reason) {
  endOnce("failed: " + reason, "TrajectoryWriter::fail after finish() or fail()");
}

void TrajectoryWriter::interrupt(const std::string& how) {
  endOnce("interrupted " + how, "TrajectoryWriter::interrupt after the run ended");
}

std::string TrajectoryWriter::readStatus(const std::string& path) {
  silenceHdf5();
  auto fail = [&](const std::string& what) -> std::string { throw InputError(path + ": " + what); };
  if (!pathExists(path)) fail("no such file");
  Handle file{h5::openReadOnly(path), H5Fclose};
  if (file.id < 0) fail("cannot open the HDF5 file");
  if (H5Lexists(file.id, "/status", H5P_DEFAULT) <= 0) fail("dataset '/status' is missing");
  Handle d{H5Dopen2(file.id, "/status", H5P_DEFAULT), H5Dclose};
  Handle stored{H5Dget_type(d.id), H5Tclose};
  if (d.id < 0 || H5Tget_class(stored.id) != H5T_STRING || H5Tis_variable_str(stored.id) > 0)
    fail("dataset '/status' is not a fixed-length string");
  const size_t size = H5Tget_size(stored.id);
  std::string out(size, '\0');
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, size);
  H5Tset_cset(type.id, H5Tget_cset(stored.id));
  if (H5Dread(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0) fail("cannot read dataset '/status'");
  out.resize(std::strlen(out.c_str()));
  return out;
}

long TrajectoryWriter::readSteps(const std::string& path) {
  silenceHdf5();
  auto fail = [&](const std::string& what) -> long { throw InputError(path + ": " + what); };
  if (!pathExists(path)) fail("no such file");
  Handle file{h5::openReadOnly(path), H5Fclose};
  if (file.id < 0) fail("cannot open the HDF5 file");
  if (H5Lexists(file.id, "/steps", H5P_DEFAULT) > 0) {
    Handle d{H5Dopen2(file.id, "/steps", H5P_DEFAULT), H5Dclose};
    long long value = -1;
    if (d.id < 0 || H5Dread(d.id, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0 || value < 0)
      fail("cannot read dataset '/steps'");
    return static_cast<long>(value);
  }
  if (H5Lexists(file.id, "/time", H5P_DEFAULT) <= 0) fail("neither '/steps' nor '/time' exists");
  Handle d{H5Dopen2(file.id, "/time", H5P_DEFAULT), H5Dclose};
  Handle space{d.id >= 0 ? H5Dget_space(d.id) : -1, H5Sclose};
  hsize_t dims[H5S_MAX_RANK] = {0};
  if (space.id < 0 || H5Sget_simple_extent_ndims(space.id) < 1 || H5Sget_simple_extent_dims(space.id, dims, nullptr) < 0)
    fail("cannot read the extent of '/time'");
  return static_cast<long>(dims[0]);
}

}  // namespace nmdp
