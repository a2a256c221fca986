#include "sim/scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "control/default_gains.hpp"
#include "control/hermite_spline.hpp"
#include "control/leg_ik.hpp"
#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "common/utf8.hpp"
#include "config/json_params.hpp"
#include "multibody/base_chart.hpp"
#include "multibody/data.hpp"
#include "multibody/feet.hpp"
#include "multibody/kinematics.hpp"
#include "terrain/terrain_factory.hpp"
#include "common/text.hpp"

namespace nmdp {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// A place in the scene: the file and the key path ("integrator.dt").
struct Where {
  std::string file;
  std::string key;
  Where operator/(const std::string& sub) const { return {file, key.empty() ? sub : key + "." + sub}; }
  std::string str() const { return file + (key.empty() ? "" : ": " + key); }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(str() + ": " + what); }
};

std::string suggestion(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string near = closestMatch(word, candidates);
  return near.empty() ? "" : " (did you mean '" + near + "'?)";
}

void checkObject(const json& v, const Where& w) {
  if (!v.is_object()) w.fail("expected a JSON object, got " + jsonForMessage(v));
}

void checkKeys(const json& obj, const Where& w, const std::vector<std::string>& valid) {
  checkObject(obj, w);
  for (auto it = obj.begin(); it != obj.end(); ++it)
    if (std::find(valid.begin(), valid.end(), it.key()) == valid.end())
      (w / it.key()).fail("unknown key" + suggestion(it.key(), valid) + "; valid keys: " + join(valid));
}

// A bound of a range: value, and whether the range is open there.
struct Bound {
  double value;
  bool open;
};
constexpr double kInf = std::numeric_limits<double>::infinity();
const Bound kNoLow{-kInf, false}, kNoHigh{kInf, false};
Bound above(double v) { return {v, true}; }
Bound atLeast(double v) { return {v, false}; }
Bound below(double v) { return {v, true}; }
Bound atMost(double v) { return {v, false}; }

std::string fmt(double x) {  // 0.05, 1, 1e-05: as short as it reads
  std::ostringstream os;
  os << std::setprecision(12) << x;
  return os.str();
}

std::string rangeText(Bound lo, Bound hi) {
  if (std::isinf(hi.value)) return std::string("must be ") + (lo.open ? "> " : ">= ") + fmt(lo.value);
  if (std::isinf(lo.value)) return std::string("must be ") + (hi.open ? "< " : "<= ") + fmt(hi.value);
  return "must be in " + std::string(lo.open ? "(" : "[") + fmt(lo.value) + ", " + fmt(hi.value) + (hi.open ? ")" : "]");
}

// No number of a scene means anything beyond this magnitude (in its SI unit), and below it products
// of two stay finite.
constexpr double kMaxMagnitude = 1e12;

