// Shared pieces of the libFuzzer targets (fuzz/fuzz_*.cpp): a scratch folder for the files a target
// hands to nmdp's readers, the splitting of one input into several files, and the rule every
// target applies: bad input may end in nmdp::InputError (what the CLI prints as one line and exit
// status 1) and in nothing else. Any other exception, a crash, a hang, a sanitizer report or an
// allocation past libFuzzer's limit is a finding.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/input_error.hpp"

namespace nmdp::fuzz {

// The fuzz input as text (bytes as they are, NULs included).
inline std::string asText(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }

// Splits `text` at every occurrence of `separator` (a line "@@" between files by default), into at
// most `parts` pieces (the last one keeps any further separators).
std::vector<std::string> split(const std::string& text, size_t parts, const std::string& separator = "\n@@\n");

// A scratch folder, one per process (in /dev/shm when it exists, removed at exit), emptied of the
// files a target wrote at the start of every input, so runs do not depend on each other.
class Scratch {
 public:
  static Scratch& get();
  // The folder emptied of the previous input's files: where every target starts.
  static Scratch& fresh();
  // Writes `content` to `name` in the folder and returns the absolute path.
  std::string write(const std::string& name, const std::string& content);
  // Splits `text` at the lines "@@" (split()) into one file per name, in order.
  void writeParts(const std::string& text, const std::vector<std::string>& names);
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  const std::string& dir() const { return dir_; }
  void clear();  // removes what write() created

 private:
  Scratch();
  ~Scratch();
  std::string dir_;
  std::vector<std::string> written_;
};

// Runs `body`; an InputError is the accepted way to refuse input and is swallowed. Anything else
// propagates out of LLVMFuzzerTestOneInput, which libFuzzer reports as a crash.
template <class F>
void acceptingInputErrors(F&& body) {
  try {
    body();
  } catch (const nmdp::InputError&) {
  }
}

// The repository's folders (compile-time: the fuzzers read seeds and robots in place).
std::string sourcePath(const std::string& relative);

}  // namespace nmdp::fuzz
