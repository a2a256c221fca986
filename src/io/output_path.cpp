#include "io/output_path.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "io/hdf5_handle.hpp"

namespace nmdp {

namespace {

std::string folderOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string nameOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// The one message of a refused output.
[[noreturn]] void refuse(const std::string& output, const std::string& option, const std::string& reason) {
  throw InputError(displayPath(output) + ": refusing to write the output of " + option + " there: " + reason);
}

bool sameFile(const struct stat& a, const struct stat& b) { return a.st_dev == b.st_dev && a.st_ino == b.st_ino; }

// The input that `info` (an existing file) is, or nullptr.
const RunInput* inputThatIs(const struct stat& info, const std::vector<RunInput>& inputs) {
  for (const RunInput& input : inputs) {
    struct stat other;
    if (!input.path.empty() && ::stat(input.path.c_str(), &other) == 0 && sameFile(info, other)) return &input;
  }
  return nullptr;
}

// stat() of an output path: false when it does not exist; refuses paths that cannot be looked up.
bool statOutput(const std::string& path, const std::string& option, struct stat& info) {
  if (path.empty()) refuse(path, option, "the path is empty");
  if (path.size() > limits::kMaxPathLength || path.find('\0') != std::string::npos)
    refuse(path, option, "the path is too long or contains a NUL character");
  if (::stat(path.c_str(), &info) == 0) return true;
  if (errno == ENOENT) {
    struct stat link;
    if (::lstat(path.c_str(), &link) == 0) refuse(path, option, "it is a symbolic link to a file that does not exist");
    return false;
  }
  refuse(path, option, std::string("cannot look it up: ") + std::strerror(errno));
}

std::vector<std::string> markedFiles(const std::string& folder) {
  const std::string marker = folder + "/" + kFolderMarker;
  struct stat info;
  if (::stat(marker.c_str(), &info) != 0 || !S_ISREG(info.st_mode) || info.st_size > (1 << 20)) return {};
  try {
    const nlohmann::json json = nlohmann::json::parse(readInputFile(marker, "output marker"));
    if (!json.is_object() || !json.contains("nmdp_output") || !json.contains("files") || !json["files"].is_array())
      return {};
    std::vector<std::string> names;
    for (const nlohmann::json& name : json["files"])
      if (name.is_string()) names.push_back(name.get<std::string>());
    return names;
  } catch (const std::exception&) {
    return {};
  }
}

}  // namespace

std::vector<RunInput> filesInFolder(const std::string& folder, const std::string& role) {
  std::vector<RunInput> files;
  DIR* dir = ::opendir(folder.c_str());
  if (!dir) return files;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string path = folder + "/" + entry->d_name;
    struct stat info;
    if (::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode)) files.push_back({path, role});
  }
  ::closedir(dir);
  return files;
}

// Whether the file begins (within its first kilobyte) with the marker of a page nmdp wrote.
bool isNmdpPage(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return false;
  char head[1024];
  const size_t n = std::fread(head, 1, sizeof head, file);
  std::fclose(file);
  return std::string(head, n).find(kPageMarkerPrefix) != std::string::npos;
}

bool isNmdpOutputFile(const std::string& path) {
  h5::silenceHdf5();
  if (H5Fis_hdf5(path.c_str()) <= 0) return isNmdpPage(path);
  const h5::Handle file{h5::openReadOnly(path), H5Fclose};
  if (file.id < 0) return false;
  auto hasAttribute = [&](const char* name) { return H5Aexists_by_name(file.id, "/", name, H5P_DEFAULT) > 0; };
  if (hasAttribute("nmdp_output") || hasAttribute("nmdp_model") || hasAttribute("nmdp_dataset")) return true;
  return hasAttribute("config") && H5Lexists(file.id, "/status", H5P_DEFAULT) > 0;  // a trajectory
}

namespace {
// Refuses `path`, which does not exist yet, when the folder it would be created in does not exist.
void requireParentFolder(const std::string& path, const std::string& option) {
  struct stat parent;
  if (::stat(folderOf(path).c_str(), &parent) != 0 || !S_ISDIR(parent.st_mode))
    refuse(path, option, "its folder " + displayPath(folderOf(path)) + " does not exist");
}
}  // namespace