double checkNumber(const json& v, const Where& w, Bound lo = kNoLow, Bound hi = kNoHigh) {
  if (!v.is_number()) w.fail("expected a number, got " + jsonForMessage(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) w.fail("expected a finite number, got " + jsonForMessage(v));
  const bool low_ok = lo.open ? x > lo.value : x >= lo.value;
  const bool high_ok = hi.open ? x < hi.value : x <= hi.value;
  if (!low_ok || !high_ok) w.fail(rangeText(lo, hi) + ", got " + jsonForMessage(v));
  if (std::abs(x) > kMaxMagnitude) w.fail(rangeText(atLeast(-kMaxMagnitude), atMost(kMaxMagnitude)) + ", got " + jsonForMessage(v));
  return x;
}

double number(const json& obj, const std::string& key, double fallback, const Where& w, Bound lo = kNoLow,
              Bound hi = kNoHigh) {
  if (!obj.contains(key)) return fallback;
  return checkNumber(obj.at(key), w / key, lo, hi);
}

std::optional<double> optionalNumber(const json& obj, const std::string& key, const Where& w, Bound lo = kNoLow,
                                     Bound hi = kNoHigh) {
  if (!obj.contains(key)) return std::nullopt;
  return checkNumber(obj.at(key), w / key, lo, hi);
}

int integer(const json& obj, const std::string& key, int fallback, const Where& w, int lo, int hi = 1000000000) {
  if (!obj.contains(key)) return fallback;
  const json& v = obj.at(key);
  if (!v.is_number_integer()) (w / key).fail("expected an integer, got " + jsonForMessage(v));
  const long long x = v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi)
                          ? static_cast<long long>(hi) + 1
                          : v.get<long long>();
  if (x < lo || x > hi)
    (w / key).fail(hi >= 1000000000 ? "must be >= " + std::to_string(lo) + ", got " + jsonForMessage(v)
                                    : "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + jsonForMessage(v));
  return static_cast<int>(x);
}

bool boolean(const json& obj, const std::string& key, bool fallback, const Where& w) {
  if (!obj.contains(key)) return fallback;
  const json& v = obj.at(key);
  if (!v.is_boolean()) (w / key).fail("expected true or false, got " + jsonForMessage(v));
  return v.get<bool>();
}

std::string readStr(const json& obj, const std::string& key, const std::string& fallback, const Where& w) {
  if (!obj.contains(key)) return fallback;
  const json& v = obj.at(key);
  if (!v.is_string()) (w / key).fail("expected a string, got " + jsonForMessage(v));
  return v.get<std::string>();
}

// A list of finite numbers of one of `sizes`, each of magnitude at most `max_abs`.
std::vector<double> numbers(const json& v, const Where& w, const std::vector<size_t>& sizes, const std::string& shape,
                            double max_abs = kMaxMagnitude) {
  bool ok = v.is_array() && std::find(sizes.begin(), sizes.end(), v.size()) != sizes.end();
  if (ok)
    for (const json& x : v) ok = ok && x.is_number() && std::isfinite(x.get<double>());
  if (!ok) w.fail("expected " + shape + ", got " + jsonForMessage(v));
  std::vector<double> out;
  for (const json& x : v) out.push_back(x.get<double>());
  for (double x : out)
    if (std::abs(x) > max_abs) w.fail("expected " + shape + " of magnitude at most " + fmt(max_abs) + ", got " + jsonForMessage(v));
  return out;
}

Vec3 vec3(const json& obj, const std::string& key, const Where& w, double max_abs = kMaxMagnitude) {
  if (!obj.contains(key)) return Vec3::Zero();
  const std::vector<double> v = numbers(obj.at(key), w / key, {3}, "three numbers [x, y, z]", max_abs);
  return Vec3(v[0], v[1], v[2]);
}

JointValues jointValues(const json& v, const Where& w, Bound lo = kNoLow, Bound hi = kNoHigh) {
  if (!v.is_object()) w.fail("expected an object {joint name: value}, got " + jsonForMessage(v));
  JointValues out;
  for (auto it = v.begin(); it != v.end(); ++it) out[it.key()] = checkNumber(it.value(), w / it.key(), lo, hi);
  return out;
}

// Joint gains (N m/rad, N m s/rad or N/m, N s/m): a 100 kg robot uses 1e3 to 1e5.
constexpr double kMaxGain = 1e9;

// A number for every joint or {joint: value}.
GainSpec gainSpec(const json& obj, const std::string& key, const Where& w) {
  GainSpec out;
  if (!obj.contains(key)) return out;
  const json& v = obj.at(key);
  if (v.is_number()) {
    out.all = checkNumber(v, w / key, atLeast(0), atMost(kMaxGain));
  } else if (v.is_object()) {
    out.joints = jointValues(v, w / key, atLeast(0), atMost(kMaxGain));
  } else {
    (w / key).fail("expected a number (every actuated joint) or an object {joint name: value}, got " + jsonForMessage(v));
  }
  return out;
}

json toJson(const JointValues& values) {
  json out = json::object();
  for (const auto& [name, value] : values) out[name] = value;
  return out;
}
json toJson(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

std::string absolute(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) p = path;
  return p.lexically_normal().string();
}

// " (the folder F does not exist)" for the outermost missing folder above a missing file, which
// says at once when a whole tree is absent (e.g. ../shared with the robots); "" if its folder exists.
std::string missingFolderNote(const fs::path& file) {
  fs::path missing;
  for (fs::path dir = file.parent_path(); !dir.empty() && dir != dir.parent_path() && !pathExists(dir.string());
       dir = dir.parent_path())
    missing = dir;
  return missing.empty() ? "" : " (the folder " + displayPath(missing.string()) + " does not exist)";
}

// What a path value must name when the scene is read.
enum class PathKind {
  Output,       // nothing yet (the output file)
  Existing,     // a file or a folder (a contact model may be a folder of text files)
  RegularFile,  // a regular file (URDF, terrain and keyframe files)
};

// A path value: a string, resolved against the scene's folder and checked as `kind` says.
std::string pathValue(const json& obj, const std::string& key, const Where& w, const std::string& base_dir,
                      PathKind kind, const std::string& what = "file") {
  const json& v = obj.at(key);
  if (!v.is_string() || v.get<std::string>().empty()) (w / key).fail("expected a file path, got " + jsonForMessage(v));
  const std::string& given = v.get<std::string>();
  if (given.size() > limits::kMaxPathLength || given.find('\0') != std::string::npos)
    (w / key).fail("not a usable path: " + std::to_string(given.size()) + " characters" +
                   (given.find('\0') != std::string::npos ? " with a NUL character" : "") + " (at most " +
                   std::to_string(limits::kMaxPathLength) + ")");
  const std::string resolved = absolute(ConfigContext{"", base_dir}.resolve(given));
  if (kind == PathKind::Output) return resolved;
  if (!pathExists(resolved)) (w / key).fail("file not found: " + displayPath(resolved) + missingFolderNote(resolved));
  if (kind == PathKind::RegularFile) {
    try {
      requireRegularFile(resolved, what);
    } catch (const InputError& e) {
      (w / key).fail(e.what());
    }
  }
  return resolved;
}

const std::vector<std::string> kTopKeys = {"robot", "contacts", "terrain", "integrator", "controller", "duration", "output"};
const std::vector<std::string> kRobotKeys = {"urdf", "base", "locked_joints", "armature", "initial"};
const std::vector<std::string> kInitialKeys = {"height", "joints", "base_position", "base_rpy", "velocity"};
const std::vector<std::string> kVelocityKeys = {"base_linear", "base_angular"};
const std::vector<std::string> kContactsKeys = {"points", "model"};
const std::vector<std::string> kPointKeys = {"link", "offset", "radius", "name", "leg_axis"};
const std::vector<std::string> kIntegratorKeys = {
    "method", "order", "dt", "adaptive", "min_substep", "kinetic_energy", "epsilon", "tol_w", "eta", "eta_reject", "eta_limited",
    "beta_min", "beta_max", "beta_initial", "adapt_start_penalty", "max_outer_iterations", "projection_tolerance",
    "projection_max_iterations", "projection_backtracking", "warm_start_weights", "predict_first_iterate",
    "zeroth_order_jacobian", "accuracy"};
const std::vector<std::string> kControllerKeys = {"kp", "kd", "tau_ff", "gait"};
const std::vector<std::string> kOutputKeys = {"file", "every"};
const std::vector<std::string> kGaitTypes = {"stand", "trot", "jump", "keyframes"};

const std::vector<std::string>& gaitKeys(SceneGaitType type) {
  static const std::vector<std::string> stand = {"type", "height"};
  static const std::vector<std::string> trot = {"type",   "height",      "stride_length", "step_height",
                                                 "period", "duty_factor", "swing_profile", "ground_speed_share",
                                                 "start_ramp"};
  static const std::vector<std::string> jump = {"type", "height", "crouch_depth", "push_off_height", "period", "pause"};
  static const std::vector<std::string> keyframes = {"type", "height", "file", "cyclic", "period"};
  switch (type) {
    case SceneGaitType::Stand: return stand;
    case SceneGaitType::Trot: return trot;
    case SceneGaitType::Jump: return jump;
    case SceneGaitType::Keyframes: return keyframes;
  }
  return stand;
}

// ---- sections -----------------------------------------------------------------------------------

// Bounds of the robot's keys: joint values and angles (rad or m), positions (m), speeds (m/s,
// rad/s), rotor inertias (kg m²), contact sphere offsets and radii (m). Each is far beyond a real
// robot and keeps the arithmetic of a step finite.
constexpr double kMaxJointValue = 1e3;
constexpr double kMaxPosition = 1e6;
constexpr double kMaxSpeed = 1e3;
constexpr double kMaxArmature = 1e6;
constexpr double kMaxContactOffset = 1e3;
constexpr double kMaxContactRadius = 10.0;
// Gait sizes (m) and periods (s).
constexpr double kMaxGaitLength = 100.0;
constexpr double kMaxGaitTime = 1e4;

void parseRobot(const json& robot, const Where& w, SceneConfig& c, json& out) {
  checkKeys(robot, w, kRobotKeys);
  if (!robot.contains("urdf")) w.fail("missing required key 'urdf' (the robot's URDF file, relative to the scene file)");
  c.urdf = pathValue(robot, "urdf", w, c.base_dir, PathKind::RegularFile, "URDF file");
  out["urdf"] = c.urdf;

  const std::string base = readStr(robot, "base", "floating", w);
  if (base == "floating") c.base = BaseType::Floating;
  else if (base == "planar") c.base = BaseType::Planar;
  else if (base == "fixed") c.base = BaseType::Fixed;
  else (w / "base").fail("unknown base type '" + base + "'" + suggestion(base, {"floating", "planar", "fixed"}) + "; valid: floating, planar, fixed");
  out["base"] = base;

  if (robot.contains("locked_joints"))
    c.locked_joints = jointValues(robot.at("locked_joints"), w / "locked_joints", atLeast(-kMaxJointValue), atMost(kMaxJointValue));
  out["locked_joints"] = toJson(c.locked_joints);

  if (robot.contains("armature")) {
    const json& a = robot.at("armature");
    if (a.is_number()) c.default_armature = checkNumber(a, w / "armature", atLeast(0), atMost(kMaxArmature));
    else if (a.is_object()) c.armature = jointValues(a, w / "armature", atLeast(0), atMost(kMaxArmature));
    else (w / "armature").fail("expected a number (every actuated joint) or an object {joint name: value}, got " + jsonForMessage(a));
    out["armature"] = a;
  } else {
    out["armature"] = 0.0;
  }

  const json initial = robot.contains("initial") ? robot.at("initial") : json::object();
  const Where wi = w / "initial";
  checkKeys(initial, wi, kInitialKeys);
  json& oi = out["initial"] = json::object();
  if (initial.contains("joints")) {
    c.initial_joints = jointValues(initial.at("joints"), wi / "joints", atLeast(-kMaxJointValue), atMost(kMaxJointValue));
    oi["joints"] = toJson(c.initial_joints);
  }
  c.initial_height = optionalNumber(initial, "height", wi, atLeast(-kMaxPosition), atMost(kMaxPosition));
  if (initial.contains("base_position")) {
    const std::vector<double> p =
        numbers(initial.at("base_position"), wi / "base_position", {2, 3}, "[x, y] or [x, y, z]", kMaxPosition);
    c.initial_x = p[0];
    c.initial_y = p[1];
    if (p.size() == 3) c.initial_height = p[2];
  }
  c.initial_rpy = vec3(initial, "base_rpy", wi, kMaxJointValue);
  const json velocity = initial.contains("velocity") ? initial.at("velocity") : json::object();
  checkKeys(velocity, wi / "velocity", kVelocityKeys);
  c.initial_linear_velocity = vec3(velocity, "base_linear", wi / "velocity", kMaxSpeed);
  c.initial_angular_velocity = vec3(velocity, "base_angular", wi / "velocity", kMaxSpeed);

  if (c.base == BaseType::Fixed) {
    for (const char* key : {"height", "base_position", "base_rpy", "velocity"})
      if (initial.contains(key)) (wi / key).fail("a fixed base has no base pose or velocity; remove this key or choose robot.base floating or planar");
    return;
  }
  if (c.base == BaseType::Planar) {
    if (c.initial_y != 0) (wi / "base_position").fail("a planar base moves in the x-z plane: y must be 0");
    if (c.initial_rpy.x() != 0 || c.initial_rpy.z() != 0)
      (wi / "base_rpy").fail("a planar base only pitches: roll and yaw must be 0");
    if (c.initial_linear_velocity.y() != 0)
      (wi / "velocity" / "base_linear").fail("a planar base moves in the x-z plane: the y velocity must be 0");
    if (c.initial_angular_velocity.x() != 0 || c.initial_angular_velocity.z() != 0)
      (wi / "velocity" / "base_angular").fail("a planar base only pitches: the x and z rates must be 0");
  }
  if (c.base == BaseType::Floating && std::abs(std::cos(c.initial_rpy.y())) < 1e-6)
    (wi / "base_rpy").fail("pitch ±π/2 is a singular orientation; tilt the robot slightly less");
  oi["base_position"] = json::array({c.initial_x, c.initial_y});
  if (c.initial_height) oi["height"] = *c.initial_height;
  oi["base_rpy"] = toJson(c.initial_rpy);
  oi["velocity"] = {{"base_linear", toJson(c.initial_linear_velocity)},
                    {"base_angular", toJson(c.initial_angular_velocity)}};
}

void parseContacts(const json& contacts, const Where& w, SceneConfig& c, json& out) {
  checkKeys(contacts, w, kContactsKeys);
  if (contacts.contains("points")) {
    const json& points = contacts.at("points");
    const Where wp = w / "points";
    if (points.is_string()) {
      if (points.get<std::string>() != "auto")
        wp.fail("expected \"auto\" or a list of {\"link\", \"offset\", \"radius\"}, got " + jsonForMessage(points));
    } else if (points.is_array()) {
      c.auto_contacts = false;
      if (points.size() > static_cast<size_t>(limits::kMaxContactPoints))
        wp.fail(std::to_string(points.size()) + " contact points, more than the " + std::to_string(limits::kMaxContactPoints) +
                " a scene may have");
      std::map<std::string, int> uses;
      for (size_t i = 0; i < points.size(); ++i) {
        const Where we = wp / std::to_string(i);
        const json& p = points[i];
        checkKeys(p, we, kPointKeys);
        if (!p.contains("link")) we.fail("missing required key 'link' (the URDF link carrying the contact sphere)");
        ContactPointSpec spec;
        spec.link = readStr(p, "link", "", we);
        spec.offset = vec3(p, "offset", we, kMaxContactOffset);
        spec.radius = number(p, "radius", 0.0, we, atLeast(0), atMost(kMaxContactRadius));
        if (p.contains("leg_axis")) {
          const Vec3 a = vec3(p, "leg_axis", we);
          if (!(a.norm() > 1e-9)) (we / "leg_axis").fail("must be a non-zero vector [x, y, z] in the link frame (from the foot up the leg)");
          spec.leg_axis = a.normalized();
        }
        const int n = uses[spec.link]++;
        spec.name = readStr(p, "name", n == 0 ? spec.link : spec.link + "#" + std::to_string(n + 1), we);
        c.contact_points.push_back(spec);
      }
    } else {
      wp.fail("expected \"auto\" or a list of {\"link\", \"offset\", \"radius\"}, got " + jsonForMessage(points));
    }
  }
  if (c.auto_contacts) {
    out["points"] = "auto";
  } else {
    json list = json::array();
    for (const ContactPointSpec& p : c.contact_points) {
      json point = {{"name", p.name}, {"link", p.link}, {"offset", toJson(p.offset)}, {"radius", p.radius}};
      if (p.leg_axis) point["leg_axis"] = toJson(*p.leg_axis);
      list.push_back(point);
    }
    out["points"] = list;
  }

  c.contact_model = contacts.contains("model") ? contacts.at("model") : json{{"type", "coulomb"}};
  const Where wm = w / "model";
  checkObject(c.contact_model, wm);
  if (!c.contact_model.contains("type")) wm.fail("missing required key 'type' (e.g. \"coulomb\", \"rbf\", \"mlp\")");
  if (!c.contact_model.at("type").is_string()) (wm / "type").fail("expected a string, got " + jsonForMessage(c.contact_model.at("type")));
  // "file" (a model file or folder) must exist; other "*_file" keys are resolved and left to the model.
  for (auto it = c.contact_model.begin(); it != c.contact_model.end(); ++it) {
    const std::string& key = it.key();
    const bool file_key = key == "file" || (key.size() > 5 && key.compare(key.size() - 5, 5, "_file") == 0);
    if (file_key) it.value() = pathValue(c.contact_model, key, wm, c.base_dir, key == "file" ? PathKind::Existing : PathKind::Output);
  }
  out["model"] = c.contact_model;
}

void parseTerrain(const json& terrain, const Where& w, SceneConfig& c) {
  c.terrain = terrain.is_null() ? json{{"type", "plane"}} : terrain;
  checkObject(c.terrain, w);
  if (!c.terrain.contains("type")) c.terrain["type"] = "plane";
  if (c.terrain.contains("file"))
    c.terrain["file"] = pathValue(c.terrain, "file", w, c.base_dir, PathKind::RegularFile, "terrain file");
  makeTerrain(c.terrain, ConfigContext{w.str(), c.base_dir});  // validates every key
}

void parseIntegrator(const json& in, const Where& w, SceneConfig& c, json& out) {
  checkKeys(in, w, kIntegratorKeys);
  IntegratorOptions& o = c.integrator;
  const std::string method = readStr(in, "method", methodName(o.method), w);
  const std::optional<Method> m = parseMethod(method);
  if (!m) (w / "method").fail("unknown method '" + method + "'" + suggestion(method, methodNames()) + "; valid: " + join(methodNames()));
  o.method = *m;
  if (in.contains("order")) {
    const json& v = in.at("order");
    if (!v.is_number_integer() || (v != 1 && v != 2))
      (w / "order").fail("expected 1 (backward Euler, the paper's) or 2 (BDF2), got " + jsonForMessage(v));
    o.order = v.get<int>();
  }
  if (o.order == 2 && o.method == Method::NeMdp)
    (w / "order").fail("ne-mdp is first order only; order 2 needs ne-pgm, ne-zopgm, pbd-pgm or pbd-zopgm");
  const std::string ke = readStr(in, "kinetic_energy", kineticEnergyName(o.kinetic_energy), w);
  const std::optional<KineticEnergyMeasure> k = parseKineticEnergy(ke);
  if (!k) (w / "kinetic_energy").fail("unknown value '" + ke + "'; valid: full-body, contact-points, full-body-pd");
  o.kinetic_energy = *k;
  // dt from 1 µs (a step that small no longer advances the clock of a long run) to 1 s; a step
  // splits at most kMaxSplits times, so one step is at most 2^20 sub-steps of work.
  constexpr double kMinDt = 1e-6;
  constexpr int kMaxSplits = 20;
  c.dt = number(in, "dt", c.dt, w, atLeast(kMinDt), atMost(1));
  o.adaptive = boolean(in, "adaptive", o.adaptive, w);
  o.min_substep = number(in, "min_substep", std::min(o.min_substep, c.dt), w, above(0), atMost(c.dt));
  if (o.min_substep < c.dt / (1 << kMaxSplits))
    (w / "min_substep").fail("must be at least dt / 2^" + std::to_string(kMaxSplits) + " = " + fmt(c.dt / (1 << kMaxSplits)) +
                             " s (a step splits at most " + std::to_string(kMaxSplits) + " times), got " + fmt(o.min_substep));
  o.epsilon = number(in, "epsilon", o.epsilon, w, above(0), atMost(1));
  o.tol_w = number(in, "tol_w", o.tol_w, w, above(0), atMost(1));
  o.eta = number(in, "eta", o.eta, w, above(1), atMost(1e3));
  o.eta_reject = number(in, "eta_reject", o.eta_reject, w, above(1), atMost(1e3));
  o.eta_limited = number(in, "eta_limited", o.eta_limited, w, above(1), atMost(1e3));
  o.beta_min = number(in, "beta_min", o.beta_min, w, above(0), atMost(1e6));
  o.beta_max = number(in, "beta_max", o.beta_max, w, above(o.beta_min), atMost(1e12));
  o.beta_initial = number(in, "beta_initial", std::clamp(o.beta_initial, o.beta_min, o.beta_max), w,
                          atLeast(o.beta_min), atMost(o.beta_max));
  o.adapt_start_penalty = boolean(in, "adapt_start_penalty", o.adapt_start_penalty, w);
  o.max_outer_iterations = integer(in, "max_outer_iterations", o.max_outer_iterations, w, 1, 100000);
  o.projection_tolerance = number(in, "projection_tolerance", o.projection_tolerance, w, above(0), atMost(1));
  o.projection_max_iterations = integer(in, "projection_max_iterations", o.projection_max_iterations, w, 1, 10000);
  o.projection_backtracking = integer(in, "projection_backtracking", o.projection_backtracking, w, 0, 60);
  o.warm_start_weights = boolean(in, "warm_start_weights", o.warm_start_weights, w);
  o.predict_first_iterate = boolean(in, "predict_first_iterate", o.predict_first_iterate, w);
  const std::string zo = readStr(in, "zeroth_order_jacobian", zerothOrderJacobianName(o.zeroth_order_jacobian), w);
  const std::optional<ZerothOrderJacobian> z = parseZerothOrderJacobian(zo);
  if (!z) (w / "zeroth_order_jacobian").fail("unknown value '" + zo + "'; valid: finite-difference, dropped");
  o.zeroth_order_jacobian = *z;
  o.accuracy = number(in, "accuracy", o.accuracy, w, atLeast(0), atMost(1));

  out = {{"method", methodName(o.method)},
         {"order", o.order},
         {"kinetic_energy", kineticEnergyName(o.kinetic_energy)},
         {"dt", c.dt},
         {"adaptive", o.adaptive},
         {"min_substep", o.min_substep},
         {"epsilon", o.epsilon},
         {"tol_w", o.tol_w},
         {"eta", o.eta},
         {"eta_reject", o.eta_reject},
         {"eta_limited", o.eta_limited},
         {"beta_min", o.beta_min},
         {"beta_max", o.beta_max},
         {"beta_initial", o.beta_initial},
         {"adapt_start_penalty", o.adapt_start_penalty},
         {"max_outer_iterations", o.max_outer_iterations},
         {"projection_tolerance", o.projection_tolerance},
         {"projection_max_iterations", o.projection_max_iterations},
         {"projection_backtracking", o.projection_backtracking},
         {"warm_start_weights", o.warm_start_weights},
         {"predict_first_iterate", o.predict_first_iterate},
         {"zeroth_order_jacobian", zerothOrderJacobianName(o.zeroth_order_jacobian)},
         {"accuracy", o.accuracy}};
}

void parseGait(const json& in, const Where& w, SceneConfig& c, json& out) {
  checkObject(in, w);
  const std::string type = readStr(in, "type", "stand", w);
  const auto found = std::find(kGaitTypes.begin(), kGaitTypes.end(), type);
  if (found == kGaitTypes.end())
    (w / "type").fail("unknown gait type '" + type + "'" + suggestion(type, kGaitTypes) + "; valid: " + join(kGaitTypes));
  c.gait_type = static_cast<SceneGaitType>(found - kGaitTypes.begin());
  const std::vector<std::string>& valid = gaitKeys(c.gait_type);
  std::vector<std::string> all;
  for (SceneGaitType t : {SceneGaitType::Stand, SceneGaitType::Trot, SceneGaitType::Jump, SceneGaitType::Keyframes})
    for (const std::string& k : gaitKeys(t))
      if (std::find(all.begin(), all.end(), k) == all.end()) all.push_back(k);
  for (auto it = in.begin(); it != in.end(); ++it) {
    if (std::find(valid.begin(), valid.end(), it.key()) != valid.end()) continue;
    if (std::find(all.begin(), all.end(), it.key()) != all.end())
      (w / it.key()).fail("not a parameter of gait type '" + type + "'; valid keys for " + type + ": " + join(valid));
    (w / it.key()).fail("unknown key" + suggestion(it.key(), valid) + "; valid keys for gait type " + type + ": " + join(valid));
  }

  out = json::object();
  out["type"] = type;
  GaitParameters& g = c.gait;
  g.stand.height = optionalNumber(in, "height", w, above(0), atMost(kMaxGaitLength));
  if (g.stand.height) out["height"] = *g.stand.height;
  switch (c.gait_type) {
    case SceneGaitType::Stand: g.type = GaitType::Stand; break;
    case SceneGaitType::Trot:
      g.type = GaitType::Trot;
      g.trot.stride_length = optionalNumber(in, "stride_length", w, atLeast(0), atMost(kMaxGaitLength));
      g.trot.step_height = optionalNumber(in, "step_height", w, atLeast(0), atMost(kMaxGaitLength));
      g.trot.period = number(in, "period", g.trot.period, w, above(0), atMost(kMaxGaitTime));
      g.trot.duty_factor = number(in, "duty_factor", g.trot.duty_factor, w, above(0), below(1));
      {
        const std::string profile = readStr(in, "swing_profile", swingProfileName(g.trot.swing_profile), w);
        try {
          g.trot.swing_profile = parseSwingProfile(profile);
        } catch (const std::invalid_argument& e) {
          (w / "swing_profile").fail(e.what());  // names the valid profiles
        }
      }
      g.trot.ground_speed_share = number(in, "ground_speed_share", g.trot.ground_speed_share, w, atLeast(0), below(1));
      g.trot.start_ramp = number(in, "start_ramp", g.trot.start_ramp, w, atLeast(0), atMost(kMaxGaitTime));
      if (g.trot.stride_length) out["stride_length"] = *g.trot.stride_length;
      if (g.trot.step_height) out["step_height"] = *g.trot.step_height;
      out["period"] = g.trot.period;
      out["duty_factor"] = g.trot.duty_factor;
      out["swing_profile"] = swingProfileName(g.trot.swing_profile);
      out["ground_speed_share"] = g.trot.ground_speed_share;
      out["start_ramp"] = g.trot.start_ramp;
      break;
    case SceneGaitType::Jump:
      g.type = GaitType::Jump;
      g.jump.crouch_depth = optionalNumber(in, "crouch_depth", w, atLeast(0), atMost(kMaxGaitLength));
      g.jump.push_off_height = optionalNumber(in, "push_off_height", w, above(0), atMost(kMaxGaitLength));
      g.jump.period = number(in, "period", g.jump.period, w, above(0), atMost(kMaxGaitTime));
      g.jump.pause = number(in, "pause", g.jump.pause, w, atLeast(0), below(g.jump.period));
      if (g.jump.crouch_depth) out["crouch_depth"] = *g.jump.crouch_depth;
      if (g.jump.push_off_height) out["push_off_height"] = *g.jump.push_off_height;
      out["period"] = g.jump.period;
      out["pause"] = g.jump.pause;
      break;
    case SceneGaitType::Keyframes:
      g.type = GaitType::Stand;  // the standing pose fills the coordinates the file does not list
      if (!in.contains("file")) w.fail("missing required key 'file' for gait type keyframes (a CSV or JSON keyframe file)");
      c.keyframe_file = pathValue(in, "file", w, c.base_dir, PathKind::RegularFile, "keyframe file");
      c.keyframes_cyclic = boolean(in, "cyclic", false, w);
      c.keyframe_period = optionalNumber(in, "period", w, above(0), atMost(kMaxGaitTime));
      if (c.keyframe_period && !c.keyframes_cyclic) (w / "period").fail("only used with \"cyclic\": true");
      out["file"] = c.keyframe_file;
      out["cyclic"] = c.keyframes_cyclic;
      if (c.keyframe_period) out["period"] = *c.keyframe_period;
      break;
  }
}

void parseController(const json& in, const Where& w, SceneConfig& c, json& out) {
  checkKeys(in, w, kControllerKeys);
  c.kp = gainSpec(in, "kp", w);
  c.kd = gainSpec(in, "kd", w);
  if (in.contains("tau_ff")) c.tau_ff = jointValues(in.at("tau_ff"), w / "tau_ff", atLeast(-kMaxGain), atMost(kMaxGain));
  out = json::object();
  if (in.contains("kp")) out["kp"] = in.at("kp");
  if (in.contains("kd")) out["kd"] = in.at("kd");
  out["tau_ff"] = toJson(c.tau_ff);
  parseGait(in.contains("gait") ? in.at("gait") : json::object(), w / "gait", c, out["gait"]);
}

// ---- model-dependent helpers ----------------------------------------------------------------------

std::string fileOf(const SceneConfig& c) { return c.path; }

// The coordinate index of an actuated joint; InputError naming `w` otherwise.
int actuatedIndex(const Model& model, const SceneConfig& c, const std::string& joint, const Where& w) {
  const int i = model.dofIndex(joint);
  if (i >= 0 && !model.bodies[i].is_base) return i;
  if (c.locked_joints.count(joint)) w.fail("joint '" + joint + "' is locked (robot.locked_joints); it has no coordinate");
  std::vector<std::string> names;
  for (int k = 0; k < model.nq; ++k)
    if (!model.bodies[k].is_base) names.push_back(model.dof_names[k]);
  w.fail("the robot (" + model.source + ") has no actuated joint '" + joint + "'" + suggestion(joint, names) +
         "; its joints: " + join(names));
}

void checkJointNames(const Model& model, const SceneConfig& c, const JointValues& values, const Where& w) {
  for (const auto& [name, value] : values) actuatedIndex(model, c, name, w / name);
}

int linkIndexOrThrow(const Model& model, const std::string& link, const Where& w) {
  const int i = model.linkIndex(link);
  if (i >= 0) return i;
  std::vector<std::string> names;
  for (const Link& l : model.links) names.push_back(l.name);
  w.fail("the robot (" + model.source + ") has no link '" + link + "'" + suggestion(link, names));
}

// Standing pose and legs, if the robot is a quadruped and the pose can be built; the error otherwise.
struct Standing {
  std::optional<StandingPose> pose;
  bool quadruped = false;
  std::string error;
};
Standing standingFrom(const Model& model, const StandParameters& stand) {
  Standing out;
  try {
    const QuadrupedLegs legs = identifyQuadrupedLegs(model, stand.nominal_q);
    out.quadruped = true;
    out.pose = standingPose(model, legs, stand);
  } catch (const std::invalid_argument& e) {
    out.error = e.what();
  }
  return out;
}

// The built-in gaits' stand parameters: controller.gait.height, and robot.initial.joints as the
// nominal pose (StandParameters::nominal_q), its unlisted joints as in the standing pose without it
// (0 if there is none). A robot whose legs do not hang under it at q = 0 (RoboSimian's stretch out
// level) needs this bent pose to stand. Keyframes start from the default standing pose instead:
// there robot.initial.joints only overrides the first frame.
StandParameters standParameters(const SceneConfig& c, const Model& model) {
  StandParameters stand = c.gait.stand;
  if (c.gait_type == SceneGaitType::Keyframes || c.initial_joints.empty()) return stand;
  const Where wj{fileOf(c), "robot.initial.joints"};
  size_t actuated = 0;
  for (int i = 0; i < model.nq; ++i) actuated += !model.bodies[i].is_base;
  Eigen::VectorXd nominal = Eigen::VectorXd::Zero(model.nq);
  if (c.initial_joints.size() < actuated) {
    const Standing fill = standingFrom(model, c.gait.stand);
    if (fill.pose) nominal = fill.pose->q;
  }
  for (const auto& [name, value] : c.initial_joints) nominal[actuatedIndex(model, c, name, wj / name)] = value;
  stand.nominal_q = nominal;
  return stand;
}

Standing standing(const SceneConfig& c, const Model& model) { return standingFrom(model, standParameters(c, model)); }

// The message for a built-in gait whose standing pose cannot be built.
std::string standingFailure(const SceneConfig& c, const Standing& s) {
  std::string what = std::string("gait type '") + sceneGaitTypeName(c.gait_type) + "' cannot be built: " + s.error;
  if (s.quadruped && c.initial_joints.empty())
    what += "; give the nominal standing pose (legs bent under the trunk) in robot.initial.joints";
  return what;
}

// Keyframes of one file: a motion sampled at 1 kHz for 15 minutes has 10^6.
constexpr size_t kMaxKeyframes = 1000000;

struct Keyframes {
  std::vector<double> times;
  std::vector<std::string> joints;
  std::vector<std::vector<double>> columns;  // per joint, per keyframe
};

[[noreturn]] void keyframeFail(const SceneConfig& c, const std::string& what) {
  (Where{fileOf(c), "controller.gait.file"}).fail(displayPath(c.keyframe_file) + ": " + what);
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) {
    const size_t a = cell.find_first_not_of(" \t\r");
    const size_t b = cell.find_last_not_of(" \t\r");
    out.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

Keyframes readKeyframes(const SceneConfig& c) {
  std::string text;
  try {
    text = readInputFile(c.keyframe_file, "keyframe file");
  } catch (const InputError& e) {
    (Where{fileOf(c), "controller.gait.file"}).fail(e.what());
  }
  Keyframes k;
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '{') {
    json j;
    try {
      j = parseJson(text, displayPath(c.keyframe_file));
    } catch (const InputError& e) {
      (Where{fileOf(c), "controller.gait.file"}).fail(e.what());
    }
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "times" && it.key() != "joints")
        keyframeFail(c, "unknown key '" + it.key() + "'; valid keys: times, joints");
    if (!j.contains("times") || !j.contains("joints"))
      keyframeFail(c, "expected {\"times\": [...], \"joints\": {name: [...]}}");
    const json& times = j.at("times");
    if (!times.is_array()) keyframeFail(c, "times: expected a list of numbers");
    if (times.size() > kMaxKeyframes) keyframeFail(c, "times: more than " + std::to_string(kMaxKeyframes) + " keyframes");
    if (j.at("joints").is_object() && j.at("joints").size() > static_cast<size_t>(limits::kMaxJoints))
      keyframeFail(c, "joints: more than " + std::to_string(limits::kMaxJoints) + " joints");
    for (const json& t : times) {
      if (!t.is_number() || !std::isfinite(t.get<double>())) keyframeFail(c, "times: expected a list of numbers, got " + jsonForMessage(t));
      k.times.push_back(t.get<double>());
    }
    if (!j.at("joints").is_object()) keyframeFail(c, "joints: expected an object {name: [values]}");
    for (auto it = j.at("joints").begin(); it != j.at("joints").end(); ++it) {
      std::vector<double> column;
      if (!it.value().is_array() || it.value().size() != k.times.size())
        keyframeFail(c, "joints." + it.key() + ": expected " + std::to_string(k.times.size()) + " numbers (one per time)");
      for (const json& x : it.value()) {
        if (!x.is_number() || !std::isfinite(x.get<double>())) keyframeFail(c, "joints." + it.key() + ": expected numbers, got " + jsonForMessage(x));
        column.push_back(x.get<double>());
      }
      k.joints.push_back(it.key());
      k.columns.push_back(column);
    }
  } else {
    std::stringstream lines(text);
    std::string line;
    int line_number = 0;
    bool header = false;
    while (std::getline(lines, line)) {
      ++line_number;
      if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
      const std::vector<std::string> cells = splitCsv(line);
      if (!header) {
        header = true;
        if (cells.empty() || cells[0] != "time")
          keyframeFail(c, "line " + std::to_string(line_number) + ": the header must be time,<joint names...>");
        if (cells.size() > static_cast<size_t>(limits::kMaxJoints) + 1)
          keyframeFail(c, "line " + std::to_string(line_number) + ": more than " + std::to_string(limits::kMaxJoints) + " joints");
        k.joints.assign(cells.begin() + 1, cells.end());
        for (const std::string& name : k.joints)
          if (name.empty()) keyframeFail(c, "line " + std::to_string(line_number) + ": empty joint name in the header");
        k.columns.assign(k.joints.size(), {});
        continue;
      }
      if (cells.size() != k.joints.size() + 1)
        keyframeFail(c, "line " + std::to_string(line_number) + ": expected " + std::to_string(k.joints.size() + 1) +
                            " values, got " + std::to_string(cells.size()));
      if (k.times.size() >= kMaxKeyframes)
        keyframeFail(c, "line " + std::to_string(line_number) + ": more than " + std::to_string(kMaxKeyframes) + " keyframes");
      for (size_t i = 0; i < cells.size(); ++i) {
        double v = 0;
        try {
          size_t used = 0;
          v = std::stod(cells[i], &used);
          if (used != cells[i].size() || !std::isfinite(v)) throw std::invalid_argument(cells[i]);
        } catch (const std::exception&) {
          keyframeFail(c, "line " + std::to_string(line_number) + ", column " + std::to_string(i + 1) + ": '" +
                              cells[i].substr(0, 40) + (cells[i].size() > 40 ? "..." : "") + "' is not a number");
        }
        if (i == 0) k.times.push_back(v);
        else k.columns[i - 1].push_back(v);
      }
    }
    if (!header) keyframeFail(c, "empty file; expected the header time,<joint names...> and one row per keyframe");
  }
  if (k.times.empty()) keyframeFail(c, "no keyframes");
  for (size_t i = 1; i < k.times.size(); ++i)
    if (!(k.times[i] > k.times[i - 1]))
      keyframeFail(c, "times must increase strictly (keyframe " + std::to_string(i + 1) + ": " + fmt(k.times[i]) +
                          " after " + fmt(k.times[i - 1]) + ")");
  std::set<std::string> listed;
  for (const std::string& name : k.joints)
    if (!listed.insert(name).second) keyframeFail(c, "joint '" + name + "' is listed twice");
  return k;
}

