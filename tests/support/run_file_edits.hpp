// Editing a run file in place from a test (the HDF5 C API), to make the files nmdp view must cope
// with: one written before a dataset existed, one naming a URDF that is gone, a damaged one.
#pragma once
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace nmdp::test {

class EditedRun {
 public:
  explicit EditedRun(const std::string& path) : id_(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)) {
    EXPECT_GE(id_, 0) << "cannot open " << path << " for writing";
  }
  ~EditedRun() {
    if (id_ >= 0) H5Fclose(id_);
  }
  EditedRun(const EditedRun&) = delete;
  EditedRun& operator=(const EditedRun&) = delete;

  // Removes a dataset or group if it exists.
  void remove(const std::string& name) {
    if (H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0) {
      EXPECT_GE(H5Ldelete(id_, name.c_str(), H5P_DEFAULT), 0) << name;
    }
  }
  void setRootString(const std::string& attribute, const std::string& value) {
    if (H5Aexists(id_, attribute.c_str()) > 0) H5Adelete(id_, attribute.c_str());
    const hid_t type = stringType(), space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(id_, attribute.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
    const char* raw = value.c_str();
    EXPECT_GE(H5Awrite(a, type, &raw), 0) << attribute;
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
  }
  void removeRootAttribute(const std::string& attribute) {
    if (H5Aexists(id_, attribute.c_str()) > 0) H5Adelete(id_, attribute.c_str());
  }
  void setStrings(const std::string& dataset, const std::vector<std::string>& values) {
    remove(dataset);
    const hsize_t n = values.size();
    const hid_t type = stringType(), space = H5Screate_simple(1, &n, nullptr);
    const hid_t d = H5Dcreate2(id_, dataset.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<const char*> raw;
    for (const std::string& v : values) raw.push_back(v.c_str());
    EXPECT_GE(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()), 0) << dataset;
    H5Dclose(d);
    H5Sclose(space);
    H5Tclose(type);
  }
  // Replaces a numeric dataset by one of shape `dims` holding `values` (float64).
  void setNumbers(const std::string& dataset, const std::vector<hsize_t>& dims, const std::vector<double>& values) {
    remove(dataset);
    const hid_t space = dims.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t d = H5Dcreate2(id_, dataset.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0) << dataset;
    H5Dclose(d);
    H5Sclose(space);
  }
  // Overwrites the whole of an existing numeric dataset in place (its shape unchanged).
  void overwrite(const std::string& dataset, const std::vector<double>& values) {
    const hid_t d = H5Dopen2(id_, dataset.c_str(), H5P_DEFAULT);
    EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0) << dataset;
    H5Dclose(d);
  }

 private:
  static hid_t stringType() {
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    return type;
  }
  hid_t id_;
};

}  // namespace nmdp::test
