// Builds a terrain from its JSON configuration object (DESIGN.md §8, §11 scene key `terrain`).
//
//   {"type": "plane", "normal": [0, 0, 1], "offset": 0}
//       φ = n̂·p − offset, n̂ = normal/‖normal‖ (defaults shown). An empty object, null, or an object
//       without "type" is this plane: the default terrain.
//   {"type": "heightfield", "file": "hills.csv", "origin": [x0, y0], "spacing": [dx, dy], "offset": 0}
//       heights from a CSV file (rows along y, columns along x; see readHeightGridCsv), the path
//       relative to the configuration file's folder; node (i, j) at (x0 + i dx, y0 + j dy);
//       "spacing" is required (a number means dx = dy), "origin" defaults to [0, 0], "offset" (m)
//       is added to every height; "heights": [[z, ...], ...] (rows along y) in place of "file" gives
//       them inline (the output's /terrain/description does). Bicubic spline, clamped to the border outside the grid
//       (HeightfieldTerrain).
//   {"type": "procedural", "slope": [slope_x, slope_y], "offset": 0,
//    "hills": [{"centre": [x, y], "height": h, "width": w}, ...]}
//       slope angles in rad (a single number is slope_x), hills Gaussian with standard deviation
//       `width` (ProceduralTerrain); all keys optional.
//
// Every type also accepts the material keys "patches" and "blend_width", a heightfield also
// "material_map": makeTerrain leaves them to makeTerrainMaterials (material_config.hpp).
//
// Every error is an InputError naming ctx.where and the key (or the file, line and column): an
// unknown type lists the valid types, an unknown key the valid keys.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/json_params.hpp"
#include "terrain/terrain.hpp"

namespace nmdp {

std::unique_ptr<Terrain> makeTerrain(const nlohmann::json& config, const ConfigContext& ctx);

// The valid values of "type".
const std::vector<std::string>& terrainTypes();

}  // namespace nmdp
