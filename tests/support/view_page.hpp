// Reading back the page `nmdp view` writes: the payload JSON from its element and the arrays in it
// (base64 of little-endian float32, float64 or uint8), and running `nmdp view` with a stand-in for
// the viewer's script (the real bundle is tested in the browser tests of viewer/).
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_cli.hpp"

namespace nmdp::test {

// The stand-in script: it holds "</script>" (written <\/script> in the page) and sets the title the
// front end sets when ready.
inline const char* const kStandInBundle =
    "/* stand-in viewer: \"</script>\" must not end the element */\n"
    "document.title = 'nmdp view: ready';\n";

// Writes the stand-in into `dir` and points $NMDP_VIEWER_BUNDLE at it for the nmdp processes
// this test starts.
inline std::string useStandInBundle(const TempDir& dir) {
  const std::string path = (dir.path() / "nmdp-view.js").string();
  std::ofstream(path) << kStandInBundle;
  ::setenv("NMDP_VIEWER_BUNDLE", path.c_str(), 1);
  return path;
}

// The payload of a page (parse errors fail the test by exception).
inline nlohmann::json payloadOf(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"nmdp-view-data\">";
  const size_t begin = html.find(open);
  if (begin == std::string::npos) throw std::runtime_error("the page has no nmdp-view-data element");
  const size_t start = begin + open.size();
  const size_t end = html.find("</script>", start);
  if (end == std::string::npos) throw std::runtime_error("the payload element is not closed");
  return nlohmann::json::parse(html.substr(start, end - start));
}

inline std::vector<std::uint8_t> fromBase64(const std::string& text) {
  std::vector<std::uint8_t> out;
  unsigned value = 0;
  int bits = 0;
  for (const char c : text) {
    int digit;
    if (c >= 'A' && c <= 'Z') digit = c - 'A';
    else if (c >= 'a' && c <= 'z') digit = c - 'a' + 26;
    else if (c >= '0' && c <= '9') digit = c - '0' + 52;
    else if (c == '+') digit = 62;
    else if (c == '/') digit = 63;
    else break;  // '=' padding
    value = (value << 6) | static_cast<unsigned>(digit);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((value >> bits) & 0xff));
    }
  }
  return out;
}

struct PayloadArray {
  std::string dtype;
  std::vector<size_t> shape;
  std::vector<double> values;  // converted from the dtype (little-endian hosts, as the tests run)
};

inline PayloadArray decodeArray(const nlohmann::json& a) {
  PayloadArray out;
  out.dtype = a.at("dtype").get<std::string>();
  out.shape = a.at("shape").get<std::vector<size_t>>();
  const std::vector<std::uint8_t> bytes = fromBase64(a.at("b64").get<std::string>());
  const size_t size = out.dtype == "float64" ? 8 : out.dtype == "float32" ? 4 : 1;
  for (size_t k = 0; k + size <= bytes.size(); k += size) {
    if (size == 8) {
      double v;
      std::memcpy(&v, &bytes[k], 8);
      out.values.push_back(v);
    } else if (size == 4) {
      float v;
      std::memcpy(&v, &bytes[k], 4);
      out.values.push_back(v);
    } else {
      out.values.push_back(bytes[k]);
    }
  }
  size_t count = 1;
  for (size_t n : out.shape) count *= n;
  EXPECT_EQ(count, out.values.size()) << "the array's shape does not match its bytes";
  EXPECT_EQ(bytes.size(), out.values.size() * size) << "the array's bytes are not whole values";
  return out;
}

// Whether any of `warnings` (a JSON list of strings) contains every one of `words`.
inline bool hasWarning(const nlohmann::json& warnings, const std::vector<std::string>& words) {
  for (const nlohmann::json& w : warnings) {
    bool all = true;
    for (const std::string& word : words) all = all && w.get<std::string>().find(word) != std::string::npos;
    if (all) return true;
  }
  return false;
}

// `nmdp view ARGS...`; the page's text in `html` when it exited 0.
inline CliResult runView(const std::vector<std::string>& args, const TempDir& dir) {
  std::vector<std::string> full = {"view"};
  full.insert(full.end(), args.begin(), args.end());
  return runNmdp(full, dir);
}

}  // namespace nmdp::test
