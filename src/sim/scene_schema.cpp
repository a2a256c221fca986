#include "sim/scene_schema.hpp"

#include <map>
#include <stdexcept>

#include "config/integrator_options.hpp"
#include "config/schema.hpp"

namespace nmdp {

namespace {

using ojson = nlohmann::ordered_json;

struct Section {
  const char* name;
  std::vector<KeyDoc> keys;
};

const std::vector<Section>& sections() {
  static const std::vector<Section> table = {
      {"", {{"robot", "object", nullptr, "", "", "the robot (required)"},
            {"contacts", "object", nullptr, "", "", "contact points and the contact model"},
            {"terrain", "object", ojson{{"type", "plane"}}, "", "", "the ground, as makeTerrain reads it; \"file\" relative to the scene"},
            {"integrator", "object", nullptr, "", "", "the time step and its method (section integrator)"},
            {"controller", "object", nullptr, "", "", "PD gains, feed-forward torques and the gait"},
            {"duration", "number", 10.0, "(0, inf)", "s", "simulated time"},
            {"output", "object", nullptr, "", "", "the trajectory file"}}},
      {"robot", {{"urdf", "path", nullptr, "", "", "the robot's URDF file (required, must exist)"},
                 {"base", "string", "floating", "floating | planar | fixed", "", "the base joint"},
                 {"locked_joints", "{joint: number}", ojson::object(), "[-1000, 1000]", "rad or m", "joints held at a value"},
                 {"armature", "number | {joint: number}", 0.0, "[0, 1e6]", "kg m^2", "rotor inertia of every actuated joint or per joint"},
                 {"initial", "object", nullptr, "", "", "the start pose and velocity"}}},
      {"robot.initial", {{"height", "number", nullptr, "[-1e6, 1e6]", "m", "trunk origin height (default: the lowest contact sphere touches the terrain)"},
                         {"joints", "{joint: number}", ojson::object(), "[-1000, 1000]", "rad or m", "the start pose (README, Start pose)"},
                         {"base_position", "[x, y] | [x, y, z]", ojson::array({0.0, 0.0}), "", "m", "base position; z overrides height"},
                         {"base_rpy", "[roll, pitch, yaw]", ojson::array({0.0, 0.0, 0.0}), "", "rad", "base orientation, ZYX as /base/rpy of the output"},
                         {"velocity", "object", nullptr, "", "", "base velocity in the world frame (zero)"}}},
      {"robot.initial.velocity", {{"base_linear", "[3 numbers]", ojson::array({0.0, 0.0, 0.0}), "", "m/s", "linear velocity, world frame"},
                                  {"base_angular", "[3 numbers]", ojson::array({0.0, 0.0, 0.0}), "", "rad/s", "angular velocity, world frame"}}},
      {"contacts", {{"points", "\"auto\" | [point]", "auto", "", "", "the contact spheres: found on the feet, or listed"},
                    {"model", "object", ojson{{"type", "coulomb"}}, "", "", "the contact model; \"file\" must exist (nmdp inspect lists the types)"}}},
      {"contacts.points[]", {{"link", "string", nullptr, "", "", "the URDF link carrying the sphere (required)"},
                             {"offset", "[x, y, z]", ojson::array({0.0, 0.0, 0.0}), "", "m", "the sphere's centre in the link frame"},
                             {"radius", "number", 0.0, "[0, 10]", "m", "the sphere's radius"},
                             {"name", "string", nullptr, "", "", "label (default: the link name)"},
                             {"leg_axis", "[x, y, z]", nullptr, "", "", "from the foot up the leg, link frame (default: from the URDF)"}}},
      {"controller", {{"kp", "number | {joint: number}", nullptr, "[0, 1e9]", "N m/rad", "stiffness (default: 8 Hz about each joint's load, control/default_gains.hpp)"},
                      {"kd", "number | {joint: number}", nullptr, "[0, 1e9]", "N m s/rad", "damping (default: critical)"},
                      {"tau_ff", "{joint: number}", ojson::object(), "[-1e9, 1e9]", "N m", "feed-forward torques"},
                      {"gait", "object", ojson{{"type", "stand"}}, "", "", "the motion the PD targets follow"}}},
      {"controller.gait:stand", {{"type", "string", "stand", "stand | trot | jump | keyframes", "", "the gait"},
                                 {"height", "number", nullptr, "(0, 100]", "m", "trunk height above the feet (default: the robot's)"}}},
      {"controller.gait:trot", {{"type", "string", "trot", "", "", "the gait"},
                                {"height", "number", nullptr, "(0, 100]", "m", "trunk height above the feet"},
                                {"stride_length", "number", nullptr, "[0, 100]", "m", "stride (default: the robot's)"},
                                {"step_height", "number", nullptr, "[0, 100]", "m", "swing height (default: the robot's)"},
                                {"period", "number", 0.5, "(0, 10000]", "s", "gait period"},
                                {"duty_factor", "number", 0.5, "(0, 1)", "", "share of the period a foot is down"},
                                {"swing_profile", "string", "cosine", "cosine | ground_speed", "", "swing foot path"},
                                {"ground_speed_share", "number", 0.15, "[0, 1)", "", "ground_speed only"},
                                {"start_ramp", "number", 0.0, "[0, 10000]", "s", "ramp from standing (control/start_ramp.hpp); 0: none"},
                                {"heading_feedback", "boolean", nullptr, "", "", "hold the start heading and line (control/heading_feedback.hpp; default: on for a floating base)"}}},
      {"controller.gait:jump", {{"type", "string", "jump", "", "", "the gait"},
                                {"height", "number", nullptr, "(0, 100]", "m", "trunk height above the feet"},
                                {"crouch_depth", "number", nullptr, "[0, 100]", "m", "crouch below height (default: the robot's)"},
                                {"push_off_height", "number", nullptr, "(0, 100]", "m", "trunk height at push-off (> height)"},
                                {"period", "number", 2.0, "(0, 10000]", "s", "jump period"},
                                {"pause", "number", 0.4, "[0, period)", "s", "standing pause of each period"}}},
      {"controller.gait:keyframes", {{"type", "string", "keyframes", "", "", "the gait"},
                                     {"height", "number", nullptr, "(0, 100]", "m", "trunk height of the standing pose unlisted joints hold"},
                                     {"file", "path", nullptr, "", "", "CSV or JSON keyframe file (required; README, Keyframe files)"},
                                     {"cyclic", "boolean", false, "", "", "repeat the motion"},
                                     {"period", "number", nullptr, "(0, 10000]", "s", "cycle period (cyclic only; default: the last keyframe closes the cycle)"}}},
      {"output", {{"file", "path", nullptr, "", "", "the HDF5 file (default: <scene stem>.h5 in the current directory)"},
                  {"every", "integer", 1, "[1, inf)", "", "store every N-th step"}}},
  };
  return table;
}

const Section& section(const std::string& name) {
  for (const Section& s : sections())
    if (name == s.name) return s;
  throw std::logic_error("no scene section '" + name + "'");
}

}  // namespace

std::vector<std::string> sceneSections() {
  std::vector<std::string> out;
  for (const Section& s : sections()) out.emplace_back(s.name);
  out.insert(out.begin() + 4, "integrator");
  return out;
}

const std::vector<std::string>& sceneSectionKeys(const std::string& name) {
  static const std::map<std::string, std::vector<std::string>> keys = [] {
    std::map<std::string, std::vector<std::string>> out;
    for (const Section& s : sections()) out[s.name] = keysOf(s.keys);
    out["integrator"] = integratorFields().keys();
    return out;
  }();
  const auto it = keys.find(name);
  if (it == keys.end()) throw std::logic_error("no scene section '" + name + "'");
  return it->second;
}

ojson sceneSchema() {
  ojson out = ojson::object();
  for (const std::string& name : sceneSections()) {
    if (name == "integrator") {
      out[name] = integratorFields().schema();
      continue;
    }
    out[name] = schemaRows(section(name).keys);
  }
  return out;
}

std::string sceneSchemaText() { return schemaText(sceneSchema()); }

}  // namespace nmdp
