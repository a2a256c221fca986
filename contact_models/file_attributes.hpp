// The checks the model-file and dataset readers (rbf_function, mlp_file, training's force_dataset)
// make on HDF5 attributes, with one message format: "<path>: attribute '<name>' of '<group>' ...".
#pragma once
#include <string>

#include "io/hdf5_file.hpp"

namespace nmdp {

class FileAttributes {
 public:
  FileAttributes(const h5::File& file, std::string path, std::string group)
      : file_(file), path_(std::move(path)), group_(std::move(group)) {}

  [[noreturn]] void fail(const std::string& what) const;  // InputError "<path>: <what>"
  // 'format_version', when present, must lie in [1, newest].
  void checkFormatVersion(int newest) const;
  double finite(const std::string& name) const;  // a finite number
  // A positive finite number; `fallback` when the attribute is absent and not required.
  double positive(const std::string& name, double fallback, bool required) const;
  int integer(const std::string& name, double lo, double hi) const;  // an integer in [lo, hi]

 private:
  const h5::File& file_;
  std::string path_, group_;
};

}  // namespace nmdp
