#include "common/input_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "common/input_error.hpp"

namespace nmdp {

namespace {

std::string mebibytes(std::uintmax_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return text;
}

[[noreturn]] void refuse(const std::string& path, const std::string& what, const std::string& reason) {
  throw InputError(displayPath(path) + ": cannot read the " + what + ": " + reason);
}

// stat(2) with the reasons a user can act on; fills `info`.
void statOrRefuse(const std::string& path, const std::string& what, struct stat& info) {
  if (path.empty()) refuse(path, what, "the path is empty");
  if (path.size() > limits::kMaxPathLength)
    refuse(path, what, "the path has " + std::to_string(path.size()) + " characters, more than the " +
                           std::to_string(limits::kMaxPathLength) + " a path may have");
  if (path.find('\0') != std::string::npos) refuse(path, what, "the path contains a NUL character");
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    if (error == ENOENT) refuse(path, what, "no such file");
    if (error == ENOTDIR) refuse(path, what, "a component of the path is not a folder");
    if (error == EACCES) refuse(path, what, "permission denied");
    if (error == ENAMETOOLONG) refuse(path, what, "the path or one of its names is too long");
    if (error == ELOOP) refuse(path, what, "too many symbolic links");
    refuse(path, what, std::strerror(error));
  }
}

}  // namespace

std::string displayPath(const std::string& path) {
  constexpr size_t kShown = 300, kEnd = 120;
  if (path.size() <= kShown) return path;
  return path.substr(0, kEnd) + "...(" + std::to_string(path.size() - 2 * kEnd) + " characters)..." +
         path.substr(path.size() - kEnd);
}

bool pathExists(const std::string& path) {
  struct stat info;
  return !path.empty() && path.size() <= limits::kMaxPathLength && path.find('\0') == std::string::npos &&
         ::stat(path.c_str(), &info) == 0;
}

void requireRegularFile(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  struct stat info;
  statOrRefuse(path, what, info);
  if (S_ISDIR(info.st_mode)) refuse(path, what, "it is a folder, not a file");
  if (!S_ISREG(info.st_mode)) refuse(path, what, "it is not a regular file (a device, pipe or socket)");
  if (static_cast<std::uintmax_t>(info.st_size) > max_bytes)
    refuse(path, what, "it has " + mebibytes(static_cast<std::uintmax_t>(info.st_size)) + ", more than the " +
                           mebibytes(max_bytes) + " such a file may have");
}

std::string readInputFile(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  requireRegularFile(path, what, max_bytes);
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) refuse(path, what, errno == EACCES ? "permission denied" : std::strerror(errno));
  std::string text;
  char buffer[1 << 16];
  size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) {
    if (text.size() + got > max_bytes)
      refuse(path, what, "it grew past the " + mebibytes(max_bytes) + " such a file may have while being read");
    text.append(buffer, got);
  }
  if (std::ferror(file.get())) refuse(path, what, "a read failed (" + std::string(std::strerror(errno)) + ")");
  return text;
}

}  // namespace nmdp
