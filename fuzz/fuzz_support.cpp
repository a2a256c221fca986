#include "fuzz/fuzz_support.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace nmdp::fuzz {

std::vector<std::string> split(const std::string& text, size_t parts, const std::string& separator) {
  std::vector<std::string> out;
  size_t start = 0;
  while (out.size() + 1 < parts) {
    const size_t at = text.find(separator, start);
    if (at == std::string::npos) break;
    out.push_back(text.substr(start, at - start));
    start = at + separator.size();
  }
  out.push_back(text.substr(start));
  while (out.size() < parts) out.emplace_back();
  return out;
}

Scratch::Scratch() {
  namespace fs = std::filesystem;
  const fs::path base = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
  dir_ = (base / ("nmdp_fuzz_" + std::to_string(::getpid()))).string();
  fs::create_directories(dir_);
}

Scratch::~Scratch() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

Scratch& Scratch::get() {
  static Scratch scratch;  // one folder per fuzzing process
  return scratch;
}

Scratch& Scratch::fresh() {
  Scratch& scratch = get();
  scratch.clear();
  return scratch;
}

void Scratch::writeParts(const std::string& text, const std::vector<std::string>& names) {
  const std::vector<std::string> parts = split(text, names.size());
  for (size_t i = 0; i < names.size(); ++i) write(names[i], parts[i]);
}

std::string Scratch::write(const std::string& name, const std::string& content) {
  const std::string p = path(name);
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  if (!out) throw std::runtime_error("fuzz scratch: cannot write " + p);
  written_.push_back(p);
  return p;
}

void Scratch::clear() {
  for (const std::string& p : written_) std::remove(p.c_str());
  written_.clear();
}

std::string sourcePath(const std::string& relative) { return std::string(NMDP_SOURCE_DIR) + "/" + relative; }

}  // namespace nmdp::fuzz
