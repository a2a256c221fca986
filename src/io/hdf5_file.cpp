#include "io/hdf5_file.hpp"

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"
#include "io/hdf5_handle.hpp"
#include "io/output_path.hpp"

namespace nmdp::h5 {

namespace {
[[noreturn]] void fail(const std::string& file, const std::string& what) { throw InputError(displayPath(file) + ": " + what); }

// HDF5 files nmdp reads (model files, datasets, trajectories): the largest real one is a few MB.
constexpr std::uintmax_t kMaxHdf5FileBytes = std::uintmax_t{16} << 30;  // 16 GiB
// Strings read from a file (names, settings, configuration text).
constexpr size_t kMaxStringBytes = size_t{64} << 20;
constexpr hssize_t kMaxStrings = 1 << 20;

// The number of elements of a dataset's or attribute's dataspace (-1 if it cannot be read).
hssize_t elementCount(hid_t space) { return space < 0 ? -1 : H5Sget_simple_extent_npoints(space); }
}  // namespace

File::File(long long id, std::string path, std::string final_path)
    : id_(id), path_(std::move(path)), final_path_(std::move(final_path)) {}

File::File(File&& other) noexcept : id_(other.id_), path_(std::move(other.path_)), final_path_(std::move(other.final_path_)) {
  other.id_ = -1;
  other.final_path_.clear();
}

File::~File() {
  if (id_ >= 0) H5Fclose(id_);
  if (!final_path_.empty()) std::remove(path_.c_str());
}

File File::openRead(const std::string& path) {
  silenceHdf5();
  requireRegularFile(path, "HDF5 file", kMaxHdf5FileBytes);
  if (H5Fis_hdf5(path.c_str()) <= 0) fail(path, "not an HDF5 file");
  const hid_t id = openReadOnly(path);
  if (id < 0) fail(path, "cannot open the HDF5 file");
  return File(id, path, "");
}

File File::createAtomic(const std::string& path) {
  silenceHdf5();
  for (int attempt = 0;; ++attempt) {
    const std::string partial = temporaryPathFor(path);
    const hid_t id = H5Fcreate(partial.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT);
    if (id < 0) {
      if (pathExists(partial) && attempt < 100) continue;  // another writer took the name meanwhile
      fail(path, "cannot create the file (is the folder writable?)");
    }
    File file(id, partial, path);
    file.writeStringAttribute("/", "nmdp_output", "nmdp");  // the marker of io/output_path.hpp
    return file;
  }
}

bool File::exists(const std::string& object) const {
  // Check every prefix: H5Lexists fails on a missing intermediate group.
  size_t pos = 0;
  while ((pos = object.find('/', pos + 1)) != std::string::npos) {
    if (H5Lexists(id_, object.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return H5Lexists(id_, object.c_str(), H5P_DEFAULT) > 0;
}

Eigen::MatrixXd File::readMatrix(const std::string& dataset, std::int64_t max_values) const {
  const Array a = readArray(dataset, max_values);
  const int rank = static_cast<int>(a.shape.size());
  if (rank < 1 || rank > 2) fail(path_, "dataset '" + dataset + "' must be 1-D or 2-D, it has rank " + std::to_string(rank));
  const Eigen::Index rows = static_cast<Eigen::Index>(a.shape[0]);
  const Eigen::Index cols = rank == 2 ? static_cast<Eigen::Index>(a.shape[1]) : 1;
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(a.values.data(), rows, cols);
}

File::Array File::readArray(const std::string& dataset, std::int64_t max_values) const {
  if (max_values < 0 || max_values > limits::kMaxArrayEntries) max_values = limits::kMaxArrayEntries;
  if (!exists(dataset)) fail(path_, "dataset '" + dataset + "' is missing");
  Handle d{H5Dopen2(id_, dataset.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) fail(path_, "cannot open dataset '" + dataset + "'");
  Handle space{H5Dget_space(d.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank < 0 || rank > 4) fail(path_, "dataset '" + dataset + "' must have rank 0 to 4, it has rank " + std::to_string(rank));
  Handle type{H5Dget_type(d.id), H5Tclose};
  const H5T_class_t type_class = H5Tget_class(type.id);
  if (type_class != H5T_FLOAT && type_class != H5T_INTEGER)
    fail(path_, "dataset '" + dataset + "' is not numeric (expected floating-point or integer values)");
  const hssize_t count = elementCount(space.id);
  if (count < 0 || count > max_values)
    fail(path_, "dataset '" + dataset + "' has " + std::to_string(count) + " values, more than the " + std::to_string(max_values) +
                    (max_values == limits::kMaxArrayEntries ? " an array may have" : " it may hold"));
  hsize_t dims[4] = {0, 0, 0, 0};
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  Array out;
  for (int k = 0; k < rank; ++k) out.shape.push_back(static_cast<std::int64_t>(dims[k]));
  out.values.resize(static_cast<size_t>(count));
  if (count > 0 && H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data()) < 0)
    fail(path_, "dataset '" + dataset + "' is not numeric");
  return out;
}

std::string File::readString(const std::string& dataset) const {
  if (!exists(dataset)) fail(path_, "dataset '" + dataset + "' is missing");
  Handle d{H5Dopen2(id_, dataset.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) fail(path_, "cannot open dataset '" + dataset + "'");
  Handle space{H5Dget_space(d.id), H5Sclose};
  Handle stored{H5Dget_type(d.id), H5Tclose};
  if (H5Tget_class(stored.id) != H5T_STRING) fail(path_, "dataset '" + dataset + "' is not a string");
  if (elementCount(space.id) != 1)
    fail(path_, "dataset '" + dataset + "' must be one string, it holds " + std::to_string(elementCount(space.id)));
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_cset(type.id, H5Tget_cset(stored.id));  // HDF5 will not convert between UTF-8 and ASCII
  if (H5Tis_variable_str(stored.id) > 0) {
    H5Tset_size(type.id, H5T_VARIABLE);
    char* value = nullptr;
    if (H5Dread(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0) fail(path_, "cannot read dataset '" + dataset + "'");
    std::string out = value ? value : "";
    H5free_memory(value);
    if (out.size() > kMaxStringBytes) fail(path_, "dataset '" + dataset + "' holds more than " + std::to_string(kMaxStringBytes) + " bytes of text");
    return out;
  }
  const size_t size = H5Tget_size(stored.id);
  if (size == 0 || size > kMaxStringBytes) fail(path_, "dataset '" + dataset + "' is not a string of a usable size");
  std::string out(size, '\0');
  H5Tset_size(type.id, size);
  if (H5Dread(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0) fail(path_, "cannot read dataset '" + dataset + "'");
  out.resize(std::strlen(out.c_str()));
  return out;
}

std::vector<std::string> File::readStrings(const std::string& dataset) const {
  if (!exists(dataset)) fail(path_, "dataset '" + dataset + "' is missing");
  Handle d{H5Dopen2(id_, dataset.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) fail(path_, "cannot open dataset '" + dataset + "'");
  Handle space{H5Dget_space(d.id), H5Sclose};
  hsize_t n = 0;
  if (H5Sget_simple_extent_ndims(space.id) != 1) fail(path_, "dataset '" + dataset + "' must be a 1-D list of strings");
  Handle stored{H5Dget_type(d.id), H5Tclose};
  if (H5Tget_class(stored.id) != H5T_STRING) fail(path_, "dataset '" + dataset + "' is not a list of strings");
  if (elementCount(space.id) > kMaxStrings)
    fail(path_, "dataset '" + dataset + "' has more than " + std::to_string(kMaxStrings) + " strings");
  H5Sget_simple_extent_dims(space.id, &n, nullptr);
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, H5T_VARIABLE);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  std::vector<char*> raw(n, nullptr);
  if (n > 0 && H5Dread(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0)
    fail(path_, "dataset '" + dataset + "' is not a list of strings");
  std::vector<std::string> out;
  size_t total = 0;
  for (char* s : raw) {
    out.emplace_back(s ? s : "");
    total += out.back().size();
  }
  if (n > 0) H5Dvlen_reclaim(type.id, space.id, H5P_DEFAULT, raw.data());
  if (total > kMaxStringBytes) fail(path_, "dataset '" + dataset + "' holds more than " + std::to_string(kMaxStringBytes) + " bytes of text");
  return out;
}

bool File::hasAttribute(const std::string& object, const std::string& name) const {
  if (object != "/" && !exists(object)) return false;
  return H5Aexists_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string File::readStringAttribute(const std::string& object, const std::string& name) const {
  if (!hasAttribute(object, name)) fail(path_, "attribute '" + name + "' of '" + object + "' is missing");
  Handle a{H5Aopen_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  Handle stored{H5Aget_type(a.id), H5Tclose};
  if (H5Tget_class(stored.id) != H5T_STRING) fail(path_, "attribute '" + name + "' of '" + object + "' is not a string");
  Handle space{H5Aget_space(a.id), H5Sclose};
  if (elementCount(space.id) != 1)
    fail(path_, "attribute '" + name + "' of '" + object + "' must be one string, it holds " + std::to_string(elementCount(space.id)));
  if (H5Tis_variable_str(stored.id) > 0) {
    Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
    H5Tset_size(type.id, H5T_VARIABLE);
    H5Tset_cset(type.id, H5Tget_cset(stored.id));  // HDF5 will not convert between UTF-8 and ASCII
    char* value = nullptr;
    if (H5Aread(a.id, type.id, &value) < 0) fail(path_, "cannot read attribute '" + name + "' of '" + object + "'");
    std::string out = value ? value : "";
    H5free_memory(value);
    return out;
  }
  const size_t size = H5Tget_size(stored.id);
  if (size == 0 || size > kMaxStringBytes) fail(path_, "attribute '" + name + "' of '" + object + "' is not a string of a usable size");
  std::string out(size, '\0');
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, size);
  H5Tset_cset(type.id, H5Tget_cset(stored.id));
  if (H5Aread(a.id, type.id, out.data()) < 0) fail(path_, "cannot read attribute '" + name + "' of '" + object + "'");
  out.resize(std::strlen(out.c_str()));  // fixed-length strings are padded with NULs (or end at the first)
  return out;
}

double File::readDoubleAttribute(const std::string& object, const std::string& name) const {
  if (!hasAttribute(object, name)) fail(path_, "attribute '" + name + "' of '" + object + "' is missing");
  Handle a{H5Aopen_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  Handle stored{H5Aget_type(a.id), H5Tclose};
  if (H5Tget_class(stored.id) != H5T_FLOAT && H5Tget_class(stored.id) != H5T_INTEGER)
    fail(path_, "attribute '" + name + "' of '" + object + "' is not a number");
  Handle space{H5Aget_space(a.id), H5Sclose};
  if (elementCount(space.id) != 1)
    fail(path_, "attribute '" + name + "' of '" + object + "' must be one number, it holds " + std::to_string(elementCount(space.id)));
  double value = 0;
  if (H5Aread(a.id, H5T_NATIVE_DOUBLE, &value) < 0) fail(path_, "cannot read attribute '" + name + "' of '" + object + "'");
  return value;
}

void File::createGroup(const std::string& group) {
  if (exists(group)) return;
  Handle g{H5Gcreate2(id_, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  if (g.id < 0) fail(path_, "cannot create group '" + group + "'");
}

void File::writeMatrix(const std::string& dataset, const Eigen::MatrixXd& m) {
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm = m;
  const hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
  writeArray(dataset, 2, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, rm.data(), true);
}

void File::writeVector(const std::string& dataset, const Eigen::VectorXd& v) {
  const hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
  writeArray(dataset, 1, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), true);
}

void File::writeIntegerVector(const std::string& dataset, const Eigen::VectorXi& v) {
  const hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
  writeArray(dataset, 1, dims, H5T_STD_I64LE, H5T_NATIVE_INT, v.data(), v.size() > 0);
}

void File::writeArray(const std::string& dataset, int rank, const unsigned long long* dims, long long file_type,
                      long long memory_type, const void* data, bool write_data) {
  Handle space{H5Screate_simple(rank, dims, nullptr), H5Sclose};
  Handle d{H5Dcreate2(id_, dataset.c_str(), file_type, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
  if (d.id < 0 || (write_data && H5Dwrite(d.id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0))
    fail(path_, "cannot write dataset '" + dataset + "'");
}

void File::writeStrings(const std::string& dataset, const std::vector<std::string>& values) {
  const hsize_t dims[1] = {values.size()};
  Handle space{H5Screate_simple(1, dims, nullptr), H5Sclose};
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, H5T_VARIABLE);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  std::vector<const char*> raw;
  for (const std::string& s : values) raw.push_back(s.c_str());
  Handle d{H5Dcreate2(id_, dataset.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
  if (d.id < 0 || (!raw.empty() && H5Dwrite(d.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0))
    fail(path_, "cannot write dataset '" + dataset + "'");
}

void File::writeStringAttribute(const std::string& object, const std::string& name, const std::string& value) {
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, H5T_VARIABLE);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  if (hasAttribute(object, name)) H5Adelete_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT);
  Handle a{H5Acreate_by_name(id_, object.c_str(), name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  const char* raw = value.c_str();
  if (a.id < 0 || H5Awrite(a.id, type.id, &raw) < 0) fail(path_, "cannot write attribute '" + name + "' of '" + object + "'");
}

void File::writeDoubleAttribute(const std::string& object, const std::string& name, double value) {
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  if (hasAttribute(object, name)) H5Adelete_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT);
  Handle a{H5Acreate_by_name(id_, object.c_str(), name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT,
                             H5P_DEFAULT),
           H5Aclose};
  if (a.id < 0 || H5Awrite(a.id, H5T_NATIVE_DOUBLE, &value) < 0)
    fail(path_, "cannot write attribute '" + name + "' of '" + object + "'");
}

void File::flush() { H5Fflush(id_, H5F_SCOPE_GLOBAL); }

void File::commit() {
  if (id_ >= 0) H5Fclose(id_);
  id_ = -1;
  if (final_path_.empty()) return;
  std::error_code ec;
  std::filesystem::rename(path_, final_path_, ec);
  if (ec) fail(final_path_, "cannot move the finished file into place: " + ec.message());
  path_ = final_path_;
  final_path_.clear();
}

}  // namespace nmdp::h5
