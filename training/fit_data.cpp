#include "training/fit_data.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "common/input_error.hpp"
#include "common/input_file.hpp"

namespace nmdp {

namespace {
const char* const kAcceptedData =
    "expected a force dataset (HDF5, as nmdp fit --import-csv writes), a folder in the CSV layout of "
    "granular/sand_samples (features.csv, wrench_samples.csv, scalars.txt) or a .csv file in such a folder";

// Whether the file starts with the HDF5 signature, at byte 0 or at a user block of 512, 1024, ... bytes
// (where the HDF5 library looks for it).
bool hasHdf5Signature(const std::string& path, std::uintmax_t size) {
  static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  std::ifstream in(path, std::ios::binary);
  for (std::uintmax_t offset = 0; in && offset + 8 <= size; offset = offset ? 2 * offset : 512) {
    char head[8];
    in.seekg(static_cast<std::streamoff>(offset));
    if (!in.read(head, 8)) return false;
    if (std::equal(head, head + 8, kSignature)) return true;
  }
  return false;
}

bool isSandSamplesFolder(const std::filesystem::path& folder) {
  std::error_code ec;
  for (const char* name : {"features.csv", "wrench_samples.csv", "scalars.txt"})
    if (!std::filesystem::is_regular_file(folder / name, ec)) return false;
  return true;
}

}  // namespace

// --data: a dataset file, a sand_samples-layout folder or a .csv file of one (the folder is imported
// on the fly); anything else is one message naming the path and what is accepted.
ForceDataset loadFitData(const std::string& path) {
  namespace fs = std::filesystem;
  const std::string shown = "--data " + displayPath(path);
  if (!pathExists(path)) throw InputError(shown + ": no such file or folder; " + kAcceptedData);
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    if (!isSandSamplesFolder(path))
      throw InputError(shown + ": a folder without features.csv, wrench_samples.csv and scalars.txt; " +
                       kAcceptedData);
    return importSandSamplesCsv(path);
  }
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".csv") {
    const fs::path parent = fs::path(path).parent_path();
    const fs::path folder = parent.empty() ? fs::path(".") : parent;
    if (!isSandSamplesFolder(folder))
      throw InputError(shown + ": a .csv file whose folder lacks features.csv, wrench_samples.csv or scalars.txt; " +
                       kAcceptedData);
    return importSandSamplesCsv(folder.string());
  }
  if (!fs::is_regular_file(path, ec))
    throw InputError(shown + ": neither a regular file nor a folder; " + kAcceptedData);
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || !hasHdf5Signature(path, size))
    throw InputError(shown + ": neither an HDF5 file nor a .csv file; " + kAcceptedData);
  return readForceDataset(path);
}

}  // namespace nmdp