void checkOutputFile(const std::string& output, const std::vector<RunInput>& inputs, const std::string& option) {
  struct stat info;
  if (!statOutput(output, option, info)) return requireParentFolder(output, option);
  if (const RunInput* input = inputThatIs(info, inputs))
    refuse(output, option, "it is " + input->role + " of this run (" + displayPath(input->path) + ")");
  if (S_ISDIR(info.st_mode)) refuse(output, option, "it is a folder");
  if (!S_ISREG(info.st_mode)) refuse(output, option, "it is not a regular file (a device, pipe or socket)");
  if (!isNmdpOutputFile(output))
    refuse(output, option, "the file exists and is not one nmdp wrote (it has no nmdp marker), so replacing it could "
                           "lose data; remove it or choose another name");
}

void checkOutputFolder(const std::string& folder, const std::vector<std::string>& names,
                       const std::vector<RunInput>& inputs, const std::string& option) {
  struct stat info;
  if (!statOutput(folder, option, info)) return requireParentFolder(folder, option);
  if (!S_ISDIR(info.st_mode)) refuse(folder, option, "it exists and is not a folder");
  for (const std::string& name : names) {
    struct stat file;
    if (::stat((folder + "/" + name).c_str(), &file) != 0) continue;
    if (const RunInput* input = inputThatIs(file, inputs))
      refuse(folder, option, "its " + name + " is " + input->role + " of this run (" + displayPath(input->path) + ")");
  }
  const std::vector<std::string> marked = markedFiles(folder);
  const std::set<std::string> ours(marked.begin(), marked.end());
  DIR* dir = ::opendir(folder.c_str());
  if (!dir) refuse(folder, option, std::string("cannot list it: ") + std::strerror(errno));
  std::string foreign;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name == "." || name == ".." || name == kFolderMarker || ours.count(name)) continue;
    foreign = name;
    break;
  }
  ::closedir(dir);
  if (!foreign.empty())
    refuse(folder, option, "the folder holds " + foreign + ", which nmdp did not write there (no " +
                               std::string(kFolderMarker) + " lists it), so writing into it could replace data; "
                               "choose a new or empty folder");
}

void writeFolderMarker(const std::string& folder, const std::string& command, const std::vector<std::string>& names) {
  nlohmann::json marker = {{"nmdp_output", command}, {"files", names}};
  writeFileAtomically(folder + "/" + kFolderMarker, marker.dump(2) + "\n");
}

std::string temporaryPathFor(const std::string& final_path) {
  static std::atomic<unsigned> counter{0};
  std::random_device device;
  std::mt19937_64 rng((static_cast<std::uint64_t>(device()) << 32) ^ static_cast<std::uint64_t>(::getpid()) ^
                      (static_cast<std::uint64_t>(counter++) << 48));
  // Names of at most 255 bytes: the final name is shortened in the temporary one when needed.
  const std::string name = nameOf(final_path).substr(0, 200);
  for (;;) {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".%016llx.partial", static_cast<unsigned long long>(rng()));
    std::string candidate = folderOf(final_path) + "/" + name + suffix;
    struct stat info;
    if (::lstat(candidate.c_str(), &info) != 0) return candidate;
  }
}

void writeFileAtomically(const std::string& path, const std::string& content) {
  for (int attempt = 0;; ++attempt) {
    const std::string temporary = temporaryPathFor(path);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST && attempt < 100) continue;
      throw InputError(displayPath(path) + ": cannot write the file: " + std::strerror(errno));
    }
    size_t written = 0;
    while (written < content.size()) {
      const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      written += static_cast<size_t>(n);
    }
    const int write_error = written == content.size() ? 0 : (errno ? errno : EIO);
    const bool closed = ::close(fd) == 0;
    if (write_error || !closed || std::rename(temporary.c_str(), path.c_str()) != 0) {
      const int error = write_error ? write_error : errno;
      std::remove(temporary.c_str());
      throw InputError(displayPath(path) + ": cannot write the file: " + std::strerror(error));
    }
    return;
  }
}

}  // namespace nmdp
