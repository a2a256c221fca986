#include "app/view_terrain.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "app/view_page.hpp"
#include "common/input_error.hpp"
#include "terrain/material_config.hpp"
#include "terrain/terrain_factory.hpp"

namespace nmdp::app {

namespace {

std::string modelType(const nlohmann::json& model) {
  return model.is_object() && model.contains("type") && model["type"].is_string() ? model["type"].get<std::string>() : "";
}

// The ground's name by its model: "rigid" for coulomb, "sand" for a learned (granular) model.
std::string materialKind(const nlohmann::json& model) {
  const std::string type = modelType(model);
  if (type == "coulomb" || type.empty()) return "rigid";
  if (type == "rbf" || type == "mlp") return "sand";
  return type;
}

}  // namespace

// φ(x, y, z) = 0 by Newton's method along z (exact in one step for the vertical distance of
// heightfields and procedural terrain, a few steps for a tilted plane).
double surfaceHeight(const Terrain& terrain, double x, double y) {
  TerrainQuery q;
  double z = 0.0;
  for (int iteration = 0; iteration < 20; ++iteration) {
    terrain.query(Vec3(x, y, z), q, true);
    if (!std::isfinite(q.distance)) return 0.0;
    if (std::abs(q.distance) < 1e-9) break;
    z -= q.distance / std::max(q.gradient.z(), 1e-3);
  }
  return z;
}

std::unique_ptr<Terrain> rebuildTerrain(const nlohmann::json& config, const std::string& base_dir, const std::string& where,
                                        std::vector<std::string>& warnings) {
  const ConfigContext ctx{where, base_dir};
  try {
    return makeTerrain(config, ctx);
  } catch (const InputError& e) {
    warnings.push_back(where + " cannot be rebuilt (" + e.what() + "): the ground is taken as the plane z = 0");
    return makeTerrain(nlohmann::json::object(), ctx);
  }
}

void GridBounds::add(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  lower = lower.cwiseMin(Eigen::Vector2d(x, y));
  upper = upper.cwiseMax(Eigen::Vector2d(x, y));
}

std::vector<double> materialColor(const nlohmann::json& model, int index) {
  const std::string kind = materialKind(model);
  if (kind == "rigid") return {0.62, 0.62, 0.64};
  if (kind == "sand") return {0.80, 0.66, 0.40};
  static const double kOthers[][3] = {{0.35, 0.55, 0.80}, {0.45, 0.72, 0.42}, {0.78, 0.42, 0.42}, {0.62, 0.45, 0.78}};
  const double* c = kOthers[static_cast<size_t>(index) % 4];
  return {c[0], c[1], c[2]};
}

nlohmann::json terrainPayload(const nlohmann::json& config, const std::string& base_dir, const std::string& where,
                              const nlohmann::json& default_model, const GridBounds& bounds, std::vector<std::string>& warnings) {
  const ConfigContext ctx{where, base_dir};
  std::unique_ptr<Terrain> terrain;
  TerrainMaterials materials;
  try {
    terrain = makeTerrain(config, ctx);
    materials = makeTerrainMaterials(config, *terrain, ctx);
  } catch (const InputError& e) {
    warnings.push_back(where + " cannot be rebuilt (" + e.what() + "): the ground is drawn as the plane z = 0");
    terrain = makeTerrain(nlohmann::json::object(), ctx);
    materials = TerrainMaterials{};
  }
  Eigen::Vector2d lower = bounds.empty() ? Eigen::Vector2d::Zero() : bounds.lower;
  Eigen::Vector2d upper = bounds.empty() ? Eigen::Vector2d::Zero() : bounds.upper;
  lower.array() -= kGridMargin;
  upper.array() += kGridMargin;
  int n[2];
  double spacing[2];
  for (int k = 0; k < 2; ++k) {
    const double width = upper[k] - lower[k];
    n[k] = static_cast<int>(std::clamp(std::floor(width / kMinGridSpacing) + 1, 2.0, static_cast<double>(kMaxGridNodes)));
    spacing[k] = width / (n[k] - 1);
  }
  const int nx = n[0], ny = n[1];
  std::vector<float> heights(static_cast<size_t>(nx) * ny);
  std::vector<std::uint8_t> material(heights.size(), 0);
  const int count = materials.layout ? materials.layout->materialCount() : 1;
  std::vector<double> w(count), wx(count), wy(count);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = lower.x() + i * spacing[0], y = lower.y() + j * spacing[1];
      const size_t at = static_cast<size_t>(j) * nx + i;
      heights[at] = static_cast<float>(surfaceHeight(*terrain, x, y));
      if (materials.layout) {
        materials.layout->weights(x, y, w.data(), wx.data(), wy.data());
        material[at] = static_cast<std::uint8_t>(std::min<long>(std::max_element(w.begin(), w.end()) - w.begin(), 255));
      }
    }
  nlohmann::json list = nlohmann::json::array();
  list.push_back({{"name", materialKind(default_model)}, {"color", materialColor(default_model, 0)}});
  for (size_t m = 0; m < materials.names.size(); ++m)
    list.push_back({{"name", materials.names[m]}, {"color", materialColor(materials.models[m], static_cast<int>(m) + 1)}});
  return {{"kind", "grid"},
          {"description", terrain->describe()},
          {"origin", {lower.x(), lower.y()}},
          {"spacing", {spacing[0], spacing[1]}},
          {"size", {nx, ny}},
          {"heights", floatArray(heights, {static_cast<size_t>(ny), static_cast<size_t>(nx)})},
          {"material", byteArray(material, {static_cast<size_t>(ny), static_cast<size_t>(nx)})},
          {"materials", list}};
}

}  // namespace nmdp::app
