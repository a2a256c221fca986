#include "app/view_page.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include "common/input_error.hpp"
#include "common/input_file.hpp"

#ifndef NMDP_VIEWER_BUNDLE_DEFAULT
#define NMDP_VIEWER_BUNDLE_DEFAULT ""
#endif

namespace nmdp::app {

namespace {
static_assert(sizeof(float) == 4 && sizeof(double) == 8, "payload arrays are IEEE float32 and float64");

bool littleEndian() {
  const std::uint16_t one = 1;
  std::uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

template <typename T>
nlohmann::json array(const char* dtype, const std::vector<T>& values, const std::vector<size_t>& shape) {
  size_t count = 1;
  for (size_t n : shape) count *= n;
  if (count != values.size()) throw std::logic_error(std::string("payload array of ") + dtype + ": shape and size differ");
  std::string bytes(values.size() * sizeof(T), '\0');
  if (!bytes.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  if (!littleEndian())
    for (size_t i = 0; i < bytes.size(); i += sizeof(T)) std::reverse(bytes.begin() + i, bytes.begin() + i + sizeof(T));
  return {{"dtype", dtype}, {"shape", shape}, {"b64", base64(bytes.data(), bytes.size())}};
}

// Every "</script" (in any case, as HTML reads it) written "<\/script".
std::string escapeScriptEnds(const std::string& script) {
  std::string out;
  out.reserve(script.size());
  for (size_t i = 0; i < script.size(); ++i) {
    out += script[i];
    if (script[i] != '<' || i + 7 >= script.size() || script[i + 1] != '/') continue;
    std::string word = script.substr(i + 2, 6);
    std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (word == "script") out += '\\';
  }
  return out;
}

// Every occurrence of `from` in `text` replaced by `to`.
std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

std::string executableFolder() {
  std::string path(4096, '\0');
  const ssize_t n = ::readlink("/proc/self/exe", path.data(), path.size() - 1);
  if (n <= 0) return "";
  path.resize(static_cast<size_t>(n));
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "" : path.substr(0, slash);
}
}  // namespace

std::string base64(const void* data, size_t size) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const unsigned v = bytes[i] << 16 | bytes[i + 1] << 8 | bytes[i + 2];
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < size) {
    const unsigned v = bytes[i] << 16 | (i + 1 < size ? bytes[i + 1] << 8 : 0);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

nlohmann::json floatArray(const std::vector<float>& values, const std::vector<size_t>& shape) {
  return array("float32", values, shape);
}
nlohmann::json doubleArray(const std::vector<double>& values, const std::vector<size_t>& shape) {
  return array("float64", values, shape);
}
nlohmann::json byteArray(const std::vector<std::uint8_t>& values, const std::vector<size_t>& shape) {
  return array("uint8", values, shape);
}

std::string findViewerBundle() {
  if (const char* chosen = std::getenv("NMDP_VIEWER_BUNDLE"); chosen && *chosen) {
    if (!pathExists(chosen))
      throw InputError(displayPath(chosen) + " ($NMDP_VIEWER_BUNDLE): the viewer's script is not there; build it with "
                       "scripts/build.sh, or npm ci && npm run build in viewer/");
    return readInputFile(chosen, "viewer script");
  }
  const std::string candidates[] = {NMDP_VIEWER_BUNDLE_DEFAULT, executableFolder() + "/../share/nmdp/nmdp-view.js"};
  std::string tried;
  for (const std::string& path : candidates) {
    if (path.empty() || path == "/../share/nmdp/nmdp-view.js") continue;
    if (pathExists(path)) return readInputFile(path, "viewer script");
    tried += (tried.empty() ? "" : " nor ") + displayPath(path);
  }
  throw InputError("the viewer's script (nmdp-view.js) is not built: neither " + tried +
                   " exists; build it with scripts/build.sh, or npm ci && npm run build in viewer/ "
                   "(or set NMDP_VIEWER_BUNDLE to its path)");
}

std::string viewPage(const nlohmann::json& payload, const std::string& script) {
  // Invalid UTF-8 from a file (a name, a URDF) is replaced rather than refused: the page is for reading.
  const std::string json = replaceAll(payload.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "<", "\\u003c");
  std::string page;
  page.reserve(json.size() + script.size() + 512);
  page += "<!doctype html><html><head><meta charset=\"utf-8\">";
  page += kViewPageMarker;
  page += "<title>nmdp view: loading</title></head>\n<body>\n<script type=\"application/json\" id=\"nmdp-view-data\">";
  page += json;
  page += "</script>\n<script>";
  page += escapeScriptEnds(script);
  page += "</script>\n</body></html>\n";
  return page;
}

}  // namespace nmdp::app
