#include "terrain/material_config.hpp"

#include <cmath>
#include <sstream>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "common/text.hpp"
#include "terrain/heightfield.hpp"

namespace nmdp {

namespace {

using json = nlohmann::json;
using Vec2 = Eigen::Vector2d;

const std::vector<std::string> kPatchKeys = {"name", "region", "model"};
const std::vector<std::string> kRegionTypes = {"rectangle", "circle", "polygon"};
const std::vector<std::string> kMapKeys = {"file", "models"};
// Region coordinates (m), as the terrain's own.
constexpr double kMaxCoordinate = 1e9;
constexpr double kMaxBlendWidth = 1e3;

[[noreturn]] void fail(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}

ConfigContext inside(const ConfigContext& ctx, const std::string& key) {
  ConfigContext c = ctx;
  c.where = ctx.where + "." + key;
  return c;
}

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

Vec2 point(const json& v, const ConfigContext& ctx, const std::string& key) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    fail(ctx, key, "expected two numbers [x, y] (m), got " + jsonForMessage(v));
  const Vec2 p(v[0].get<double>(), v[1].get<double>());
  if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate)
    fail(ctx, key, "must be finite and within 1e9 m of the world origin, got " + jsonForMessage(v));
  return p;
}

MaterialRegion readRegion(const json& r, const ConfigContext& ctx, double blend_width) {
  if (!r.is_object() || !r.contains("type") || !r.at("type").is_string())
    fail(ctx, "", "expected an object with a \"type\" (" + join(kRegionTypes) + "), got " + jsonForMessage(r));
  const std::string type = r.at("type").get<std::string>();
  if (type == "rectangle") {
    requireKnownKeys(r, {"type", "min", "max"}, ctx);
    for (const char* key : {"min", "max"})
      if (!r.contains(key)) fail(ctx, key, "missing: a rectangle needs its corners \"min\": [x0, y0] and \"max\": [x1, y1]");
    const Vec2 lo = point(r.at("min"), ctx, "min"), hi = point(r.at("max"), ctx, "max");
    if (!(hi.x() - lo.x() >= blend_width) || !(hi.y() - lo.y() >= blend_width))
      fail(ctx, "max", "the rectangle from " + jsonForMessage(r.at("min")) + " to " + jsonForMessage(r.at("max")) +
                           " must be at least blend_width = " + number(blend_width) + " m wide and long (max > min)");
    return MaterialRegion::rectangle(lo, hi);
  }
  if (type == "circle") {
    requireKnownKeys(r, {"type", "centre", "radius"}, ctx);
    for (const char* key : {"centre", "radius"})
      if (!r.contains(key)) fail(ctx, key, "missing: a circle needs \"centre\": [x, y] and \"radius\" (m)");
    const Vec2 c = point(r.at("centre"), ctx, "centre");
    const double radius = readNumber(r, "radius", 0.0, ctx, 0.0, kMaxCoordinate);
    if (!(2.0 * radius >= blend_width))
      fail(ctx, "radius", "the diameter must be at least blend_width = " + number(blend_width) + " m, got radius " + number(radius));
    return MaterialRegion::circle(c, radius);
  }
  if (type == "polygon") {
    requireKnownKeys(r, {"type", "points"}, ctx);
    if (!r.contains("points") || !r.at("points").is_array())
      fail(ctx, "points", "expected a list of points [[x, y], ...], got " + (r.contains("points") ? jsonForMessage(r.at("points")) : std::string("nothing")));
    const json& list = r.at("points");
    if (list.size() > static_cast<size_t>(limits::kMaxPolygonPoints))
      fail(ctx, "points", std::to_string(list.size()) + " points, more than the " + std::to_string(limits::kMaxPolygonPoints) + " a polygon may have");
    std::vector<Vec2> points;
    for (size_t i = 0; i < list.size(); ++i) points.push_back(point(list[i], ctx, "points[" + std::to_string(i) + "]"));
    if (const std::string problem = polygonProblem(points); !problem.empty()) fail(ctx, "points", problem);
    return MaterialRegion::polygon(std::move(points));
  }
  const std::string near = closestMatch(type, kRegionTypes);
  fail(ctx, "type", "unknown region type '" + type + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                        "; valid types: " + join(kRegionTypes));
}

