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
#include "sim/trajectory_columns.hpp"

namespace nmdp {

using namespace trajectory_columns;

namespace {
using h5::Handle;
using h5::silenceHdf5;

hid_t variableString() {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  return type;
}

// A scalar UTF-8 string attribute of `object`; false on failure.
bool writeStringAttribute(hid_t object, const std::string& name, const std::string& value) {
  Handle type{variableString(), H5Tclose};
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate2(object, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  const char* raw = value.c_str();
  return a.id >= 0 && H5Awrite(a.id, type.id, &raw) >= 0;
}

// A 1-D UTF-8 string array attribute of `object`; false on failure.
bool writeStringArrayAttribute(hid_t object, const std::string& name, const std::vector<std::string>& values) {
  const hsize_t dims[1] = {values.size()};
  Handle type{variableString(), H5Tclose};
  Handle space{H5Screate_simple(1, dims, nullptr), H5Sclose};
  Handle a{H5Acreate2(object, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  std::vector<const char*> raw;
  for (const std::string& v : values) raw.push_back(v.c_str());
  return a.id >= 0 && (raw.empty() || H5Awrite(a.id, type.id, raw.data()) >= 0);
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
  if (!layout.coordinate_units.empty() && layout.coordinate_units.size() != layout.joint_names.size())
    throw std::invalid_argument("TrajectoryLayout::coordinate_units must be empty or one per joint name");
  if (layout.feature_names.empty() || layout.feature_units.size() != layout.feature_names.size() ||
      layout.feature_descriptions.size() != layout.feature_names.size())
    throw std::invalid_argument("TrajectoryLayout: feature names, units and descriptions must be one per feature (at least one)");
  if (layout.mesh_paths.size() != layout.mesh_files.size())
    throw std::invalid_argument("TrajectoryLayout: mesh_paths must be one per mesh file");
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
      F_(static_cast<int>(layout.feature_names.size())),
      L_(static_cast<int>(layout.link_names.size())),
      flush_every_(layout.flush_every),
      flush_interval_(layout.flush_interval),
      chunk_rows_(layout.chunk_rows) {
  checkLayout(layout);
  data_.resize(kColumnCount);
  partial_row_.resize(layout);
  prepareFolder(layout);
  const std::string partial = createPartialFile();
  try {
    createColumns(layout);
    extent_ = layout.chunk_rows;
    writeDescription(layout);
    createStatusDatasets();
    writeStatus("running");
    writeCounters(0, 0);
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
  // One chunk of every per-step dataset.
  long long row_bytes = 0;
  for (int k = 0; k < kColumnCount; ++k) {
    const ColumnSpec& spec = kColumns[k];
    const ColumnDims dims = columnDims(spec.shape, n_, C_, F_, L_);
    row_bytes += static_cast<long long>(elementBytes(spec.type) * (dims.rank > 1 ? dims.d1 : 1) * (dims.rank > 2 ? dims.d2 : 1));
  }
  chunk_bytes_ = static_cast<long long>(chunk_rows_) * row_bytes;
  // The metadata written with the first chunk (groups, names, attributes, the chunk indexes): a
  // generous bound, so that a file that starts always ends.
  const long long first_metadata = 64 * 1024 + 2 * static_cast<long long>(layout.config_json.size() +
                                                                          layout.urdf_text.size() +
                                                                          layout.terrain_description.size());
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

void TrajectoryWriter::createColumns(const TrajectoryLayout& layout) {
  for (const char* g : {"/base", "/contacts", "/joints", "/energy", "/links", "/stats", "/model", "/terrain"}) {
    Handle group{H5Gcreate2(file_, g, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    if (group.id < 0) error(std::string("cannot create group '") + g + "'");
  }
  for (int k = 0; k < kColumnCount; ++k) {
    const ColumnSpec& spec = kColumns[k];
    const ColumnDims dims = columnDims(spec.shape, n_, C_, F_, L_);
    const hid_t file_type = spec.type == ColumnType::kF64   ? H5T_IEEE_F64LE
                            : spec.type == ColumnType::kI32 ? H5T_STD_I32LE
                                                            : H5T_STD_U8LE;
    const hid_t mem_type = spec.type == ColumnType::kF64   ? H5T_NATIVE_DOUBLE
                           : spec.type == ColumnType::kI32 ? H5T_NATIVE_INT
                                                           : H5T_NATIVE_UINT8;
    Column& c = data_[static_cast<size_t>(k)];
    createColumn(c, spec.path, file_type, mem_type, dims.rank, dims.d1, dims.d2);
    c.source = spec.source;
    const std::vector<std::string> units = columnUnits(spec, layout, n_);
    bool ok = writeStringAttribute(c.dataset, "units", units.empty() ? spec.units : joined(units)) &&
              writeStringAttribute(c.dataset, "description", spec.description) &&
              (units.empty() || writeStringArrayAttribute(c.dataset, "column_units", units)) &&
              (*spec.frame == '\0' || writeStringAttribute(c.dataset, "frame", spec.frame));
    if (ok && spec.unit_kind == UnitKind::kFeatures)
      ok = writeStringArrayAttribute(c.dataset, "names", layout.feature_names) &&
           writeStringArrayAttribute(c.dataset, "descriptions", layout.feature_descriptions);
    if (!ok) error(std::string("cannot write the attributes of '") + spec.path + "'");
  }
}

void TrajectoryWriter::writeDescription(const TrajectoryLayout& layout) {
  auto describe = [&](hid_t d, const char* name, const std::string& description) {
    if (!writeStringAttribute(d, "units", "1") || !writeStringAttribute(d, "description", description))
      error(std::string("cannot write the attributes of '") + name + "'");
  };
  auto writeNames = [&](const char* name, const std::vector<std::string>& values, const std::string& description) {
    const hsize_t dims[1] = {values.size()};
    Handle space{H5Screate_simple(1, dims, nullptr), H5Sclose};
    Handle type{variableString(), H5Tclose};
    std::vector<const char*> raw;
    for (const std::string& s : values) raw.push_back(s.c_str());
    Handle d{H5Dcreate2(file_, name, type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
    if (d.id < 0 || (!raw.empty() && H5Dwrite(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0))
      error(std::string("cannot write dataset '") + name + "'");
    describe(d.id, name, description);
  };
  auto writeText = [&](const char* name, const std::string& value, const std::string& description) {
    if (value.empty()) return;
    Handle space{H5Screate(H5S_SCALAR), H5Sclose};
    Handle type{variableString(), H5Tclose};
    const char* raw = value.c_str();
    Handle d{H5Dcreate2(file_, name, type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
    if (d.id < 0 || H5Dwrite(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, &raw) < 0)
      error(std::string("cannot write dataset '") + name + "'");
    describe(d.id, name, description);
  };
  writeNames("/joint_names", layout.joint_names, "Names of /q's columns (and of every per-coordinate dataset's).");
  writeNames("/contacts/names", layout.contact_names, "Names of the contacts, the rows of every /contacts dataset.");
  writeNames("/links/names", layout.link_names, "Names of the URDF links of /links/position and /links/quaternion.");
  writeText("/model/urdf", layout.urdf_text, "The URDF text the run used.");
  writeText("/model/urdf_path", layout.urdf_path, "The absolute path the URDF was read from.");
  if (!layout.urdf_text.empty()) {
    writeNames("/model/mesh_files", layout.mesh_files, "Every distinct filename of the URDF's <mesh> elements, as written there.");
    writeNames("/model/mesh_paths", layout.mesh_paths,
               "Each of /model/mesh_files resolved to an absolute path as the URDF loader resolves it (\"\" when not found).");
  }
  writeText("/terrain/description", layout.terrain_description,
            "JSON of the resolved terrain object (a heightfield's heights inlined in place of its file), which the "
            "scene key `terrain` accepts as it is.");

  if (!writeStringAttribute(file_, "config", layout.config_json)) error("cannot write root attribute 'config'");
  if (!writeStringAttribute(file_, "nmdp_output", "trajectory")) error("cannot write root attribute 'nmdp_output'");
  for (const auto& [name, value] : layout.string_attributes)
    if (!writeStringAttribute(file_, name, value)) error("cannot write root attribute '" + name + "'");
  for (const auto& [name, value] : layout.number_attributes) {
    Handle space{H5Screate(H5S_SCALAR), H5Sclose};
    Handle a{H5Acreate2(file_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    if (a.id < 0 || H5Awrite(a.id, H5T_NATIVE_DOUBLE, &value) < 0) error("cannot write root attribute '" + name + "'");
  }
}

void TrajectoryWriter::createStatusDatasets() {
  // /status, /rows and /steps: contiguous and allocated now, so each update rewrites the same bytes in place.
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
    rows_dataset_ = H5Dcreate2(file_, "/rows", H5T_STD_I64LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT);
    if (rows_dataset_ < 0) error("cannot create dataset '/rows'");
    steps_dataset_ = H5Dcreate2(file_, "/steps", H5T_STD_I64LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT);
    if (steps_dataset_ < 0) error("cannot create dataset '/steps'");
  }
  const std::pair<long long, const char*> described[] = {
      {status_dataset_, "How the run ended: running (still, or killed), complete, failed: <why>, interrupted <how>."},
      {rows_dataset_, "The number of complete rows: read the first /rows rows of every per-row dataset."},
      {steps_dataset_, "Time steps of dt the complete rows cover (the t = 0 row is step 0)."}};
  for (const auto& [dataset, description] : described)
    if (!writeStringAttribute(dataset, "units", "1") || !writeStringAttribute(dataset, "description", description))
      error("cannot write the attributes of /status, /rows or /steps");
  status_buffer_.assign(kStatusBytes, '\0');
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
  if (rows_dataset_ >= 0) H5Dclose(rows_dataset_);
  if (steps_dataset_ >= 0) H5Dclose(steps_dataset_);
  if (status_type_ >= 0) H5Tclose(status_type_);
  status_dataset_ = rows_dataset_ = steps_dataset_ = status_type_ = -1;
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

void TrajectoryWriter::append(const TrajectoryRow& row) {
  if (file_ < 0) throw std::logic_error("TrajectoryWriter::append after finish() or fail()");
  const auto rowsAre = [](const auto& m, int rows, int cols) { return m.rows() == rows && m.cols() == cols; };
  if (!rowsAre(row.q, n_, 1) || !rowsAre(row.qdot, n_, 1) || !rowsAre(row.torque, n_, 1) ||
      !rowsAre(row.torque_pd, n_, 1) || !rowsAre(row.torque_feedforward, n_, 1) || !rowsAre(row.q_target, n_, 1) ||
      !rowsAre(row.qdot_target, n_, 1) || !rowsAre(row.wrench, C_, 6) || !rowsAre(row.foot_point, C_, 3) ||
      !rowsAre(row.signed_distance, C_, 1) || !rowsAre(row.features, C_, F_) || !rowsAre(row.link_position, L_, 3) ||
      !rowsAre(row.link_quaternion, L_, 4))
    throw std::invalid_argument("TrajectoryWriter::append: the row's sizes do not match the layout (n = " +
                                std::to_string(n_) + ", C = " + std::to_string(C_) + ", F = " + std::to_string(F_) +
                                ", L = " + std::to_string(L_) + "): size it with TrajectoryRow::resize");
  if (rows_ == extent_) grow();  // before anything of this row is staged: OutOfSpace leaves no trace
  for (Column& c : data_) stage(c, c.source(row));
  ++rows_;
  last_step_ = row.step;
  if (++pending_ == flush_every_ ||
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_commit_).count() >= flush_interval_)
    commitPending();
}

void TrajectoryWriter::append(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot,
                              const Vec3& base_position, const Vec3& base_rpy, const std::vector<Vec6>& contact_wrench,
                              const StepStats& stats) {
  if (q.size() != n_ || qdot.size() != n_ || static_cast<int>(contact_wrench.size()) != C_)
    throw std::invalid_argument("TrajectoryWriter::append: q, qdot must have " + std::to_string(n_) +
                                " entries and contact_wrench " + std::to_string(C_));
  TrajectoryRow& row = partial_row_;
  row.time = time;
  row.step = rows_;
  row.q = q;
  row.qdot = qdot;
  row.base_position = base_position;
  row.base_rpy = base_rpy;
  for (int c = 0; c < C_; ++c) row.wrench.row(c) = contact_wrench[static_cast<size_t>(c)].transpose();
  row.stats = stats;
  append(row);
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
  flushFile();  // 1: the rows are on disk before /rows announces them
  writeCounters(rows_, last_step_);
  pending_ = 0;
  flushFile();  // 2: the steps are committed
  last_commit_ = std::chrono::steady_clock::now();
}

void TrajectoryWriter::writeCounters(long rows, long steps) {
  const long long row_count = rows, step_count = steps;
  if (H5Dwrite(rows_dataset_, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &row_count) < 0)
    error("cannot write dataset '/rows'");
  if (H5Dwrite(steps_dataset_, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &step_count) < 0)
    error("cannot write dataset '/steps'");
}

void TrajectoryWriter::end(const std::string& status) {
  if (pending_ > 0) commitPending();
  if (extent_ != rows_) {
    setExtent(rows_);  // the DESIGN.md 11 layout: len(/time) == /rows
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

namespace {
// An int64 scalar dataset of `file`, or -1 if absent; InputError if unreadable.
long long readCounter(hid_t file, const char* name, const std::string& path) {
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0) return -1;
  Handle d{H5Dopen2(file, name, H5P_DEFAULT), H5Dclose};
  long long value = -1;
  if (d.id < 0 || H5Dread(d.id, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0 || value < 0)
    throw InputError(path + ": cannot read dataset '" + name + "'");
  return value;
}

// The rows of a trajectory file, and its /steps (-1 for files without /rows).
std::pair<long, long> readRowsAndSteps(const std::string& path) {
  silenceHdf5();
  auto fail = [&](const std::string& what) -> std::pair<long, long> { throw InputError(path + ": " + what); };
  if (!pathExists(path)) fail("no such file");
  Handle file{h5::openReadOnly(path), H5Fclose};
  if (file.id < 0) fail("cannot open the HDF5 file");
  if (const long long rows = readCounter(file.id, "/rows", path); rows >= 0) {
    const long long steps = readCounter(file.id, "/steps", path);
    if (steps < 0) fail("dataset '/steps' is missing");
    return {static_cast<long>(rows), static_cast<long>(steps)};
  }
  if (const long long rows = readCounter(file.id, "/steps", path); rows >= 0) return {static_cast<long>(rows), -1};
  if (H5Lexists(file.id, "/time", H5P_DEFAULT) <= 0) fail("neither '/rows', '/steps' nor '/time' exists");
  Handle d{H5Dopen2(file.id, "/time", H5P_DEFAULT), H5Dclose};
  Handle space{d.id >= 0 ? H5Dget_space(d.id) : -1, H5Sclose};
  hsize_t dims[H5S_MAX_RANK] = {0};
  if (space.id < 0 || H5Sget_simple_extent_ndims(space.id) < 1 || H5Sget_simple_extent_dims(space.id, dims, nullptr) < 0)
    fail("cannot read the extent of '/time'");
  return {static_cast<long>(dims[0]), -1};
}
}  // namespace

long TrajectoryWriter::readRows(const std::string& path) { return readRowsAndSteps(path).first; }

long TrajectoryWriter::readSteps(const std::string& path) {
  const auto [rows, steps] = readRowsAndSteps(path);
  return steps >= 0 ? steps : std::max(rows - 1, 0L);
}

void TrajectoryRow::resize(const TrajectoryLayout& layout) {
  const Eigen::Index n = static_cast<Eigen::Index>(layout.joint_names.size());
  const Eigen::Index C = static_cast<Eigen::Index>(layout.contact_names.size());
  const Eigen::Index F = static_cast<Eigen::Index>(layout.feature_names.size());
  const Eigen::Index L = static_cast<Eigen::Index>(layout.link_names.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  time = nan;
  step = 0;
  for (Eigen::VectorXd* v : {&q, &qdot, &torque, &torque_pd, &torque_feedforward, &q_target, &qdot_target})
    v->setConstant(n, nan);
  base_position.setConstant(nan);
  base_rpy.setConstant(nan);
  base_quaternion.setConstant(nan);
  base_chart.setConstant(nan);
  wrench.setConstant(C, 6, nan);
  foot_point.setConstant(C, 3, nan);
  signed_distance.setConstant(C, nan);
  features.setConstant(C, F, nan);
  kinetic_energy = potential_energy = nan;
  link_position.setConstant(L, 3, nan);
  link_quaternion.setConstant(L, 4, nan);
  stats = StepStats();
}

}  // namespace nmdp
