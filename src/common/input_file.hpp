// Reading the files a user hands to nmdp. Every path is checked before it is opened: it must name
// an existing regular file (not a folder, a device such as /dev/zero, a pipe or a socket, which
// would block, never end or be read to exhaustion) of bounded size. Every failure is one InputError
// "<path>: <what is wrong>", the path shortened for the message when it is absurdly long; nothing
// here throws std::filesystem_error.
#pragma once
#include <cstdint>
#include <string>

#include "common/limits.hpp"

namespace nmdp {

// Throws InputError "<path>: cannot read the <what>: <reason>" unless `path` names an existing
// regular file of at most `max_bytes` (symbolic links are followed). `what` names the role of the
// file, e.g. "URDF file" or "scene file".
void requireRegularFile(const std::string& path, const std::string& what,
                        std::uintmax_t max_bytes = limits::kMaxTextFileBytes);

// The whole content of the file, after requireRegularFile(). A file that grows past `max_bytes`
// while being read is refused too.
std::string readInputFile(const std::string& path, const std::string& what,
                          std::uintmax_t max_bytes = limits::kMaxTextFileBytes);

// `path` as messages show it: unchanged up to 300 characters, else its first and last 120 with
// the number of characters left out between them.
std::string displayPath(const std::string& path);

// Whether `path` names an existing file or folder; false (never an exception) for any path the
// system cannot look up, such as one longer than PATH_MAX.
bool pathExists(const std::string& path);

}  // namespace nmdp