// The pose the coordinates a keyframe file does not list hold: standing pose, or q = 0.
Eigen::VectorXd holdPose(const SceneConfig& c, const Model& model) {
  const Standing s = standing(c, model);
  if (s.pose) return s.pose->q;
  return Eigen::VectorXd::Zero(model.nq);
}

// Keyframe positions (nq each) from the file over the base pose.
std::vector<Eigen::VectorXd> keyframePositions(const SceneConfig& c, const Model& model, const Keyframes& k,
                                               const Eigen::VectorXd& base) {
  std::vector<int> index;
  for (const std::string& name : k.joints) {
    const int i = model.dofIndex(name);
    if (i < 0 || model.bodies[i].is_base) {
      std::vector<std::string> names;
      for (int j = 0; j < model.nq; ++j)
        if (!model.bodies[j].is_base) names.push_back(model.dof_names[j]);
      keyframeFail(c, "the robot has no actuated joint '" + name + "'" + suggestion(name, names));
    }
    index.push_back(i);
  }
  std::vector<Eigen::VectorXd> positions(k.times.size(), base);
  for (size_t f = 0; f < k.times.size(); ++f)
    for (size_t j = 0; j < index.size(); ++j) positions[f][index[j]] = k.columns[j][f];
  return positions;
}


// Writes the base coordinates of q (or q̇) from a world translation and rotation vector triple.
void setBase(const Model& model, const Vec3& translation, const Vec3& angles, Eigen::VectorXd& q) {
  for (int i = 0; i < model.nq; ++i) {
    const Body& b = model.bodies[i];
    if (!b.is_base) continue;
    int axis = 0;
    for (int k = 0; k < 3; ++k)
      if (std::abs(b.axis[k]) > 0.5) axis = k;
    q[i] = b.kind == JointKind::Prismatic ? translation[axis] : angles[axis];
  }
}

