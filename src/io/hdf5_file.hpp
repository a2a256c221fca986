// A thin RAII layer over the HDF5 C API for the project's files (model files, datasets,
// trajectories). Matrices are stored row-major as 2-D float64 datasets, readable by h5py.
// Every failure throws InputError naming the file and the dataset or attribute.
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <vector>

namespace nmdp::h5 {

class File {
 public:
  // Opens an existing file for reading (also a trajectory whose writer was killed: see
  // openReadOnly in hdf5_handle.hpp).
  static File openRead(const std::string& path);
  // Creates a file under a unique temporary name beside `path` (io/output_path.hpp) with the root
  // attribute nmdp_output, the marker of files nmdp wrote; commit() renames it to `path`, so a reader
  // never sees a half-written file. Destroying an uncommitted file removes the temporary file.
  static File createAtomic(const std::string& path);
  File(File&& other) noexcept;
  File& operator=(File&&) = delete;
  File(const File&) = delete;
  ~File();

  const std::string& path() const { return path_; }
  bool exists(const std::string& object) const;  // dataset or group, e.g. "/rbf/centres"

  // 1-D datasets come back as a column. A dataset of more than `max_values` values is refused from
  // its header, before anything is allocated: a reader that knows a dataset's size passes it, so a
  // file cannot make it allocate more (the default is limits::kMaxArrayEntries).
  Eigen::MatrixXd readMatrix(const std::string& dataset, std::int64_t max_values = -1) const;
  std::vector<std::string> readStrings(const std::string& dataset) const;
  // A numeric dataset of any rank up to 4 (e.g. N × C × 6; a scalar has an empty shape), as float64 in C order, with its shape;
  // the same size check as readMatrix.
  struct Array {
    std::vector<std::int64_t> shape;
    std::vector<double> values;
  };
  Array readArray(const std::string& dataset, std::int64_t max_values = -1) const;
  // A scalar (or one-element) string dataset, e.g. a stored text.
  std::string readString(const std::string& dataset) const;
  std::string readStringAttribute(const std::string& object, const std::string& name) const;
  double readDoubleAttribute(const std::string& object, const std::string& name) const;
  bool hasAttribute(const std::string& object, const std::string& name) const;

  void createGroup(const std::string& group);
  void writeMatrix(const std::string& dataset, const Eigen::MatrixXd& m);
  void writeVector(const std::string& dataset, const Eigen::VectorXd& v);  // 1-D
  void writeIntegerVector(const std::string& dataset, const Eigen::VectorXi& v);  // 1-D int64 (read back with readMatrix)
  void writeStrings(const std::string& dataset, const std::vector<std::string>& values);
  void writeStringAttribute(const std::string& object, const std::string& name, const std::string& value);
  void writeDoubleAttribute(const std::string& object, const std::string& name, double value);

  void flush();
  void commit();  // close and move into place (atomic files only)

 private:
  // One dataset of `rank` dimensions (hsize_t dims; hid_t types, kept out of this header); the data
  // is written only when write_data (HDF5 refuses a write of zero elements from a null buffer).
  void writeArray(const std::string& dataset, int rank, const unsigned long long* dims, long long file_type,
                  long long memory_type, const void* data, bool write_data);
  File(long long id, std::string path, std::string final_path);
  long long id_ = -1;  // hid_t
  std::string path_;        // the file being accessed
  std::string final_path_;  // non-empty for atomic files until commit()
};

}  // namespace nmdp::h5
