// Parsing a scene file: the sections robot, contacts, terrain, integrator, controller (and its
// gait), duration and output, each validated with a message naming the file and the key.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "common/text.hpp"
#include "config/json_params.hpp"
#include "sim/scene_parts.hpp"
#include "sim/scene_schema.hpp"
#include "terrain/material_config.hpp"
#include "terrain/terrain_factory.hpp"

namespace nmdp {

namespace scene_detail {
json toJson(const JointValues& values) {
  json out = json::object();
  for (const auto& [name, value] : values) out[name] = value;
  return out;
}
json toJson(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

}  // namespace scene_detail

namespace {

namespace fs = std::filesystem;
using namespace scene_detail;
using namespace read;

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
    out.joints = namedValues(v, w / key, atLeast(0), atMost(kMaxGain));
  } else {
    (w / key).fail("expected a number (every actuated joint) or an object {joint name: value}, got " + jsonForMessage(v));
  }
  return out;
}

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

// A contact model object's paths: "file" (a model file or folder) must exist; other "*_file" keys
// are resolved and left to the model.
void resolveModelFiles(json& model, const Where& w, const std::string& base_dir) {
  if (!model.is_object()) return;
  for (auto it = model.begin(); it != model.end(); ++it) {
    const std::string& key = it.key();
    const bool file_key = key == "file" || (key.size() > 5 && key.compare(key.size() - 5, 5, "_file") == 0);
    if (file_key) it.value() = pathValue(model, key, w, base_dir, key == "file" ? PathKind::Existing : PathKind::Output);
  }
}

const std::vector<std::string>& gaitKeys(SceneGaitType type) {
  return sceneSectionKeys(std::string("controller.gait:") + sceneGaitTypeName(type));
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
  checkKeys(robot, w, sceneSectionKeys("robot"));
  if (!robot.contains("urdf")) w.fail("missing required key 'urdf' (the robot's URDF file, relative to the scene file)");
  c.urdf = pathValue(robot, "urdf", w, c.base_dir, PathKind::RegularFile, "URDF file");
  out["urdf"] = c.urdf;

  c.base = named(robot, "base", c.base, kBaseTypes, "base type", w);
  const std::string base = nameOf(kBaseTypes, c.base);
  out["base"] = base;

  if (robot.contains("locked_joints"))
    c.locked_joints = namedValues(robot.at("locked_joints"), w / "locked_joints", atLeast(-kMaxJointValue), atMost(kMaxJointValue));
  out["locked_joints"] = toJson(c.locked_joints);

  if (robot.contains("armature")) {
    const json& a = robot.at("armature");
    if (a.is_number()) c.default_armature = checkNumber(a, w / "armature", atLeast(0), atMost(kMaxArmature));
    else if (a.is_object()) c.armature = namedValues(a, w / "armature", atLeast(0), atMost(kMaxArmature));
    else (w / "armature").fail("expected a number (every actuated joint) or an object {joint name: value}, got " + jsonForMessage(a));
    out["armature"] = a;
  } else {
    out["armature"] = 0.0;
  }

  const json initial = robot.contains("initial") ? robot.at("initial") : json::object();
  const Where wi = w / "initial";
  checkKeys(initial, wi, sceneSectionKeys("robot.initial"));
  json& oi = out["initial"] = json::object();
  if (initial.contains("joints")) {
    c.initial_joints = namedValues(initial.at("joints"), wi / "joints", atLeast(-kMaxJointValue), atMost(kMaxJointValue));
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
  checkKeys(velocity, wi / "velocity", sceneSectionKeys("robot.initial.velocity"));
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
  checkKeys(contacts, w, sceneSectionKeys("contacts"));
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
        checkKeys(p, we, sceneSectionKeys("contacts.points[]"));
        if (!p.contains("link")) we.fail("missing required key 'link' (the URDF link carrying the contact sphere)");
        ContactPointSpec spec;
        spec.link = read::string(p, "link", "", we);
        spec.offset = vec3(p, "offset", we, kMaxContactOffset);
        spec.radius = number(p, "radius", 0.0, we, atLeast(0), atMost(kMaxContactRadius));
        if (p.contains("leg_axis")) {
          const Vec3 a = vec3(p, "leg_axis", we);
          if (!(a.norm() > 1e-9)) (we / "leg_axis").fail("must be a non-zero vector [x, y, z] in the link frame (from the foot up the leg)");
          spec.leg_axis = a.normalized();
        }
        const int n = uses[spec.link]++;
        spec.name = read::string(p, "name", n == 0 ? spec.link : spec.link + "#" + std::to_string(n + 1), we);
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
  resolveModelFiles(c.contact_model, wm, c.base_dir);
  out["model"] = c.contact_model;
}

void parseTerrain(const json& terrain, const Where& w, SceneConfig& c) {
  c.terrain = terrain.is_null() ? json{{"type", "plane"}} : terrain;
  checkObject(c.terrain, w);
  if (!c.terrain.contains("type")) c.terrain["type"] = "plane";
  if (c.terrain.contains("file"))
    c.terrain["file"] = pathValue(c.terrain, "file", w, c.base_dir, PathKind::RegularFile, "terrain file");
  // The materials' model files, as contacts.model's (the rest of their shape is checked below).
  if (c.terrain.contains("patches") && c.terrain.at("patches").is_array()) {
    json& patches = c.terrain["patches"];
    for (size_t i = 0; i < patches.size(); ++i)
      if (patches[i].is_object() && patches[i].contains("model"))
        resolveModelFiles(patches[i]["model"], w / ("patches[" + std::to_string(i) + "]") / "model", c.base_dir);
  }
  if (c.terrain.contains("material_map") && c.terrain.at("material_map").is_object()) {
    json& map = c.terrain["material_map"];
    const Where wm = w / "material_map";
    if (map.contains("file")) map["file"] = pathValue(map, "file", wm, c.base_dir, PathKind::RegularFile, "material map file");
    if (map.contains("models") && map.at("models").is_array())
      for (size_t k = 0; k < map.at("models").size(); ++k)
        resolveModelFiles(map["models"][k], wm / ("models[" + std::to_string(k) + "]"), c.base_dir);
  }
  const ConfigContext ctx{w.str(), c.base_dir};
  const std::unique_ptr<Terrain> built = makeTerrain(c.terrain, ctx);  // validates every key
  makeTerrainMaterials(c.terrain, *built, ctx);
}

void parseIntegrator(const json& in, const Where& w, SceneConfig& c, json& out) {
  const IntegratorSettings s = readIntegratorSettings(in, w);
  c.dt = s.dt;
  c.integrator = s.options;
  out = integratorFields().dump(s);
}

void parseGait(const json& in, const Where& w, SceneConfig& c, json& out) {
  checkObject(in, w);
  const std::string type = read::string(in, "type", "stand", w);
  c.gait_type = named(in, "type", SceneGaitType::Stand, kSceneGaitTypes, "gait type", w);
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
        const std::string profile = read::string(in, "swing_profile", swingProfileName(g.trot.swing_profile), w);
        try {
          g.trot.swing_profile = parseSwingProfile(profile);
        } catch (const std::invalid_argument& e) {
          (w / "swing_profile").fail(e.what());  // names the valid profiles
        }
      }
      g.trot.ground_speed_share = number(in, "ground_speed_share", g.trot.ground_speed_share, w, atLeast(0), below(1));
      g.trot.start_ramp = number(in, "start_ramp", g.trot.start_ramp, w, atLeast(0), atMost(kMaxGaitTime));
      if (in.contains("heading_feedback")) g.trot.heading_feedback = boolean(in, "heading_feedback", true, w);
      if (g.trot.stride_length) out["stride_length"] = *g.trot.stride_length;
      if (g.trot.step_height) out["step_height"] = *g.trot.step_height;
      out["period"] = g.trot.period;
      out["duty_factor"] = g.trot.duty_factor;
      out["swing_profile"] = swingProfileName(g.trot.swing_profile);
      out["ground_speed_share"] = g.trot.ground_speed_share;
      out["start_ramp"] = g.trot.start_ramp;
      if (g.trot.heading_feedback) out["heading_feedback"] = *g.trot.heading_feedback;
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
  checkKeys(in, w, sceneSectionKeys("controller"));
  c.kp = gainSpec(in, "kp", w);
  c.kd = gainSpec(in, "kd", w);
  if (in.contains("tau_ff")) c.tau_ff = namedValues(in.at("tau_ff"), w / "tau_ff", atLeast(-kMaxGain), atMost(kMaxGain));
  out = json::object();
  if (in.contains("kp")) out["kp"] = in.at("kp");
  if (in.contains("kd")) out["kd"] = in.at("kd");
  out["tau_ff"] = toJson(c.tau_ff);
  parseGait(in.contains("gait") ? in.at("gait") : json::object(), w / "gait", c, out["gait"]);
}

}  // namespace

const char* sceneGaitTypeName(SceneGaitType type) { return nameOf(kSceneGaitTypes, type); }


SceneConfig parseScene(const json& scene, const std::string& path) {
  SceneConfig c;
  c.path = path;
  c.base_dir = fs::path(absolute(path)).parent_path().string();
  const Where top{path, ""};
  checkKeys(scene, top, sceneSectionKeys(""));
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
    top.fail("duration " + numberText(c.duration) + " s at integrator.dt " + numberText(c.dt) + " s is " + numberText(c.duration / c.dt) +
             " steps, more than the " + numberText(limits::kMaxSteps) + " a run can count and store; shorten duration or lengthen integrator.dt");
  out["duration"] = c.duration;

  const json output = scene.contains("output") ? scene.at("output") : json::object();
  const Where wo = top / "output";
  checkKeys(output, wo, sceneSectionKeys("output"));
  if (output.contains("file")) c.output_file = pathValue(output, "file", wo, c.base_dir, PathKind::Output);
  else c.output_file = absolute(fs::path(path).stem().string() + ".h5");
  c.output_every = integer(output, "every", 1, wo, 1);
  out["output"] = {{"file", c.output_file}, {"every", c.output_every}};
  return c;
}


}  // namespace nmdp