int verticalBaseIndex(const Model& model) {
  for (int i = 0; i < model.nq; ++i)
    if (model.bodies[i].is_base && model.bodies[i].kind == JointKind::Prismatic && std::abs(model.bodies[i].axis.z()) > 0.5)
      return i;
  return -1;
}

// The start pose's joints (the base is set by the caller): a built-in gait's standing pose, solved
// from robot.initial.joints (standParameters); otherwise the first keyframe, or q = 0, with the
// joints of robot.initial.joints set as given.
Eigen::VectorXd startJoints(const SceneConfig& c, const Model& model) {
  Eigen::VectorXd q;
  if (c.gait_type == SceneGaitType::Keyframes) {
    q = keyframePositions(c, model, readKeyframes(c), holdPose(c, model)).front();
  } else {
    const Standing s = standing(c, model);
    if (s.pose) return s.pose->q;
    q = Eigen::VectorXd::Zero(model.nq);
  }
  const Where wj{fileOf(c), "robot.initial.joints"};
  for (const auto& [name, value] : c.initial_joints) q[actuatedIndex(model, c, name, wj / name)] = value;
  return q;
}

}  // namespace

const char* sceneGaitTypeName(SceneGaitType type) { return kGaitTypes[static_cast<int>(type)].c_str(); }

