// Running `nmdp simulate` on the example scenes from a test: the scene files, and a run that must
// complete (exit 0, the file written, status "complete").
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "run_files.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {

inline std::string sceneFile(const std::string& name) { return sourcePath("models/scenes/" + name); }
inline std::string trotScene() { return sceneFile("quadruped_trot_flat.json"); }

// `nmdp simulate ARGS...` must complete: exit 0, status "complete". Returns stdout, stderr and the exit.
inline CliResult runComplete(const std::vector<std::string>& args, const TempDir& dir, const std::string& out) {
  std::vector<std::string> full = {"simulate"};
  full.insert(full.end(), args.begin(), args.end());
  full.insert(full.end(), {"--out", out});
  SCOPED_TRACE(commandLine(full));
  const CliResult r = runNmdp(full, dir);
  EXPECT_TRUE(r.exited) << "nmdp was killed by a signal";
  EXPECT_EQ(r.exit_code, 0) << "stderr: " << r.err;
  EXPECT_TRUE(std::filesystem::exists(out)) << out << " was not written; stderr: " << r.err;
  if (std::filesystem::exists(out)) {
    EXPECT_EQ(statusOf(out), "complete") << "stderr: " << r.err;
  }
  return r;
}

}  // namespace nmdp::test
