#include "terrain/terrain_factory.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/plane.hpp"
#include "terrain/procedural.hpp"
#include "common/text.hpp"

namespace nmdp {

namespace {

// Every type also takes the material keys (material_config.hpp reads them); only a heightfield a map.
const std::vector<std::string> kPlaneKeys = {"type", "normal", "offset", "patches", "blend_width"};
const std::vector<std::string> kHeightfieldKeys = {"type",   "file",    "heights",     "origin",      "spacing",
                                                   "offset", "patches", "blend_width", "material_map"};
const std::vector<std::string> kProceduralKeys = {"type", "slope", "offset", "hills", "patches", "blend_width"};
const std::vector<std::string> kHillKeys = {"centre", "height", "width"};

[[noreturn]] void fail(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// Two numbers [a, b]; a single number gives [a, a] when `scalar_both`, [a, scalar_second] otherwise.
void readPair(const nlohmann::json& object, const std::string& key, const ConfigContext& ctx, bool scalar_both,
              double scalar_second, double& a, double& b) {
  if (!object.contains(key)) return;
  const nlohmann::json& v = object.at(key);
  if (v.is_number()) {
    a = readNumber(object, key, a, ctx);
    b = scalar_both ? a : scalar_second;
    return;
  }
  const std::vector<double> xs = readNumbers(object, key, {}, ctx);
  if (xs.size() != 2) fail(ctx, key, "expected two numbers [x, y], got " + jsonForMessage(v));
  a = xs[0];
  b = xs[1];
}

double readSlope(double angle, const nlohmann::json& object, const ConfigContext& ctx) {
  if (!(std::abs(angle) < 0.5 * M_PI))
    fail(ctx, "slope",
         "slope angles are in rad and must lie in (-pi/2, pi/2), got " + jsonForMessage(object.at("slope")) +
             (std::abs(angle) >= 0.5 * M_PI && std::abs(angle) <= 90.0 ? " (degrees? multiply by pi/180)" : ""));
  return angle;
}

// Bounds of terrain sizes (m), far beyond any scene (Everest is 8.8 km high) and keeping the spline and
// the hills' exponentials finite; hills of one terrain (each query sums over all of them).
constexpr double kMaxHeight = 1e6;
constexpr double kMinSpacing = 1e-6, kMaxSpacing = 1e6;
constexpr double kMaxCoordinate = 1e9;
constexpr size_t kMaxHills = 1000;

std::unique_ptr<Terrain> makePlane(const nlohmann::json& config, const ConfigContext& ctx) {
  requireKnownKeys(config, kPlaneKeys, ctx);
  const Vec3 normal = readVec3(config, "normal", Vec3::UnitZ(), ctx);
  if (!(normal.norm() > 1e-12)) fail(ctx, "normal", "the normal must be a non-zero vector, got " + jsonForMessage(config.at("normal")));
  const double offset = readNumber(config, "offset", 0.0, ctx, -kMaxHeight, kMaxHeight);
  return std::make_unique<PlaneTerrain>(normal, offset);
}

// The heights given inline, "heights": [[row j = 0 along x], [row j = 1], ...], checked as
// readHeightGridCsv checks a file (the same messages, naming heights[j][i] instead of line and column).
HeightGrid inlineHeights(const nlohmann::json& config, const ConfigContext& ctx) {
  const nlohmann::json& rows = config.at("heights");
  const std::string where = ctx.where + ".heights";
  if (!rows.is_array()) throw InputError(where + ": expected rows of heights [[z, ...], ...], got " + jsonForMessage(rows));
  HeightGrid grid;
  for (size_t j = 0; j < rows.size(); ++j) {
    const nlohmann::json& row = rows[j];
    const std::string at_row = where + "[" + std::to_string(j) + "]";
    if (!row.is_array()) throw InputError(at_row + ": expected a row of heights [z, ...], got " + jsonForMessage(row));
    for (size_t i = 0; i < row.size(); ++i) {
      const std::string at = at_row + "[" + std::to_string(i) + "]";
      if (static_cast<std::int64_t>(grid.z.size()) >= limits::kMaxHeightfieldCells)
        throw InputError(at + ": more than " + std::to_string(limits::kMaxHeightfieldCells) +
                         " heights, beyond the largest heightfield nmdp takes (4096 x 4096)");
      if (row[i].is_null())
        throw InputError(at + ": empty cell: holes in a heightfield are not supported, every grid node needs a finite height");
      if (!row[i].is_number()) throw InputError(at + ": '" + jsonForMessage(row[i]) + "' is not a number");
      const double z = row[i].get<double>();
      if (!std::isfinite(z)) throw InputError(at + ": '" + jsonForMessage(row[i]) + "' is not a finite height");
      grid.z.push_back(z);
    }
    const int columns = static_cast<int>(row.size());
    if (j == 0) {
      grid.nx = columns;
    } else if (columns != grid.nx) {
      throw InputError(at_row + ": this row has " + std::to_string(columns) + " value" + (columns == 1 ? "" : "s") +
                       " but the first row has " + std::to_string(grid.nx) +
                       ": every row of the grid needs the same number of values");
    }
    ++grid.ny;
  }
  if (grid.nx < 2 || grid.ny < 2)
    throw InputError(where + ": a heightfield needs at least 2x2 values (2 rows of 2 heights), got " +
                     (grid.ny == 0 ? std::string("none")
                                   : std::to_string(grid.ny) + " row" + (grid.ny == 1 ? "" : "s") + " of " +
                                         std::to_string(grid.nx)));
  return grid;
}

std::unique_ptr<Terrain> makeHeightfield(const nlohmann::json& config, const ConfigContext& ctx) {
  requireKnownKeys(config, kHeightfieldKeys, ctx);
  const bool inline_heights = config.contains("heights");
  if (inline_heights && config.contains("file"))
    fail(ctx, "heights", "give either a \"file\" of heights or the \"heights\" themselves, not both");
  if (!inline_heights && !config.contains("file"))
    fail(ctx, "file", "missing: a heightfield needs a CSV file of heights (or \"heights\": [[z, ...], ...])");
  const std::string file = inline_heights ? std::string() : readString(config, "file", "", ctx);
  if (!inline_heights && file.empty()) fail(ctx, "file", "empty file name");
  if (!config.contains("spacing"))
    fail(ctx, "spacing", "missing: give the grid spacing [dx, dy] in m (a number for dx = dy)");
  double dx = 1.0, dy = 1.0, x0 = 0.0, y0 = 0.0;
  readPair(config, "spacing", ctx, true, 0.0, dx, dy);
  if (!(dx > 0.0) || !(dy > 0.0))
    fail(ctx, "spacing", "the grid spacing must be positive, got " + jsonForMessage(config.at("spacing")));
  if (dx < kMinSpacing || dy < kMinSpacing || dx > kMaxSpacing || dy > kMaxSpacing)
    fail(ctx, "spacing", "the grid spacing must lie in [1e-06, 1e+06] m, got " + jsonForMessage(config.at("spacing")));
  if (config.contains("origin") && config.at("origin").is_number())
    fail(ctx, "origin", "expected two numbers [x0, y0], got " + jsonForMessage(config.at("origin")));
  readPair(config, "origin", ctx, true, 0.0, x0, y0);
  if (std::abs(x0) > kMaxCoordinate || std::abs(y0) > kMaxCoordinate)
    fail(ctx, "origin", "the grid origin must lie within 1e9 m of the world origin, got " + jsonForMessage(config.at("origin")));
  const double offset = readNumber(config, "offset", 0.0, ctx, -kMaxHeight, kMaxHeight);

  HeightGrid grid;
  const std::string path = inline_heights ? ctx.where + ".heights" : ctx.resolve(file);
  if (inline_heights) {
    grid = inlineHeights(config, ctx);
  } else {
    try {
      grid = readHeightGridCsv(path);
    } catch (const InputError& e) {
      fail(ctx, "file", e.what());
    }
  }
  grid.x0 = x0;
  grid.y0 = y0;
  grid.dx = dx;
  grid.dy = dy;
  for (double& z : grid.z) {
    if (std::abs(z) > kMaxHeight)
      fail(ctx, inline_heights ? "heights" : "file",
           (inline_heights ? std::string() : displayPath(path) + ": ") + "a height of " + number(z) + " m is beyond 1e6 m");
    z += offset;
  }
  return std::make_unique<HeightfieldTerrain>(std::move(grid), inline_heights ? std::string() : file);
}

std::unique_ptr<Terrain> makeProcedural(const nlohmann::json& config, const ConfigContext& ctx) {
  requireKnownKeys(config, kProceduralKeys, ctx);
  double sx = 0.0, sy = 0.0;
  readPair(config, "slope", ctx, false, 0.0, sx, sy);
  if (config.contains("slope")) {
    readSlope(sx, config, ctx);
    readSlope(sy, config, ctx);
  }
  const double offset = readNumber(config, "offset", 0.0, ctx, -kMaxHeight, kMaxHeight);
  std::vector<GaussianHill> hills;
  if (config.contains("hills")) {
    const nlohmann::json& list = config.at("hills");
    if (!list.is_array())
      fail(ctx, "hills", "expected a list of {\"centre\": [x, y], \"height\": h, \"width\": w}, got " + jsonForMessage(list));
    if (list.size() > kMaxHills) fail(ctx, "hills", std::to_string(list.size()) + " hills, more than the 1000 a terrain may have");
    for (size_t i = 0; i < list.size(); ++i) {
      ConfigContext hc = ctx;
      hc.where = ctx.where + ".hills[" + std::to_string(i) + "]";
      const nlohmann::json& h = list[i];
      requireKnownKeys(h, kHillKeys, hc);
      for (const std::string& key : kHillKeys)
        if (!h.contains(key)) fail(hc, key, "missing (a hill needs centre [x, y], height and width, in m)");
      GaussianHill hill;
      if (h.at("centre").is_number())
        fail(hc, "centre", "expected two numbers [x, y], got " + jsonForMessage(h.at("centre")));
      readPair(h, "centre", hc, true, 0.0, hill.cx, hill.cy);
      if (std::abs(hill.cx) > kMaxCoordinate || std::abs(hill.cy) > kMaxCoordinate)
        fail(hc, "centre", "must lie within 1e9 m of the world origin, got " + jsonForMessage(h.at("centre")));
      hill.height = readNumber(h, "height", 0.0, hc, -kMaxHeight, kMaxHeight);
      hill.width = readNumber(h, "width", 1.0, hc, -kMaxSpacing, kMaxSpacing);
      if (!(hill.width >= kMinSpacing))
        fail(hc, "width", "the width (standard deviation, m) must be at least 1e-06, got " + number(hill.width));
      hills.push_back(hill);
    }
  }
  return std::make_unique<ProceduralTerrain>(sx, sy, offset, std::move(hills));
}

}  // namespace

const std::vector<std::string>& terrainTypes() {
  static const std::vector<std::string> types = {"plane", "heightfield", "procedural"};
  return types;
}

std::unique_ptr<Terrain> makeTerrain(const nlohmann::json& config, const ConfigContext& context) {
  ConfigContext ctx = context;
  if (ctx.where.empty()) ctx.where = "terrain";
  if (config.is_null()) return std::make_unique<PlaneTerrain>();
  if (!config.is_object()) fail(ctx, "", "expected a JSON object such as {\"type\": \"plane\"}, got " + jsonForMessage(config));
  if (!config.contains("type")) {
    // No type: the default plane, unless the keys given belong to another type.
    for (auto it = config.begin(); it != config.end(); ++it)
      if (std::find(kPlaneKeys.begin(), kPlaneKeys.end(), it.key()) == kPlaneKeys.end())
        fail(ctx, "type", "missing (without it the terrain is a plane, which has no key '" + it.key() +
                              "'); valid types: " + join(terrainTypes()));
    return makePlane(config, ctx);
  }
  const std::string type = readString(config, "type", "plane", ctx);
  if (type == "plane") return makePlane(config, ctx);
  if (type == "heightfield") return makeHeightfield(config, ctx);
  if (type == "procedural") return makeProcedural(config, ctx);
  const std::string near = closestMatch(type, terrainTypes());
  fail(ctx, "type", "unknown terrain type '" + type + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                        "; valid types: " + join(terrainTypes()));
}

}  // namespace nmdp
