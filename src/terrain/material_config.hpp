// Reads a terrain's material patches or material map from its configuration (the scene's
// "terrain" object; the terrain's own keys are makeTerrain's):
//
//   "patches": [{"name": "sand pit", "region": REGION, "model": {...}}, ...],  "blend_width": 0.05
//       REGION {"type": "rectangle", "min": [x0, y0], "max": [x1, y1]}
//            | {"type": "circle", "centre": [x, y], "radius": r}
//            | {"type": "polygon", "points": [[x, y], ...]}   (simple, either orientation)
//       blend_width (m, default 0.05): the band centred on each boundary across which the
//       materials blend. Patches may not overlap, nor come closer than their bands reach
//       (blend_width / 2 beyond a circle, blend_width / √2 beyond a corner); a rectangle's sides and
//       a circle's diameter must be at least blend_width.
//   "material_map": {"file": "materials.csv", "models": [{...}, ...]}   (heightfield only)
//       one integer per heightfield node, the CSV shaped as the heightfield's; 0 is the default
//       material, k ≥ 1 takes models[k − 1]; the materials blend over one grid cell.
//
// The terrain layer reads the geometry only: each material's "model" object is passed on as given
// for the caller (the scene) to build. Errors are InputErrors naming ctx.where and the key.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/json_params.hpp"
#include "terrain/material_layout.hpp"
#include "terrain/terrain.hpp"

namespace nmdp {

struct TerrainMaterials {
  std::shared_ptr<const MaterialLayout> layout;  // null: the whole ground is the default material
  // Per material m ≥ 1 (index m − 1): its name, its "model" object as configured and the key path
  // of that object (e.g. "patches[0].model").
  std::vector<std::string> names;
  std::vector<nlohmann::json> models;
  std::vector<std::string> model_keys;
};

// Default blend width (m): 5 cm, a foot's diameter on the project's quadruped.
constexpr double kDefaultBlendWidth = 0.05;

// The terrain keys this reader owns (makeTerrain accepts them and leaves them here).
const std::vector<std::string>& terrainMaterialKeys();

// `terrain` is the terrain built from `config` (a material map needs its heightfield grid).
TerrainMaterials makeTerrainMaterials(const nlohmann::json& config, const Terrain& terrain, const ConfigContext& ctx);

}  // namespace nmdp
