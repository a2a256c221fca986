// Temporary folders and files for tests that write fixtures at run time.
#pragma once
#include <errno.h>  // program_invocation_short_name (glibc)
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

namespace nmdp::test {

// A fresh folder under std::filesystem::temp_directory_path() named
// "nmdp_<test>_<pid>_<counter>_<random>", removed with everything in it at scope exit. <test> is the
// running executable's name, read at run time so that every test target compiles with the same
// definitions (one precompiled header serves them all).
class TempDir {
 public:
  TempDir() {
    namespace fs = std::filesystem;
    static std::atomic<int> counter{0};
    std::random_device rd;
    for (int attempt = 0;; ++attempt) {
      path_ = fs::temp_directory_path() / (std::string("nmdp_") + program_invocation_short_name + "_" +
                                           std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" +
                                           std::to_string(rd()));
      if (fs::create_directory(path_)) break;
      if (attempt > 100) throw std::runtime_error("cannot create a temporary directory");
    }
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string dir() const { return path_.string(); }
  // The path of `name` in the folder (nothing is created).
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  // Writes `content` to `name` (sub-folders are created) and returns its path.
  std::string write(const std::string& name, const std::string& content) const {
    const std::filesystem::path p = path_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out << content;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + p.string());
    return p.string();
  }

 private:
  std::filesystem::path path_;
};

// One file name in a fresh temporary folder; the file (and anything written next to it, such as
// "<name>.partial") is removed with the folder at scope exit.
class TempFile {
 public:
  explicit TempFile(const std::string& name) : path_(dir_.file(name)) {}
  const std::string& path() const { return path_; }

 private:
  TempDir dir_;
  std::string path_;
};

}  // namespace nmdp::test
