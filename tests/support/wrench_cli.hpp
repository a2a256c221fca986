// Running `nmdp wrench` from a test: the contract for bad input (one line on stderr, exit code 1,
// nothing on stdout), a run that must succeed and its JSON output, and a 6 × K matrix read from it.
#pragma once
#include <gtest/gtest.h>

#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "contact_models/contact_model.hpp"
#include "test_cli.hpp"

namespace nmdp::test {

// The contract for bad input: exit code exactly 1, nothing on stdout, one stderr line
// "nmdp wrench: error: ..." that contains every string of `expect` (the file, the key, ...).
inline void expectWrenchError(const std::vector<std::string>& args, const TempDir& dir, const std::vector<std::string>& expect) {
  SCOPED_TRACE(commandLine(args));
  const CliResult r = runNmdp(args, dir);
  ASSERT_TRUE(r.exited) << "nmdp was killed by a signal";
  EXPECT_EQ(r.exit_code, 1) << "stderr: " << r.err;  // not 0, not an internal error (3), not a crash
  EXPECT_TRUE(r.out.empty()) << "nothing on stdout for bad input, got:\n" << r.out;
  ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
  EXPECT_EQ(r.err.rfind("nmdp wrench: error: ", 0), 0u) << r.err;
  for (const std::string& s : expect) EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
}

// Runs a command that must succeed and returns its JSON output.
inline nlohmann::json runWrenchOk(const std::vector<std::string>& args, const TempDir& dir) {
  SCOPED_TRACE(commandLine(args));
  const CliResult r = runNmdp(args, dir);
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0) << "stderr: " << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  try {
    return nlohmann::json::parse(r.out);
  } catch (const nlohmann::json::exception& e) {
    ADD_FAILURE() << "stdout is not JSON (" << e.what() << "):\n" << r.out;
    return nlohmann::json();
  }
}

// V (or one dV) of the JSON output as a 6×K matrix; checks the layout on the way.
inline Mat6X matrixOf(const nlohmann::json& columns, int K) {
  Mat6X M(6, K);
  M.setConstant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(columns.is_array()) << columns.dump();
  if (!columns.is_array()) return M;
  EXPECT_EQ(static_cast<int>(columns.size()), K) << "expected " << K << " columns: " << columns.dump();
  for (int j = 0; j < K && j < static_cast<int>(columns.size()); ++j) {
    EXPECT_TRUE(columns[j].is_array() && columns[j].size() == 6) << "column " << j << ": " << columns[j].dump();
    if (!columns[j].is_array() || columns[j].size() != 6) continue;
    for (int i = 0; i < 6; ++i) M(i, j) = columns[j][i].is_number() ? columns[j][i].get<double>() : M(i, j);
  }
  return M;
}

}  // namespace nmdp::test
