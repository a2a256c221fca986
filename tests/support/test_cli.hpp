// Running the `nmdp` executable (NMDP_BINARY) from a test, with stdout, stderr and the exit code.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_temp_dir.hpp"

namespace nmdp::test {

inline std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct CliResult {
  bool exited = false;  // terminated normally (not by a signal)
  int exit_code = -1;   // valid when exited
  std::string out, err;
};

// Runs `nmdp ARGS...` with stdout and stderr captured to files in `dir`. A `prefix` (shell commands
// whose last one executes what follows it, e.g. "ulimit -v 2097152; exec timeout -s KILL 20") runs
// it through `sh -c`.
inline CliResult runNmdp(const std::vector<std::string>& args, const TempDir& dir, const std::string& prefix = "") {
  static std::atomic<int> counter{0};
  const int id = counter++;
  const std::filesystem::path out = dir.path() / ("stdout_" + std::to_string(id) + ".txt");
  const std::filesystem::path err = dir.path() / ("stderr_" + std::to_string(id) + ".txt");
  std::string cmd = shellQuote(NMDP_BINARY);
  for (const std::string& a : args) cmd += " " + shellQuote(a);
  if (!prefix.empty()) cmd = "sh -c " + shellQuote(prefix + " " + cmd);
  cmd += " >" + shellQuote(out.string()) + " 2>" + shellQuote(err.string()) + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exited = status != -1 && WIFEXITED(status);
  if (r.exited) r.exit_code = WEXITSTATUS(status);
  r.out = readText(out);
  r.err = readText(err);
  return r;
}

// `text` is exactly one line ending in '\n'; `what` names it in the messages. Fatal (returns at
// once) when `text` is empty: wrap in ASSERT_NO_FATAL_FAILURE to stop the caller as well.
inline void expectOneLine(const std::string& text, const std::string& what) {
  ASSERT_FALSE(text.empty()) << what << " is empty";
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << what << " must be exactly one line:\n" << text;
  EXPECT_EQ(text.back(), '\n') << what << ": " << text;
}

}  // namespace nmdp::test
