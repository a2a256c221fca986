#include "config/json_params.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/text.hpp"
#include "config/json_reader.hpp"

namespace nmdp {

std::string ConfigContext::resolve(const std::string& path) const {
  if (path.empty() || std::filesystem::path(path).is_absolute() || base_dir.empty()) return path;
  return (std::filesystem::path(base_dir) / path).lexically_normal().string();
}

namespace {
[[noreturn]] void fail(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  // Edit distance is quadratic: names longer than any real key or joint get no suggestion.
  constexpr size_t kLongest = 256;
  std::string best;
  if (word.size() > kLongest) return best;
  size_t best_distance = std::max<size_t>(3, word.size() / 2) + 1;
  for (const std::string& c : candidates) {
    if (c.size() > kLongest) continue;
    const size_t d = editDistance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

namespace {
// The reader's place for a key of a context: "where.key".
KeyPath pathOf(const ConfigContext& ctx) { return KeyPath{ctx.where, "", "."}; }
}  // namespace

void requireKnownKeys(const nlohmann::json& object, const std::vector<std::string>& valid, const ConfigContext& ctx) {
  checkKeys(object, pathOf(ctx), valid);
}

double readNumber(const nlohmann::json& object, const std::string& key, double fallback, const ConfigContext& ctx,
                  double lo, double hi) {
  if (!object.contains(key)) return fallback;
  const nlohmann::json& v = object.at(key);
  const double x = read::finiteNumber(v, pathOf(ctx) / key);
  if (x < lo || x > hi) {
    std::string range = "[" + (lo <= -1e299 ? std::string("-inf") : nlohmann::json(lo).dump()) + ", " +
                        (hi >= 1e299 ? std::string("inf") : nlohmann::json(hi).dump()) + "]";
    fail(ctx, key, "value " + jsonForMessage(v) + " is out of range " + range);
  }
  return x;
}

int readInteger(const nlohmann::json& object, const std::string& key, int fallback, const ConfigContext& ctx, int lo,
                int hi) {
  if (!object.contains(key)) return fallback;
  const nlohmann::json& v = object.at(key);
  const long long x = read::wholeNumber(v, pathOf(ctx) / key, hi);
  if (x < lo || x > hi) fail(ctx, key, "value " + jsonForMessage(v) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(x);
}

std::string readString(const nlohmann::json& object, const std::string& key, const std::string& fallback,
                       const ConfigContext& ctx) {
  return read::string(object, key, fallback, pathOf(ctx));
}

bool readBool(const nlohmann::json& object, const std::string& key, bool fallback, const ConfigContext& ctx) {
  return read::boolean(object, key, fallback, pathOf(ctx));
}

std::vector<double> readNumbers(const nlohmann::json& object, const std::string& key,
                                const std::vector<double>& fallback, const ConfigContext& ctx) {
  if (!object.contains(key)) return fallback;
  const nlohmann::json& v = object.at(key);
  if (!v.is_array()) fail(ctx, key, "expected a list of numbers, got " + jsonForMessage(v));
  std::vector<double> out;
  for (const nlohmann::json& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>()) || std::abs(x.get<double>()) > 1e12)
      fail(ctx, key, "expected a list of finite numbers of magnitude at most 1e12, got " + jsonForMessage(v));
    out.push_back(x.get<double>());
  }
  return out;
}

Eigen::Vector3d readVec3(const nlohmann::json& object, const std::string& key, const Eigen::Vector3d& fallback,
                         const ConfigContext& ctx) {
  if (!object.contains(key)) return fallback;
  const std::vector<double> v = readNumbers(object, key, {}, ctx);
  if (v.size() != 3) fail(ctx, key, "expected three numbers [x, y, z], got " + jsonForMessage(object.at(key)));
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

}  // namespace nmdp
