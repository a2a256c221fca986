// Which nmdp this is: the project version (CMakeLists.txt) and the git commit it was built from,
// for `nmdp --version` and the root attributes of every file nmdp writes. Defined in a file the
// build generates (cmake/write_version.cmake) and linked only into the executable and the Python
// module, so that a new commit relinks those two and not every test.
#pragma once

namespace nmdp {

struct BuildVersion {
  const char* version;  // "0.9.0"
  const char* commit;   // 40 hex digits, with "-dirty" appended when tracked files were modified, or "unknown"
};

BuildVersion buildVersion();

}  // namespace nmdp