void requireModelObject(const json& object, const std::string& key, const ConfigContext& ctx) {
  if (!object.contains(key)) fail(ctx, key, "missing: the material's contact model, e.g. {\"type\": \"rbf\", \"file\": \"sand.h5\"}");
  const json& m = object.at(key);
  if (!m.is_object() || !m.contains("type") || !m.at("type").is_string())
    fail(ctx, key, "expected a contact model object with a string \"type\", e.g. {\"type\": \"coulomb\"}, got " + jsonForMessage(m));
}

TerrainMaterials readPatches(const json& config, const ConfigContext& ctx) {
  const double blend_width = readNumber(config, "blend_width", kDefaultBlendWidth, ctx, -kMaxBlendWidth, kMaxBlendWidth);
  if (!(blend_width > 0.0)) fail(ctx, "blend_width", "must be positive (m), got " + number(blend_width));
  const json& list = config.at("patches");
  if (!list.is_array())
    fail(ctx, "patches", "expected a list of {\"name\", \"region\", \"model\"}, got " + jsonForMessage(list));
  if (list.size() > static_cast<size_t>(limits::kMaxMaterialPatches))
    fail(ctx, "patches", std::to_string(list.size()) + " patches, more than the " + std::to_string(limits::kMaxMaterialPatches) + " a terrain may have");
  TerrainMaterials out;
  std::vector<MaterialPatch> patches;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "patches[" + std::to_string(i) + "]";
    const ConfigContext pc = inside(ctx, key);
    const json& p = list[i];
    if (!p.is_object()) fail(pc, "", "expected {\"name\", \"region\", \"model\"}, got " + jsonForMessage(p));
    requireKnownKeys(p, kPatchKeys, pc);
    if (!p.contains("region")) fail(pc, "region", "missing: the patch's region, e.g. {\"type\": \"rectangle\", \"min\": [0, -1], \"max\": [2, 1]}");
    requireModelObject(p, "model", pc);
    MaterialPatch patch;
    patch.name = readString(p, "name", "patch " + std::to_string(i), pc);
    patch.region = readRegion(p.at("region"), inside(pc, "region"), blend_width);
    patches.push_back(std::move(patch));
    out.names.push_back(patches.back().name);
    out.models.push_back(p.at("model"));
    out.model_keys.push_back(key + ".model");
  }
  BlendKernel kernel;
  kernel.h = 0.5 * blend_width;
  for (size_t i = 0; i < patches.size(); ++i)
    for (size_t j = 0; j < i; ++j) {
      const double gap = regionSeparation(patches[i].region, patches[j].region);
      const double need = patches[i].region.reach(kernel) + patches[j].region.reach(kernel);
      if (gap >= need) continue;
      fail(ctx, "patches[" + std::to_string(i) + "]",
           "patch '" + patches[i].name + "' " +
               (gap == 0.0 ? "overlaps patch '" + patches[j].name + "' (patches[" + std::to_string(j) + "])"
                           : "is " + number(gap) + " m from patch '" + patches[j].name + "' (patches[" + std::to_string(j) +
                                 "]), closer than the " + number(need) + " m their blending bands need (blend_width " +
                                 number(blend_width) + " m)") +
               "; move them apart or join them into one patch");
    }
  if (!patches.empty()) out.layout = std::make_shared<MaterialLayout>(std::move(patches), blend_width);
  return out;
}

