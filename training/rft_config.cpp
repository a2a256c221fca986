#include "training/rft_config.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "config/json_params.hpp"
#include "config/json_reader.hpp"
#include "config/schema.hpp"
#include "common/text.hpp"

namespace nmdp {

namespace {
using json = nlohmann::json;
using ojson = nlohmann::ordered_json;  // the resolved configuration keeps the documented key order
constexpr double kHalfPi = 1.57079632679489661923;

[[noreturn]] void fail(const std::string& where, const std::string& key, const std::string& what) {
  throw InputError(where + ": " + key + ": " + what);
}

// `object` (at `where: path`) must be an object with the keys of that section only.
void checkKeys(const json& object, const std::string& where, const std::string& path) {
  nmdp::checkKeys(object, KeyPath{where, path}, keysOf(rftSectionKeys(path)));
}

const json& child(const json& object, const std::string& key) {
  static const json kEmpty = json::object();
  return object.contains(key) ? object.at(key) : kEmpty;
}

// Depths and angles of one grid; the directions are the wrench space's vertices.
constexpr size_t kMaxGridValues = 1000;

}  // namespace

std::vector<double> readRftGridValues(const json& object, const std::string& key, const std::vector<double>& fallback,
                                      const ConfigContext& ctx, double lo, double hi, const std::string& range) {
  const std::vector<double> v = readNumbers(object, key, fallback, ctx);
  const std::string at = ctx.where + "." + key;
  if (v.empty()) throw InputError(at + ": expected at least one value");
  if (v.size() > kMaxGridValues)
    throw InputError(at + ": " + std::to_string(v.size()) + " values, more than the " + std::to_string(kMaxGridValues) + " a grid may have");
  std::set<double> seen;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i] < lo || v[i] > hi) throw InputError(at + ": " + json(v[i]).dump() + " is outside " + range);
    if (!seen.insert(v[i]).second) throw InputError(at + ": " + json(v[i]).dump() + " is listed twice (each point once)");
  }
  return v;
}

RftMedium readRftMedium(const json& m, const std::string& where, ojson& resolved) {
  checkKeys(m, where, "medium");
  const ConfigContext ctx{where + ": medium", ""};
  RftMedium medium;
  medium.zeta = readNumber(m, "zeta", medium.zeta, ctx, 1e-12, 1e6);
  RftCoefficients& c = medium.coefficients;
  const std::vector<std::pair<std::string, double*>> fields = {
      {"A00", &c.A00}, {"A10", &c.A10},   {"B11", &c.B11},   {"B01", &c.B01}, {"Bm11", &c.Bm11},
      {"C11", &c.C11}, {"C01", &c.C01},   {"Cm11", &c.Cm11}, {"D10", &c.D10}};
  std::vector<std::string> names;
  for (const auto& f : fields) names.push_back(f.first);
  if (m.contains("coefficients")) {
    const json& k = m.at("coefficients");
    nmdp::checkKeys(k, KeyPath{where, "medium.coefficients"}, names);
    const ConfigContext kctx{where + ": medium.coefficients", ""};
    for (const auto& f : fields) {
      if (!k.contains(f.first))
        throw InputError(where + ": medium.coefficients." + f.first +
                         ": missing (give all nine coefficients, or none for the generic values)");
      *f.second = readNumber(k, f.first, 0.0, kctx);
    }
  }
  ojson coefficients = ojson::object();
  for (const auto& f : fields) coefficients[f.first] = *f.second;
  resolved = {{"zeta", medium.zeta}, {"coefficients", coefficients}};
  return medium;
}

