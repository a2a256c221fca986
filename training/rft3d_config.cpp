#include "training/rft3d_config.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "common/text.hpp"
#include "config/json_params.hpp"
#include "config/json_reader.hpp"
#include "training/rft_config.hpp"

namespace nmdp {

namespace {
using json = nlohmann::json;
using ojson = nlohmann::ordered_json;
constexpr double kHalfPi = 1.57079632679489661923;
// gen-rft's work is samples × elements² stress evaluations: bounded to tens of seconds.
constexpr double kMaxStressEvaluations = 1e9;

[[noreturn]] void fail(const std::string& where, const std::string& key, const std::string& what) {
  throw InputError(where + ": " + key + ": " + what);
}

// `object` at `where: path` has the keys of `section` only (default: the section named `path`).
void checkSection(const json& object, const std::string& where, const std::string& path, const std::string& section = "") {
  nmdp::checkKeys(object, KeyPath{where, path}, keysOf(rft3dSectionKeys(section.empty() ? path : section)));
}

const json& child(const json& object, const std::string& key) {
  static const json kEmpty = json::object();
  return object.contains(key) ? object.at(key) : kEmpty;
}

std::string oneOf(const std::string& value, const std::vector<std::string>& choices, const std::string& what) {
  const std::string near = closestMatch(value, choices);
  return "unknown " + what + " '" + value + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") + "; " +
         what + "s: " + join(choices);
}

Rft3dFoot readFoot(const json& f, const std::string& where, bool planar, double& torque_centre, ojson& resolved) {
  checkSection(f, where, "foot");
  const ConfigContext ctx{where + ": foot", ""};
  Rft3dFoot foot;
  const std::string shape = readString(f, "shape", "sphere", ctx);
  if (shape == "sphere")
    foot.shape = Rft3dShape::Sphere;
  else if (shape == "plate")
    foot.shape = Rft3dShape::Plate;
  else if (shape == "blade")
    foot.shape = Rft3dShape::Blade;
  else
    fail(where, "foot.shape", oneOf(shape, {"sphere", "plate", "blade"}, "shape"));
  resolved = ojson::object();
  resolved["shape"] = shape;
  if (foot.shape == Rft3dShape::Sphere) {
    for (const char* key : {"length", "width"})
      if (f.contains(key)) fail(where, std::string("foot.") + key, "not used by the sphere (its size is 'radius')");
    foot.radius = readNumber(f, "radius", 0.02, ctx, 1e-6, 100.0);
    resolved["radius"] = foot.radius;
  } else {
    if (f.contains("radius")) fail(where, "foot.radius", "not used by the " + shape + " (its size is 'length' and 'width')");
    for (const char* key : {"length", "width"})
      if (!f.contains(key)) fail(where, std::string("foot.") + key, "required for the " + shape + " (m)");
    foot.length = readNumber(f, "length", 0.0, ctx, 1e-6, 100.0);
    foot.width = readNumber(f, "width", 0.0, ctx, 1e-6, 100.0);
    resolved["length"] = foot.length;
    resolved["width"] = foot.width;
  }
  foot.elements = readInteger(f, "elements", foot.elements, ctx, 1, 10000);
  resolved["elements"] = foot.elements;
  if (!planar && f.contains("torque_centre"))
    fail(where, "foot.torque_centre", "used by the planar output only (the spatial torque is about the foot point)");
  torque_centre = readNumber(f, "torque_centre", 0.0, ctx, -100.0, 100.0);
  if (planar) resolved["torque_centre"] = torque_centre;
  return foot;
}

std::vector<Eigen::Vector3d> readDirections(const json& d, const std::string& where, bool planar, ojson& resolved) {
  const std::string path = "grid.directions";
  const ConfigContext ctx{where + ": " + path, ""};
  if (!d.is_object()) throw InputError(where + ": " + path + ": expected a JSON object, got " + jsonForMessage(d));
  const std::string type = readString(d, "type", planar ? "circle" : "cube", ctx);
  resolved = {{"type", type}};
  const std::vector<std::string> types =
      planar ? std::vector<std::string>{"circle", "list"} : std::vector<std::string>{"cube", "fibonacci", "list", "circle"};
  if (std::find(types.begin(), types.end(), type) == types.end()) {
    if (planar && (type == "cube" || type == "fibonacci"))
      fail(where, path + ".type", "'" + type + "' leaves the x-z plane; the planar output takes: " + join(types));
    fail(where, path + ".type", oneOf(type, types, "type"));
  }
  checkSection(d, where, path, path + ":" + type);
  if (type == "cube") return rft3dCubeDirections();
  if (type == "fibonacci" || type == "circle") {
    if (type == "fibonacci" && !d.contains("count")) fail(where, path + ".count", "required for type 'fibonacci'");
    const int count = readInteger(d, "count", 26, ctx, 1, limits::kMaxVertices);
    resolved["count"] = count;
    return type == "circle" ? rft3dCircleDirections(count) : rft3dFibonacciDirections(count);
  }
  const std::string at = where + ": " + path + ".vectors";
  if (!d.contains("vectors") || !d.at("vectors").is_array() || d.at("vectors").empty())
    throw InputError(at + ": expected a non-empty list of [x, y, z] (terrain frame; only the direction matters)");
  if (d.at("vectors").size() > static_cast<size_t>(limits::kMaxVertices))
    throw InputError(at + ": " + std::to_string(d.at("vectors").size()) + " vectors, more than the " +
                     std::to_string(limits::kMaxVertices) + " vertices a wrench space may have");
  std::vector<Eigen::Vector3d> out;
  for (size_t i = 0; i < d.at("vectors").size(); ++i) {
    const json& v = d.at("vectors")[i];
    const std::string vi = at + "[" + std::to_string(i) + "]";
    if (!v.is_array() || v.size() != 3) throw InputError(vi + ": expected [x, y, z], got " + jsonForMessage(v));
    for (const json& x : v)
      if (!x.is_number() || !std::isfinite(x.get<double>()) || std::abs(x.get<double>()) > 1e6)
        throw InputError(vi + ": expected three finite numbers of magnitude at most 1e6, got " + jsonForMessage(v));
    const Eigen::Vector3d u(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    if (u.isZero(0.0)) throw InputError(vi + ": a zero vector is no direction");
    if (planar && u.y() != 0.0) throw InputError(vi + ": the planar output needs y = 0 (a direction in the x-z plane)");
    out.push_back(u);
  }
  resolved["vectors"] = ojson::parse(d.at("vectors").dump());
  return out;
}
}  // namespace

bool isRft3dConfig(const json& config, const std::string& where) {
  if (!config.is_object() || !config.contains("dimension")) return false;
  const json& d = config.at("dimension");
  if (d.is_number_integer() && (d.get<long long>() == 2 || d.get<long long>() == 3)) return d.get<long long>() == 3;
  if (d.is_number_float() && (d.get<double>() == 2.0 || d.get<double>() == 3.0)) return d.get<double>() == 3.0;
  fail(where, "dimension", "expected 2 (planar) or 3, got " + jsonForMessage(d));
}

const std::vector<KeyDoc>& rft3dSectionKeys(const std::string& section) {
  static const std::map<std::string, std::vector<KeyDoc>> sections = {
      {"", {{"dimension", "integer", 3, "2 | 3", "", "3: this configuration; 2 or absent: the planar one"},
            {"output", "string", "spatial", "spatial | planar", "",
             "the 3-D dataset, or the planar dataset of the same foot and medium (gamma 0, x-z directions)"},
            {"medium", "object", nullptr, "", "", "the granular medium (as the planar configuration)"},
            {"foot", "object", nullptr, "", "", "the foot's shape and size"},
            {"grid", "object", nullptr, "", "", "the depths, tilts and directions sampled"}}},
      {"medium", rftSectionKeys("medium")},
      {"foot", {{"shape", "string", "sphere", "sphere | plate | blade", "", "the foot's surface"},
                {"radius", "number", 0.02, "[1e-6, 100]", "m", "sphere only"},
                {"length", "number", nullptr, "[1e-6, 100]", "m", "plate (along the foot) and blade (up the leg); required there"},
                {"width", "number", nullptr, "[1e-6, 100]", "m", "plate and blade (across the leg); required there"},
                {"elements", "integer", 64, "[1, 10000]", "", "cuts per direction of the surface"},
                {"torque_centre", "number", 0.0, "[-100, 100]", "m", "up the leg from the foot point; planar output only"}}},
      {"grid", {{"depths", "[number]", ojson::array({-0.01, -0.03, -0.05, -0.07, 0.0}), "[-100, 0]", "m",
                 "foot-point depths, no repeats"},
                {"betas", "[number]", ojson::array({-0.6, 0.0, 0.6}), "[-pi/2, pi/2]", "rad", "sagittal leg leans, no repeats"},
                {"gammas", "[number]", ojson::array({-0.6, 0.0, 0.6}), "[-pi/2, pi/2]", "rad",
                 "lateral leg leans, no repeats; not with the planar output (gamma 0)"},
                {"directions", "object", ojson{{"type", "cube"}}, "", "", "the translations of the wrench space's vertices"}}},
      {"grid.directions:cube", {{"type", "string", "cube", "cube | fibonacci | list | circle", "",
                                 "the 26 directions {-1, 0, 1}^3 \\ 0, normalized (spatial default)"}}},
      {"grid.directions:fibonacci", {{"type", "string", "fibonacci", "", "", "directions spread over the sphere"},
                                     {"count", "integer", nullptr, "[1, 256]", "", "how many (required)"}}},
      {"grid.directions:list", {{"type", "string", "list", "", "", "the directions given"},
                                {"vectors", "[[x, y, z]]", nullptr, "", "", "non-zero vectors, terrain frame (required)"}}},
      {"grid.directions:circle", {{"type", "string", "circle", "", "", "evenly spaced in the x-z plane (planar default)"},
                                  {"count", "integer", 26, "[1, 256]", "", "how many"}}},
  };
  static const std::vector<KeyDoc> none;
  const auto it = sections.find(section);
  return it == sections.end() ? none : it->second;
}

nlohmann::ordered_json rft3dConfigSchema() {
  nlohmann::ordered_json out;
  for (const char* section : {"", "medium", "foot", "grid", "grid.directions:cube", "grid.directions:fibonacci",
                              "grid.directions:list", "grid.directions:circle"})
    out[section] = schemaRows(rft3dSectionKeys(section));
  return out;
}

Rft3dConfig readRft3dConfig(const json& config, const std::string& where) {
  checkSection(config, where, "");
  if (!isRft3dConfig(config, where)) fail(where, "dimension", "3 is required for the 3-D configuration");
  Rft3dConfig c;
  const ConfigContext top{where, ""};
  const std::string output = readString(config, "output", "spatial", top);
  if (output == "spatial")
    c.output = Rft3dOutput::Spatial;
  else if (output == "planar")
    c.output = Rft3dOutput::Planar;
  else
    fail(where, "output", oneOf(output, {"spatial", "planar"}, "output"));
  const bool planar = c.output == Rft3dOutput::Planar;
  ojson medium, foot, grid = ojson::object(), directions;
  c.medium = readRftMedium(child(config, "medium"), where, medium);
  c.foot = readFoot(child(config, "foot"), where, planar, c.torque_centre, foot);
  const json& g = child(config, "grid");
  checkSection(g, where, "grid");
  const ConfigContext gctx{where + ": grid", ""};
  c.grid.depths = readRftGridValues(g, "depths", {-0.01, -0.03, -0.05, -0.07, 0.0}, gctx, -100.0, 0.0,
                                    "[-100, 0] (m, negative below the surface)");
  c.grid.betas = readRftGridValues(g, "betas", {-0.6, 0.0, 0.6}, gctx, -kHalfPi, kHalfPi, "[-pi/2, pi/2] (rad)");
  if (planar && g.contains("gammas")) fail(where, "grid.gammas", "not used by the planar output (gamma is 0)");
  c.grid.gammas = planar ? std::vector<double>{0.0}
                         : readRftGridValues(g, "gammas", {-0.6, 0.0, 0.6}, gctx, -kHalfPi, kHalfPi, "[-pi/2, pi/2] (rad)");
  const json default_directions = json{{"type", planar ? "circle" : "cube"}};
  c.grid.directions = readDirections(g.contains("directions") ? g.at("directions") : default_directions, where, planar,
                                     directions);
  const double samples = static_cast<double>(c.grid.depths.size() * c.grid.betas.size() * c.grid.gammas.size() *
                                             c.grid.directions.size());
  const double elements = static_cast<double>(c.foot.elements) * c.foot.elements;
  if (samples > static_cast<double>(limits::kMaxForceSamples) || samples * elements > kMaxStressEvaluations)
    throw InputError(where + ": grid: " + std::to_string(static_cast<long long>(samples)) + " samples x " +
                     std::to_string(c.foot.elements) + "^2 foot elements is more work than gen-rft takes (at most 1e9 "
                     "element evaluations, " + std::to_string(limits::kMaxForceSamples) + " samples)");
  grid["depths"] = c.grid.depths;
  grid["betas"] = c.grid.betas;
  if (!planar) grid["gammas"] = c.grid.gammas;
  grid["directions"] = directions;
  c.resolved = ojson::object();
  c.resolved["dimension"] = 3;
  c.resolved["output"] = output;
  c.resolved["medium"] = medium;
  c.resolved["foot"] = foot;
  c.resolved["grid"] = grid;
  return c;
}

ForceDataset rft3dConfigSamples(const Rft3dConfig& config) {
  return config.output == Rft3dOutput::Planar
             ? rft3dPlanarSamples(config.medium, config.foot, config.grid, config.torque_centre)
             : rft3dSamples(config.medium, config.foot, config.grid);
}

}  // namespace nmdp