TerrainMaterials readMaterialMap(const json& config, const Terrain& terrain, const ConfigContext& ctx) {
  const ConfigContext mc = inside(ctx, "material_map");
  const json& map = config.at("material_map");
  const auto* heightfield = dynamic_cast<const HeightfieldTerrain*>(&terrain);
  if (!heightfield) fail(mc, "", "a material map lies on a heightfield's grid; this terrain is not a heightfield (use \"patches\")");
  if (!map.is_object()) fail(mc, "", "expected {\"file\": \"materials.csv\", \"models\": [...]}, got " + jsonForMessage(map));
  requireKnownKeys(map, kMapKeys, mc);
  if (!map.contains("file")) fail(mc, "file", "missing: a CSV of integer materials, one per heightfield node");
  if (!map.contains("models") || !map.at("models").is_array() || map.at("models").empty())
    fail(mc, "models", "expected a non-empty list of contact models, models[k - 1] for material k (0 is contacts.model)");
  const json& models = map.at("models");
  if (models.size() > static_cast<size_t>(limits::kMaxMaterialPatches))
    fail(mc, "models", std::to_string(models.size()) + " models, more than the " + std::to_string(limits::kMaxMaterialPatches) + " a terrain may have");
  TerrainMaterials out;
  for (size_t k = 0; k < models.size(); ++k) {
    const std::string key = "models[" + std::to_string(k) + "]";
    if (!models[k].is_object() || !models[k].contains("type") || !models[k].at("type").is_string())
      fail(mc, key, "expected a contact model object with a string \"type\", got " + jsonForMessage(models[k]));
    out.names.push_back("material " + std::to_string(k + 1));
    out.models.push_back(models[k]);
    out.model_keys.push_back("material_map." + key);
  }
  const std::string file = readString(map, "file", "", mc);
  const std::string path = mc.resolve(file);
  HeightGrid cells;
  try {
    cells = readHeightGridCsv(path);
  } catch (const InputError& e) {
    fail(mc, "file", e.what());
  }
  const HeightGrid& grid = heightfield->grid();
  if (cells.nx != grid.nx || cells.ny != grid.ny)
    fail(mc, "file", displayPath(path) + ": " + std::to_string(cells.nx) + " x " + std::to_string(cells.ny) +
                         " materials (columns x rows), but the heightfield has " + std::to_string(grid.nx) + " x " +
                         std::to_string(grid.ny) + " nodes: the map needs one material per node");
  MaterialGrid materials;
  materials.x0 = grid.x0;
  materials.y0 = grid.y0;
  materials.dx = grid.dx;
  materials.dy = grid.dy;
  materials.nx = grid.nx;
  materials.ny = grid.ny;
  materials.materials = static_cast<int>(models.size()) + 1;
  materials.material.reserve(cells.z.size());
  for (size_t n = 0; n < cells.z.size(); ++n) {
    const double v = cells.z[n];
    const std::string cell = "row " + std::to_string(n / cells.nx + 1) + ", column " + std::to_string(n % cells.nx + 1);
    if (v != std::floor(v)) fail(mc, "file", displayPath(path) + ": " + cell + " holds " + number(v) + ", not an integer material");
    if (v < 0) fail(mc, "file", displayPath(path) + ": " + cell + " holds " + number(v) + ": a cell with no material (0 is the default, k >= 1 models[k - 1])");
    if (v > static_cast<double>(models.size()))
      fail(mc, "file", displayPath(path) + ": " + cell + " holds material " + number(v) + ", which has no model (models lists " +
                           std::to_string(models.size()) + ": materials 1.." + std::to_string(models.size()) + ")");
    materials.material.push_back(static_cast<int>(v));
  }
  out.layout = std::make_shared<MaterialLayout>(std::move(materials));
  return out;
}

}  // namespace

const std::vector<std::string>& terrainMaterialKeys() {
  static const std::vector<std::string> keys = {"patches", "blend_width", "material_map"};
  return keys;
}

TerrainMaterials makeTerrainMaterials(const json& config, const Terrain& terrain, const ConfigContext& context) {
  ConfigContext ctx = context;
  if (ctx.where.empty()) ctx.where = "terrain";
  if (!config.is_object()) return {};
  const bool patches = config.contains("patches"), map = config.contains("material_map");
  if (patches && map) fail(ctx, "material_map", "give either \"patches\" or a \"material_map\", not both");
  if (map) {
    if (config.contains("blend_width")) fail(ctx, "blend_width", "a material map blends over one grid cell; remove blend_width");
    return readMaterialMap(config, terrain, ctx);
  }
  if (!patches) {
    if (config.contains("blend_width")) fail(ctx, "blend_width", "only used with \"patches\"");
    return {};
  }
  return readPatches(config, ctx);
}

}  // namespace nmdp