namespace {

RftFoot readFoot(const json& f, const std::string& where, ojson& resolved) {
  const ConfigContext ctx{where + ": foot", ""};
  checkKeys(f, where, "foot");
  RftFoot foot;
  const std::string shape = readString(f, "shape", "disc", ctx);
  const std::vector<std::string> shapes = {"disc", "plate", "blade"};
  if (shape == "disc") {
    foot.shape = RftShape::Disc;
  } else if (shape == "plate") {
    foot.shape = RftShape::Plate;
  } else if (shape == "blade") {
    foot.shape = RftShape::Blade;
  } else {
    const std::string near = closestMatch(shape, shapes);
    fail(where, "foot.shape", "unknown shape '" + shape + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                                  "; shapes: " + join(shapes));
  }
  resolved = ojson::object();
  resolved["shape"] = shape;
  if (foot.shape == RftShape::Disc) {
    if (f.contains("length")) fail(where, "foot.length", "not used by the disc (its size is 'radius')");
    foot.radius = readNumber(f, "radius", 0.02, ctx, 1e-6, 100.0);
    foot.width = readNumber(f, "width", 2 * foot.radius, ctx, 1e-6, 100.0);
    resolved["radius"] = foot.radius;
  } else {
    if (f.contains("radius")) fail(where, "foot.radius", "not used by the " + shape + " (its size is 'length')");
    if (!f.contains("length")) fail(where, "foot.length", "required for the " + shape + " (m)");
    if (!f.contains("width")) fail(where, "foot.width", "required for the " + shape + " (its out-of-plane extent, m)");
    foot.length = readNumber(f, "length", 0.0, ctx, 1e-6, 100.0);
    foot.width = readNumber(f, "width", 0.0, ctx, 1e-6, 100.0);
    resolved["length"] = foot.length;
  }
  foot.torque_centre = readNumber(f, "torque_centre", 0.0, ctx, -100.0, 100.0);
  foot.elements = readInteger(f, "elements", foot.elements, ctx, 1, 1000000);
  resolved["width"] = foot.width;
  resolved["torque_centre"] = foot.torque_centre;
  resolved["elements"] = foot.elements;
  return foot;
}

std::vector<RftTwist> readDirections(const json& d, const std::string& where, ojson& resolved) {
  const std::string path = "grid.directions";
  const ConfigContext ctx{where + ": " + path, ""};
  if (!d.is_object()) throw InputError(where + ": " + path + ": expected a JSON object, got " + jsonForMessage(d));
  const std::string type = readString(d, "type", "circle", ctx);
  resolved = {{"type", type}};
  if (type == "circle") {
    checkKeys(d, where, path + ":circle");
    const int count = readInteger(d, "count", 26, ctx, 1, limits::kMaxVertices);
    resolved["count"] = count;
    return rftCircleDirections(count);
  }
  if (type == "cube") {
    checkKeys(d, where, path + ":cube");
    if (!d.contains("rotation_radius"))
      fail(where, path + ".rotation_radius", "required for type 'cube' (m: a point this far from the torque centre "
                                             "moves at unit speed under unit rotation)");
    const double r = readNumber(d, "rotation_radius", 0.0, ctx, 1e-6, 100.0);
    resolved["rotation_radius"] = r;
    return rftCubeDirections(r);
  }
  if (type == "list") {
    checkKeys(d, where, path + ":list");
    const std::string at = where + ": " + path + ".twists";
    if (!d.contains("twists") || !d.at("twists").is_array() || d.at("twists").empty())
      throw InputError(at + ": expected a non-empty list of [vx, vz, omega] (m/s, m/s, rad/s)");
    if (d.at("twists").size() > static_cast<size_t>(limits::kMaxVertices))
      throw InputError(at + ": " + std::to_string(d.at("twists").size()) + " twists, more than the " +
                       std::to_string(limits::kMaxVertices) + " vertices a wrench space may have");
    std::vector<RftTwist> out;
    for (size_t i = 0; i < d.at("twists").size(); ++i) {
      const json& t = d.at("twists")[i];
      const std::string ti = at + "[" + std::to_string(i) + "]";
      if (!t.is_array() || t.size() != 3)
        throw InputError(ti + ": expected [vx, vz, omega] (m/s, m/s, rad/s), got " + jsonForMessage(t));
      for (const json& x : t)
        if (!x.is_number() || !std::isfinite(x.get<double>()) || std::abs(x.get<double>()) > 1e6)
          throw InputError(ti + ": expected three finite numbers of magnitude at most 1e6, got " + jsonForMessage(t));
      const RftTwist tw{t[0].get<double>(), t[1].get<double>(), t[2].get<double>()};
      if (tw.vx == 0 && tw.vz == 0 && tw.omega == 0) throw InputError(ti + ": a zero twist is no direction");
      out.push_back(tw);
    }
    resolved["twists"] = ojson::parse(d.at("twists").dump());
    return out;
  }
  const std::vector<std::string> types = {"circle", "cube", "list"};
  const std::string near = closestMatch(type, types);
  fail(where, path + ".type", "unknown type '" + type + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                                  "; types: " + join(types));
}
}  // namespace

