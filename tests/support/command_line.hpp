// The command line of an `nmdp` run started by a test, quoted for the shell: what SCOPED_TRACE shows.
#pragma once
#include <string>
#include <vector>

#include "test_cli.hpp"

namespace nmdp::test {

inline std::string commandLine(const std::vector<std::string>& args) {
  std::string s = "nmdp";
  for (const std::string& a : args) s += " " + shellQuote(a);
  return s;
}

}  // namespace nmdp::test
