// The one JSON reader of configuration files: a place in a file (KeyPath), the bounds of a value
// (Bound) and typed reads that throw an InputError "<file>: <key.path>: <what is wrong>, got <value>".
// Scenes, contact models, terrains, fit and gen-rft configurations all read through it
// (json_params.hpp keeps the ConfigContext form of the same reads).
#pragma once
#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/named_enum.hpp"
#include "common/text.hpp"

namespace nmdp {

// A place in a configuration: the file (or other source) and the key path ("integrator.dt").
struct KeyPath {
  std::string file;
  std::string key;
  std::string separator = ": ";  // between file and key: "scene.json: robot" or "fit.json.mlp"
  KeyPath operator/(const std::string& sub) const { return {file, key.empty() ? sub : key + "." + sub, separator}; }
  std::string str() const { return file + (key.empty() ? "" : separator + key); }
  [[noreturn]] void fail(const std::string& what) const;
};

// A bound of a range: its value, and whether the range is open there.
struct Bound {
  double value;
  bool open;
};
Bound above(double v);
Bound atLeast(double v);
Bound below(double v);
Bound atMost(double v);
extern const Bound kNoLow, kNoHigh;

// No number of a configuration means anything beyond this magnitude (in its SI unit), and below it
// products of two stay finite.
constexpr double kMaxMagnitude = 1e12;

std::string numberText(double x);              // 0.05, 1, 1e-05: as short as it reads
std::string rangeText(Bound lo, Bound hi);     // "must be in (0, 1]", "must be >= 0", ...
std::string intervalText(Bound lo, Bound hi);  // "(0, 1]", "[0, inf)"
bool inRange(double x, Bound lo, Bound hi);
// " (did you mean 'x'?)" for the closest candidate, "" if none is close.
std::string suggestion(const std::string& word, const std::vector<std::string>& candidates);

void checkObject(const nlohmann::json& v, const KeyPath& w);
// An object whose keys are all in `valid` (the message names the closest valid key and lists them).
void checkKeys(const nlohmann::json& object, const KeyPath& w, const std::vector<std::string>& valid);

namespace read {

// A JSON number that is finite (any magnitude); an integer (above `hi`: hi + 1, so that a range
// check fails without overflow).
double finiteNumber(const nlohmann::json& v, const KeyPath& w);
long long wholeNumber(const nlohmann::json& v, const KeyPath& w, int hi);
// A finite number in [lo, hi] (each bound open or closed) and of magnitude at most kMaxMagnitude.
double checkNumber(const nlohmann::json& v, const KeyPath& w, Bound lo = kNoLow, Bound hi = kNoHigh);
double number(const nlohmann::json& object, const std::string& key, double fallback, const KeyPath& w,
              Bound lo = kNoLow, Bound hi = kNoHigh);
std::optional<double> optionalNumber(const nlohmann::json& object, const std::string& key, const KeyPath& w,
                                     Bound lo = kNoLow, Bound hi = kNoHigh);
constexpr int kNoIntegerLimit = 1000000000;
int integer(const nlohmann::json& object, const std::string& key, int fallback, const KeyPath& w, int lo,
            int hi = kNoIntegerLimit);
bool boolean(const nlohmann::json& object, const std::string& key, bool fallback, const KeyPath& w);
std::string string(const nlohmann::json& object, const std::string& key, const std::string& fallback, const KeyPath& w);
// A list of finite numbers with one of `sizes` entries, each of magnitude at most `max_abs`;
// `shape` says what is expected ("three numbers [x, y, z]").
std::vector<double> numbers(const nlohmann::json& v, const KeyPath& w, const std::vector<size_t>& sizes,
                            const std::string& shape, double max_abs = kMaxMagnitude);
Eigen::Vector3d vec3(const nlohmann::json& object, const std::string& key, const KeyPath& w,
                     double max_abs = kMaxMagnitude);
// {name: number} with every number in [lo, hi].
std::map<std::string, double> namedValues(const nlohmann::json& v, const KeyPath& w, Bound lo = kNoLow,
                                          Bound hi = kNoHigh);

// A name from an EnumName table (common/named_enum.hpp); "unknown <what> 'x' (did you mean ...);
// valid: a, b" otherwise.
template <class E, std::size_t N>
E named(const nlohmann::json& object, const std::string& key, E fallback, const EnumName<E> (&table)[N],
        const std::string& what, const KeyPath& w) {
  const std::string given = string(object, key, nameOf(table, fallback), w);
  const std::optional<E> found = enumFromName(table, given);
  if (!found) {
    const std::vector<std::string> names = namesOf(table);
    (w / key).fail("unknown " + what + " '" + given + "'" + suggestion(given, names) + "; valid: " + join(names));
  }
  return *found;
}

}  // namespace read
}  // namespace nmdp