// ---- loading and overrides ------------------------------------------------------------------------

json loadSceneJson(const std::string& path) {
  const json scene = parseJson(readInputFile(path, "scene file"), displayPath(path));
  if (!scene.is_object())
    throw InputError(displayPath(path) + ": expected a JSON object {\"robot\": ..., ...}, got " + std::string(scene.type_name()));
  return scene;
}

void applyOverride(json& scene, const std::string& assignment, const std::string& file) {
  // The assignment as messages show it: an absurdly long one is shortened like a path.
  const std::string prefix = (file.empty() ? "" : file + ": ") + "--set " + displayPath(assignment) + ": ";
  if (!isValidUtf8(assignment)) throw InputError(prefix + "not valid UTF-8 text");
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos) throw InputError(prefix + "expected key.path=value (e.g. integrator.dt=0.01)");
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  std::vector<std::string> segments;
  {
    size_t start = 0;
    while (true) {
      const size_t dot = key.find('.', start);
      segments.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
  }
  for (const std::string& s : segments)
    if (s.empty()) throw InputError(prefix + "empty key" + (key.empty() ? "" : " segment in '" + key + "'") + "; expected key.path=value");
  if (segments.size() > static_cast<size_t>(limits::kMaxJsonDepth))
    throw InputError(prefix + "the key has " + std::to_string(segments.size()) + " levels, more than the " +
                     std::to_string(limits::kMaxJsonDepth) + " a scene may nest");

  // A plain string unless it is JSON: --set integrator.method=ne-zopgm.
  const json value = isJson(text) ? parseJson(text, prefix.substr(0, prefix.size() - 2)) : json(text);

  if (!scene.is_object()) scene = json::object();
  json* node = &scene;
  std::string walked;
  for (size_t i = 0; i < segments.size(); ++i) {
    const std::string& s = segments[i];
    const bool last = i + 1 == segments.size();
    json* next = nullptr;
    if (node->is_array()) {
      size_t used = 0;
      long index = -1;
      try {
        index = std::stol(s, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != s.size() || index < 0 || static_cast<size_t>(index) >= node->size())
        throw InputError(prefix + "'" + walked + "' is a list of " + std::to_string(node->size()) +
                         " items; expected an index 0.." + std::to_string(static_cast<long>(node->size()) - 1) + ", got '" + s + "'");
      next = &(*node)[static_cast<size_t>(index)];
    } else {
      if (!node->contains(s) && !last) (*node)[s] = json::object();
      next = &(*node)[s];
    }
    walked += (walked.empty() ? "" : ".") + s;
    if (last) {
      *next = value;
      return;
    }
    if (!next->is_object() && !next->is_array())
      throw InputError(prefix + "'" + walked + "' is " + jsonForMessage(*next) + ", not an object; cannot set a key inside it");
    node = next;
  }
}

// ---- parsing ----------------------------------------------------------------------------------------

SceneConfig parseScene(const json& scene, const std::string& path) {
  SceneConfig c;
  c.path = path;
  c.base_dir = fs::path(absolute(path)).parent_path().string();
  const Where top{path, ""};
  checkKeys(scene, top, kTopKeys);
  json& out = c.resolved = json::object();

  if (!scene.contains("robot")) top.fail("missing required key 'robot' (at least {\"urdf\": \"robot.urdf\"})");
  parseRobot(scene.at("robot"), top / "robot", c, out["robot"]);
  parseContacts(scene.contains("contacts") ? scene.at("contacts") : json::object(), top / "contacts", c, out["contacts"]);
  parseTerrain(scene.contains("terrain") ? scene.at("terrain") : json(), top / "terrain", c);
  out["terrain"] = c.terrain;
  parseIntegrator(scene.contains("integrator") ? scene.at("integrator") : json::object(), top / "integrator", c,
                  out["integrator"]);
  parseController(scene.contains("controller") ? scene.at("controller") : json::object(), top / "controller", c,
                  out["controller"]);
  // Not capped at kMaxMagnitude: what bounds a duration is its number of steps, said below.
  if (scene.contains("duration")) {
    const json& v = scene.at("duration");
    const Where wd = top / "duration";
    if (!v.is_number()) wd.fail("expected a number, got " + jsonForMessage(v));
    c.duration = v.get<double>();
    if (!(c.duration > 0) || !std::isfinite(c.duration)) wd.fail("must be > 0, got " + jsonForMessage(v));
  }
  // The run's step count must be storable (limits::kMaxSteps): 1e308 s would overflow it.
  if (!(c.duration / c.dt <= limits::kMaxSteps))
    top.fail("duration " + fmt(c.duration) + " s at integrator.dt " + fmt(c.dt) + " s is " + fmt(c.duration / c.dt) +
             " steps, more than the " + fmt(limits::kMaxSteps) + " a run can count and store; shorten duration or lengthen integrator.dt");
  out["duration"] = c.duration;

  const json output = scene.contains("output") ? scene.at("output") : json::object();
  const Where wo = top / "output";
  checkKeys(output, wo, kOutputKeys);
  if (output.contains("file")) c.output_file = pathValue(output, "file", wo, c.base_dir, PathKind::Output);
  else c.output_file = absolute(fs::path(path).stem().string() + ".h5");
  c.output_every = integer(output, "every", 1, wo, 1);
  out["output"] = {{"file", c.output_file}, {"every", c.output_every}};
  return c;
}

// ---- with the model ---------------------------------------------------------------------------------

void validateAgainstModel(const SceneConfig& c, const Model& model) {
  const Where top{fileOf(c), ""};
  checkJointNames(model, c, c.initial_joints, top / "robot" / "initial" / "joints");
  checkJointNames(model, c, c.armature, top / "robot" / "armature");
  checkJointNames(model, c, c.kp.joints, top / "controller" / "kp");
  checkJointNames(model, c, c.kd.joints, top / "controller" / "kd");
  checkJointNames(model, c, c.tau_ff, top / "controller" / "tau_ff");
  if (c.auto_contacts) {
    if (detectFeet(model).empty())
      (top / "contacts" / "points").fail("\"auto\" found no feet on " + model.source +
                                         " (no leg has collision geometry); list the contact points as [{\"link\": ..., \"offset\": [x, y, z], \"radius\": r}]");
  } else {
    for (size_t i = 0; i < c.contact_points.size(); ++i)
      linkIndexOrThrow(model, c.contact_points[i].link, top / "contacts" / "points" / std::to_string(i) / "link");
  }
  if (c.gait_type != SceneGaitType::Keyframes) {
    // Trot and jump need a quadruped's standing pose; stand holds the start pose of other robots.
    const Standing s = standing(c, model);
    if (!s.pose && (s.quadruped || c.gait_type != SceneGaitType::Stand)) (top / "controller" / "gait").fail(standingFailure(c, s));
  }
  if (c.gait_type == SceneGaitType::Keyframes) keyframePositions(c, model, readKeyframes(c), Eigen::VectorXd::Zero(model.nq));
}

json resolvedWithModel(const SceneConfig& c, const Model& model) {
  validateAgainstModel(c, model);
  json out = c.resolved;
  const PdGains gains = gainsFor(c, model);
  json kp = json::object(), kd = json::object(), joints = json::object();
  const Eigen::VectorXd q = initialConfiguration(c, model);
  for (int i = 0; i < model.nq; ++i) {
    if (model.bodies[i].is_base) continue;
    kp[model.dof_names[i]] = gains.kp[i];
    kd[model.dof_names[i]] = gains.kd[i];
    joints[model.dof_names[i]] = q[i];
  }
  out["controller"]["kp"] = kp;
  out["controller"]["kd"] = kd;
  json& initial = out["robot"]["initial"];
  initial["joints"] = joints;
  const int z = verticalBaseIndex(model);
  if (z >= 0) initial["height"] = q[z];

  json points = json::array();
  for (const ContactPoint& p : contactPointsFor(c, model))
    points.push_back({{"name", p.name}, {"link", model.links[p.link].name}, {"offset", toJson(p.offset)}, {"radius", p.radius}});
  out["contacts"]["points"] = points;

  const Standing s = standing(c, model);
  if (s.pose) {
    json& gait = out["controller"]["gait"];
    gait["height"] = s.pose->height;
    if (c.gait_type == SceneGaitType::Trot) {
      const TrotParameters t = withRobotDefaults(c.gait.trot, *s.pose);
      gait["stride_length"] = *t.stride_length;
      gait["step_height"] = *t.step_height;
    } else if (c.gait_type == SceneGaitType::Jump) {
      const JumpParameters j = withRobotDefaults(c.gait.jump, *s.pose);
      gait["crouch_depth"] = *j.crouch_depth;
      gait["push_off_height"] = *j.push_off_height;
    }
  }
  return out;
}

UrdfOptions urdfOptionsFor(const SceneConfig& c) {
  UrdfOptions o;
  o.base = c.base;
  o.locked_joints = c.locked_joints;
  o.armature = c.armature;
  o.default_armature = c.default_armature;
  return o;
}

std::vector<ContactPoint> contactPointsFor(const SceneConfig& c, const Model& model) {
  std::vector<ContactPoint> out;
  const Where top{fileOf(c), ""};
  if (c.auto_contacts) return footContactPoints(model);
  for (size_t i = 0; i < c.contact_points.size(); ++i) {
    const ContactPointSpec& s = c.contact_points[i];
    ContactPoint p;
    p.name = s.name;
    p.link = linkIndexOrThrow(model, s.link, top / "contacts" / "points" / std::to_string(i) / "link");
    p.offset = s.offset;
    p.radius = s.radius;
    p.leg_axis = s.leg_axis ? *s.leg_axis : legAxisOf(model, p.link, p.offset, p.radius);
    out.push_back(p);
  }
  return out;
}

PdGains gainsFor(const SceneConfig& c, const Model& model) {
  const Where top{fileOf(c), ""};
  // Default gains from the joint inertias at the pose the robot starts in (the gait's standing pose
  // for the built-in gaits): control/default_gains.hpp.
  PdGains g = defaultPdGains(model, initialConfiguration(c, model));
  auto apply = [&](const GainSpec& spec, Eigen::VectorXd& values, const Where& w) {
    for (int i = 0; i < model.nq; ++i)
      if (spec.all && !model.bodies[i].is_base) values[i] = *spec.all;
    for (const auto& [name, value] : spec.joints) values[actuatedIndex(model, c, name, w / name)] = value;
  };
  apply(c.kp, g.kp, top / "controller" / "kp");
  apply(c.kd, g.kd, top / "controller" / "kd");
  for (const auto& [name, value] : c.tau_ff) g.tau_ff[actuatedIndex(model, c, name, top / "controller" / "tau_ff" / name)] = value;
  return g;
}

std::unique_ptr<PdTargetSource> gaitFor(const SceneConfig& c, const Model& model) {
  const Where wg{fileOf(c), "controller.gait"};
  if (c.gait_type == SceneGaitType::Keyframes) {
    const Keyframes k = readKeyframes(c);
    std::vector<double> times = k.times;
    std::vector<Eigen::VectorXd> positions = keyframePositions(c, model, k, holdPose(c, model));
    SplineEndMode mode = SplineEndMode::HoldEnds;
    double period = 0.0;
    if (c.keyframes_cyclic) {
      mode = SplineEndMode::Periodic;
      if (c.keyframe_period) {
        period = *c.keyframe_period;
        if (!(period > times.back() - times.front()))
          (wg / "period").fail("must exceed the keyframes' time span " + fmt(times.back() - times.front()) + " s, got " + fmt(period));
      } else {
        if (times.size() < 3)
          keyframeFail(c, "a cyclic motion without controller.gait.period needs at least 3 keyframes, the last repeating the first");
        if ((positions.back() - positions.front()).cwiseAbs().maxCoeff() > 1e-6)
          keyframeFail(c, "with \"cyclic\": true the last keyframe must repeat the first (it closes the cycle), or give controller.gait.period");
        period = times.back() - times.front();
        times.pop_back();
        positions.pop_back();
      }
    }
    try {
      return std::make_unique<KeyframePdTarget>(std::move(times), positions, std::vector<Eigen::VectorXd>{}, mode, period);
    } catch (const std::invalid_argument& e) {
      keyframeFail(c, e.what());
    }
  }
  const Standing s = standing(c, model);
  if (!s.pose) {
    if (c.gait_type != SceneGaitType::Stand || s.quadruped) wg.fail(standingFailure(c, s));
    // Not a quadruped: hold the initial joint pose.
    if (c.gait.stand.height) (wg / "height").fail("needs a quadruped to build a standing pose: " + s.error);
    return std::make_unique<ConstantPdTarget>(initialConfiguration(c, model));
  }
  GaitParameters gait = c.gait;
  gait.stand = standParameters(c, model);
  try {
    return makeGaitTarget(model, gait);
  } catch (const std::invalid_argument& e) {
    wg.fail(std::string("gait type '") + sceneGaitTypeName(c.gait_type) + "' cannot be built: " + e.what());
  }
}

Eigen::VectorXd initialConfiguration(const SceneConfig& c, const Model& model) {
  Eigen::VectorXd q = startJoints(c, model);
  if (model.base == BaseType::Fixed) return q;

  const Vec3 angles = model.base == BaseType::Floating ? baseAnglesFromRpy(c.initial_rpy) : c.initial_rpy;
  setBase(model, Vec3(c.initial_x, c.initial_y, c.initial_height.value_or(0.0)), angles, q);
  const int z = verticalBaseIndex(model);
  if (c.initial_height || z < 0) return q;

  // Default height: shift up or down until the lowest contact sphere touches the terrain.
  const std::vector<ContactPoint> contacts = contactPointsFor(c, model);
  if (contacts.empty()) {
    const Standing s = standing(c, model);
    if (s.pose) q[z] = s.pose->height;
    return q;
  }
  const std::unique_ptr<Terrain> terrain = makeTerrain(c.terrain, ConfigContext{c.path + ": terrain", c.base_dir});
  Data data(model);
  forwardKinematics(model, data, q);
  double shift = -kInf;
  for (const ContactPoint& p : contacts) {
    const Vec3 centre = linkPoint(model, data, p.link, p.offset);
    // Solve φ(centre + s e_z) = radius for s by Newton (exact in one step for a level plane).
    double s = 0.0;
    TerrainQuery tq;
    for (int it = 0; it < 50; ++it) {
      terrain->query(centre + s * Vec3::UnitZ(), tq, true);
      const double f = tq.distance - p.radius;
      const double slope = std::max(tq.gradient.z(), 1e-3);
      const double step = -f / slope;
      s += step;
      if (std::abs(step) < 1e-13) break;
    }
    shift = std::max(shift, s);
  }
  q[z] += shift;
  return q;
}

Eigen::VectorXd initialVelocity(const SceneConfig& c, const Model& model) {
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(model.nq);
  if (model.base == BaseType::Fixed) return qd;
  Vec3 rates = c.initial_angular_velocity;
  if (model.base == BaseType::Floating) {
    // ω = ȧ x + ḃ Rx(a) y + ċ Rx(a) Ry(b) z for R = Rx(a) Ry(b) Rz(c).
    const Vec3 angles = baseAnglesFromRpy(c.initial_rpy);
    const Mat3 Rx = Eigen::AngleAxisd(angles.x(), Vec3::UnitX()).toRotationMatrix();
    const Mat3 Ry = Eigen::AngleAxisd(angles.y(), Vec3::UnitY()).toRotationMatrix();
    Mat3 E;
    E.col(0) = Vec3::UnitX();
    E.col(1) = Rx * Vec3::UnitY();
    E.col(2) = Rx * Ry * Vec3::UnitZ();
    rates = E.partialPivLu().solve(c.initial_angular_velocity);
  }
  setBase(model, c.initial_linear_velocity, rates, qd);
  return qd;
}

}  // namespace nmdp
