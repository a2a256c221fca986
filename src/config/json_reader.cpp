#include "config/json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/text.hpp"
#include "config/json_params.hpp"

namespace nmdp {

void KeyPath::fail(const std::string& what) const { throw InputError(str() + ": " + what); }

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

const Bound kNoLow{-kInf, false}, kNoHigh{kInf, false};
Bound above(double v) { return {v, true}; }
Bound atLeast(double v) { return {v, false}; }
Bound below(double v) { return {v, true}; }
Bound atMost(double v) { return {v, false}; }

std::string numberText(double x) {
  std::ostringstream os;
  os << std::setprecision(12) << x;
  return os.str();
}

std::string rangeText(Bound lo, Bound hi) {
  if (std::isinf(hi.value)) return std::string("must be ") + (lo.open ? "> " : ">= ") + numberText(lo.value);
  if (std::isinf(lo.value)) return std::string("must be ") + (hi.open ? "< " : "<= ") + numberText(hi.value);
  return "must be in " + intervalText(lo, hi);
}

std::string intervalText(Bound lo, Bound hi) {
  return std::string(lo.open || std::isinf(lo.value) ? "(" : "[") + numberText(lo.value) + ", " + numberText(hi.value) +
         (hi.open || std::isinf(hi.value) ? ")" : "]");
}

bool inRange(double x, Bound lo, Bound hi) {
  const bool low_ok = lo.open ? x > lo.value : x >= lo.value;
  const bool high_ok = hi.open ? x < hi.value : x <= hi.value;
  return low_ok && high_ok;
}

std::string suggestion(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string near = closestMatch(word, candidates);
  return near.empty() ? "" : " (did you mean '" + near + "'?)";
}

void checkObject(const nlohmann::json& v, const KeyPath& w) {
  if (!v.is_object()) w.fail("expected a JSON object, got " + jsonForMessage(v));
}

void checkKeys(const nlohmann::json& object, const KeyPath& w, const std::vector<std::string>& valid) {
  checkObject(object, w);
  for (auto it = object.begin(); it != object.end(); ++it)
    if (std::find(valid.begin(), valid.end(), it.key()) == valid.end())
      (w / it.key()).fail("unknown key" + suggestion(it.key(), valid) + "; valid keys: " + join(valid));
}

namespace read {

using json = nlohmann::json;

double finiteNumber(const json& v, const KeyPath& w) {
  if (!v.is_number()) w.fail("expected a number, got " + jsonForMessage(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) w.fail("expected a finite number, got " + jsonForMessage(v));
  return x;
}

long long wholeNumber(const json& v, const KeyPath& w, int hi) {
  if (!v.is_number_integer()) w.fail("expected an integer, got " + jsonForMessage(v));
  return v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi)
             ? static_cast<long long>(hi) + 1
             : v.get<long long>();
}

double checkNumber(const json& v, const KeyPath& w, Bound lo, Bound hi) {
  const double x = finiteNumber(v, w);
  if (!inRange(x, lo, hi)) w.fail(rangeText(lo, hi) + ", got " + jsonForMessage(v));
  if (std::abs(x) > kMaxMagnitude)
    w.fail(rangeText(atLeast(-kMaxMagnitude), atMost(kMaxMagnitude)) + ", got " + jsonForMessage(v));
  return x;
}

double number(const json& object, const std::string& key, double fallback, const KeyPath& w, Bound lo, Bound hi) {
  if (!object.contains(key)) return fallback;
  return checkNumber(object.at(key), w / key, lo, hi);
}

std::optional<double> optionalNumber(const json& object, const std::string& key, const KeyPath& w, Bound lo, Bound hi) {
  if (!object.contains(key)) return std::nullopt;
  return checkNumber(object.at(key), w / key, lo, hi);
}

int integer(const json& object, const std::string& key, int fallback, const KeyPath& w, int lo, int hi) {
  if (!object.contains(key)) return fallback;
  const json& v = object.at(key);
  const long long x = wholeNumber(v, w / key, hi);
  if (x < lo || x > hi)
    (w / key).fail(hi >= kNoIntegerLimit ? "must be >= " + std::to_string(lo) + ", got " + jsonForMessage(v)
                                         : "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                               jsonForMessage(v));
  return static_cast<int>(x);
}

bool boolean(const json& object, const std::string& key, bool fallback, const KeyPath& w) {
  if (!object.contains(key)) return fallback;
  const json& v = object.at(key);
  if (!v.is_boolean()) (w / key).fail("expected true or false, got " + jsonForMessage(v));
  return v.get<bool>();
}

std::string string(const json& object, const std::string& key, const std::string& fallback, const KeyPath& w) {
  if (!object.contains(key)) return fallback;
  const json& v = object.at(key);
  if (!v.is_string()) (w / key).fail("expected a string, got " + jsonForMessage(v));
  return v.get<std::string>();
}

std::vector<double> numbers(const json& v, const KeyPath& w, const std::vector<size_t>& sizes, const std::string& shape,
                            double max_abs) {
  bool ok = v.is_array() && std::find(sizes.begin(), sizes.end(), v.size()) != sizes.end();
  if (ok)
    for (const json& x : v) ok = ok && x.is_number() && std::isfinite(x.get<double>());
  if (!ok) w.fail("expected " + shape + ", got " + jsonForMessage(v));
  std::vector<double> out;
  for (const json& x : v) out.push_back(x.get<double>());
  for (double x : out)
    if (std::abs(x) > max_abs)
      w.fail("expected " + shape + " of magnitude at most " + numberText(max_abs) + ", got " + jsonForMessage(v));
  return out;
}

Eigen::Vector3d vec3(const json& object, const std::string& key, const KeyPath& w, double max_abs) {
  if (!object.contains(key)) return Eigen::Vector3d::Zero();
  const std::vector<double> v = numbers(object.at(key), w / key, {3}, "three numbers [x, y, z]", max_abs);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

std::map<std::string, double> namedValues(const json& v, const KeyPath& w, Bound lo, Bound hi) {
  if (!v.is_object()) w.fail("expected an object {joint name: value}, got " + jsonForMessage(v));
  std::map<std::string, double> out;
  for (auto it = v.begin(); it != v.end(); ++it) out[it.key()] = checkNumber(it.value(), w / it.key(), lo, hi);
  return out;
}

}  // namespace read
}  // namespace nmdp