const std::vector<KeyDoc>& rftSectionKeys(const std::string& section) {
  using ojson = nlohmann::ordered_json;
  static const std::map<std::string, std::vector<KeyDoc>> sections = {
      {"", {{"medium", "object", nullptr, "", "", "the granular medium"},
            {"foot", "object", nullptr, "", "", "the intruder's shape and size"},
            {"grid", "object", nullptr, "", "", "the depths, angles and directions sampled"}}},
      {"medium", {{"zeta", "number", 1.0, "[1e-12, 1e6]", "N/cm^3", "the medium's scaling factor"},
                  {"coefficients", "{A00, A10, B11, B01, Bm11, C11, C01, Cm11, D10}", nullptr, "", "",
                   "all nine Fourier coefficients, or none for the generic values"}}},
      {"foot", {{"shape", "string", "disc", "disc | plate | blade", "", "the foot's cross-section"},
                {"radius", "number", 0.02, "[1e-6, 100]", "m", "disc only"},
                {"length", "number", nullptr, "[1e-6, 100]", "m", "plate and blade only (required there)"},
                {"width", "number", nullptr, "[1e-6, 100]", "m", "out-of-plane extent; disc default 2 radius, required otherwise"},
                {"torque_centre", "number", 0.0, "[-100, 100]", "m", "up the leg from the foot point"},
                {"elements", "integer", 400, "[1, 1000000]", "", "surface elements the foot is cut into"}}},
      {"grid", {{"depths", "[number]", ojson::array({-0.01, -0.03, -0.05, -0.07, 0.0}), "[-100, 0]", "m",
                 "foot depths, no repeats (default: the sand samples')"},
                {"angles", "[number]", ojson::array({0.0, 0.3, 0.6, 0.9}), "[-pi/2, pi/2]", "rad", "foot angles, no repeats"},
                {"directions", "object", ojson{{"type", "circle"}}, "", "", "the twists of the wrench space's vertices"}}},
      {"grid.directions:circle", {{"type", "string", "circle", "circle | cube | list", "", "evenly spaced velocity directions"},
                                  {"count", "integer", 26, "[1, 256]", "", "how many"}}},
      {"grid.directions:cube", {{"type", "string", "cube", "", "", "the 26 directions of a cube's faces, edges and corners"},
                                {"rotation_radius", "number", nullptr, "[1e-6, 100]", "m",
                                 "a point this far from the torque centre moves at unit speed under unit rotation (required)"}}},
      {"grid.directions:list", {{"type", "string", "list", "", "", "the twists given"},
                                {"twists", "[[vx, vz, omega]]", nullptr, "", "m/s, m/s, rad/s", "non-zero twists (required)"}}},
  };
  static const std::vector<KeyDoc> none;
  const auto it = sections.find(section);
  return it == sections.end() ? none : it->second;
}

nlohmann::ordered_json rftConfigSchema() {
  nlohmann::ordered_json out;
  for (const char* section : {"", "medium", "foot", "grid", "grid.directions:circle", "grid.directions:cube",
                              "grid.directions:list"})
    out[section] = schemaRows(rftSectionKeys(section));
  return out;
}

constexpr double kMaxStressEvaluations = 1e9;

RftConfig readRftConfig(const json& config, const std::string& where) {
  checkKeys(config, where, "");
  RftConfig c;
  ojson medium, foot, grid = ojson::object(), directions;
  c.medium = readRftMedium(child(config, "medium"), where, medium);
  c.foot = readFoot(child(config, "foot"), where, foot);
  const json& g = child(config, "grid");
  checkKeys(g, where, "grid");
  const ConfigContext gctx{where + ": grid", ""};
  // The defaults are the points of the published sand samples (granular/README.md).
  c.grid.depths = readRftGridValues(g, "depths", {-0.01, -0.03, -0.05, -0.07, 0.0}, gctx, -100.0, 0.0,
                               "[-100, 0] (m, negative below the surface)");
  c.grid.angles = readRftGridValues(g, "angles", {0.0, 0.3, 0.6, 0.9}, gctx, -kHalfPi, kHalfPi, "[-pi/2, pi/2] (rad)");
  c.grid.directions =
      readDirections(g.contains("directions") ? g.at("directions") : json{{"type", "circle"}}, where, directions);
  // The work of gen-rft is samples × elements evaluations of the stress: bounded to seconds.
  const double samples = static_cast<double>(c.grid.depths.size() * c.grid.angles.size() * c.grid.directions.size());
  if (samples > static_cast<double>(limits::kMaxForceSamples) || samples * c.foot.elements > kMaxStressEvaluations)
    throw InputError(where + ": grid: " + std::to_string(c.grid.depths.size()) + " depths x " + std::to_string(c.grid.angles.size()) +
                     " angles x " + std::to_string(c.grid.directions.size()) + " directions x " + std::to_string(c.foot.elements) +
                     " foot elements is more work than gen-rft takes (at most 1e9 element evaluations)");
  grid["depths"] = c.grid.depths;
  grid["angles"] = c.grid.angles;
  grid["directions"] = directions;
  c.resolved = nlohmann::ordered_json::object();
  c.resolved["medium"] = medium;
  c.resolved["foot"] = foot;
  c.resolved["grid"] = grid;
  return c;
}

}  // namespace nmdp
