// The repository's own files, for the architecture checks (tests/architecture/): where the source
// root is, which files lie below some top folders, and a file's text.
#pragma once
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace nmdp::test {

inline std::filesystem::path sourceRoot() { return std::filesystem::path(NMDP_SOURCE_DIR); }

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The regular files below root/top for each of `tops` whose extension is one of `extensions`
// (".cpp"), as paths relative to root with '/', sorted; a top that does not exist gives none.
inline std::vector<std::string> sourceFiles(const std::filesystem::path& root, const std::vector<std::string>& tops,
                                            const std::vector<std::string>& extensions) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const std::string& top : tops) {
    if (!fs::is_directory(root / top)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) continue;
      out.push_back(fs::relative(entry.path(), root).generic_string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace nmdp::test
