// Reading a run's HDF5 file as a user's tools do: numeric datasets through the HDF5 C API (any
// rank, with their stored type), the list of datasets, the complete-row count, the stored config
// and status, and the numeric datasets of the layout (DESIGN.md 11).
// tests/CMakeLists.txt gives tests no HDF5 include folder (nmdp_io links HDF5 privately); Debian
// installs the serial headers under hdf5/serial.
#pragma once
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"

namespace nmdp::test {

// A numeric dataset read as double (row-major, any rank), with its dimensions and stored type.
struct Dataset {
  bool ok = false;
  std::vector<hsize_t> dims;
  H5T_class_t type_class = H5T_NO_CLASS;
  size_t type_size = 0;
  H5T_sign_t sign = H5T_SGN_ERROR;  // integers only
  std::vector<double> values;
  long rows() const { return dims.empty() ? 0 : static_cast<long>(dims[0]); }
  size_t rowSize() const {
    size_t s = 1;
    for (size_t i = 1; i < dims.size(); ++i) s *= dims[i];
    return s;
  }
};

inline bool datasetExists(hid_t file, const std::string& name) {
  // H5Lexists needs every intermediate group to exist.
  size_t pos = 0;
  while ((pos = name.find('/', pos + 1)) != std::string::npos)
    if (H5Lexists(file, name.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0;
}

// Opens a file read-only as the README says: plainly, or as a SWMR reader (a killed writer's file).
inline hid_t openFile(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures are reported by the test
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f >= 0) return f;
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_metadata_read_attempts(fapl, 12);  // a damaged file fails instead of hanging
  const hid_t swmr = H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl);
  H5Pclose(fapl);
  return swmr;
}

inline Dataset readDataset(const std::string& path, const std::string& name) {
  Dataset out;
  const hid_t f = openFile(path);
  if (f < 0) return out;
  if (datasetExists(f, name)) {
    const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    if (d >= 0) {
      const hid_t space = H5Dget_space(d), type = H5Dget_type(d);
      out.dims.resize(std::max(0, H5Sget_simple_extent_ndims(space)));
      H5Sget_simple_extent_dims(space, out.dims.data(), nullptr);
      out.type_class = H5Tget_class(type);
      out.type_size = H5Tget_size(type);
      if (out.type_class == H5T_INTEGER) out.sign = H5Tget_sign(type);
      const hssize_t count = H5Sget_simple_extent_npoints(space);
      out.values.resize(static_cast<size_t>(std::max<hssize_t>(count, 0)));
      out.ok = out.type_class == H5T_STRING ||
               count == 0 || H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data()) >= 0;
      H5Tclose(type);
      H5Sclose(space);
      H5Dclose(d);
    }
  }
  H5Fclose(f);
  return out;
}

// Every dataset path in the file ("/time", "/base/position", ...).
inline std::set<std::string> datasetNames(const std::string& path) {
  std::set<std::string> names;
  const hid_t f = openFile(path);
  if (f < 0) return names;
  struct Visit {
    hid_t file;
    std::set<std::string>* names;
  } visit{f, &names};
  const H5L_iterate_t callback = [](hid_t, const char* name, const auto*, void* data) -> herr_t {
    Visit& v = *static_cast<Visit*>(data);
    const hid_t object = H5Oopen(v.file, name, H5P_DEFAULT);
    if (object >= 0) {
      if (H5Iget_type(object) == H5I_DATASET) v.names->insert(std::string("/") + name);
      H5Oclose(object);
    }
    return 0;
  };
  H5Lvisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, callback, &visit);
  H5Fclose(f);
  return names;
}

// The per-row datasets of a trajectory file: every chunked dataset.
inline std::vector<std::string> perRowDatasets(const std::string& path) {
  std::vector<std::string> out;
  const hid_t f = openFile(path);
  if (f < 0) return out;
  for (const std::string& name : datasetNames(path)) {
    const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    const hid_t plist = H5Dget_create_plist(d);
    if (H5Pget_layout(plist) == H5D_CHUNKED) out.push_back(name);
    H5Pclose(plist);
    H5Dclose(d);
  }
  H5Fclose(f);
  return out;
}

// The number of complete rows: the scalar /rows when the writer stores one, else /steps (older
// files counted rows there), else len(/time).
inline long completeRows(const std::string& path) {
  for (const char* counter : {"/rows", "/steps"}) {
    const Dataset rows = readDataset(path, counter);
    if (rows.ok && rows.values.size() == 1) return std::lround(rows.values[0]);
  }
  const Dataset time = readDataset(path, "/time");
  return time.ok ? time.rows() : -1;
}

inline nlohmann::json configOf(const std::string& path) {
  try {
    const h5::File file = h5::File::openRead(path);
    return nlohmann::json::parse(file.readStringAttribute("/", "config"));
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": root attribute 'config' is not readable JSON: " << e.what();
    return nlohmann::json();
  }
}

inline std::string statusOf(const std::string& path) {
  try {
    return TrajectoryWriter::readStatus(path);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
    return "<unreadable>";
  }
}

inline double maxAbsDifference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return INFINITY;
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

inline bool allFinite(const std::vector<double>& v, size_t count) {
  for (size_t i = 0; i < std::min(count, v.size()); ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

// The sizes kNumericDatasets' shapes name: coordinates, contacts, links, contact features.
enum : long { kN = -1, kC = -2, kL = -3, kF = -4 };
// The per-row numeric datasets of the layout (README "Usage") that are finite in every complete row,
// and their shapes after the row dimension. (/joints/q_target and /joints/qdot_target are NaN on
// unactuated coordinates.)
inline const std::vector<std::pair<std::string, std::vector<long>>> kNumericDatasets = {
    {"/time", {}},
    {"/q", {kN}},
    {"/qdot", {kN}},
    {"/base/position", {3}},
    {"/base/rpy", {3}},
    {"/base/quaternion", {4}},
    {"/base/chart", {4}},
    {"/contacts/wrench", {kC, 6}},
    {"/contacts/foot_point", {kC, 3}},
    {"/contacts/signed_distance", {kC}},
    {"/contacts/features", {kC, kF}},
    {"/joints/torque", {kN}},
    {"/joints/torque_pd", {kN}},
    {"/joints/torque_feedforward", {kN}},
    {"/energy/kinetic", {}},
    {"/energy/potential", {}},
    {"/links/position", {kL, 3}},
    {"/links/quaternion", {kL, 4}},
    {"/stats/outer_iterations", {}},
    {"/stats/g_evaluations", {}},
    {"/stats/substeps", {}},
    {"/stats/min_substep", {}},
    {"/stats/wall_time", {}},
    {"/stats/converged", {}},
    {"/stats/error_estimate", {}},
};

}  // namespace nmdp::test
