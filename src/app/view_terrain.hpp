// The terrain of the page: the run's terrain rebuilt (terrain/terrain_factory.hpp) and sampled on a
// grid covering every run's trunk path and foot points with a margin, with the dominant ground
// material at each node (terrain/material_config.hpp) and a colour per material.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "terrain/terrain.hpp"

namespace nmdp::app {

// The page's grid: at most this many nodes a side, nodes at least kMinGridSpacing apart (m), and
// the margin around the paths it covers (m).
inline constexpr int kMaxGridNodes = 256;
inline constexpr double kMinGridSpacing = 0.01;
inline constexpr double kGridMargin = 1.0;

struct GridBounds {
  Eigen::Vector2d lower = Eigen::Vector2d::Constant(1e300), upper = Eigen::Vector2d::Constant(-1e300);
  void add(double x, double y);
  bool empty() const { return lower.x() > upper.x(); }
};

// The payload's Terrain object for `config` (a terrain object of a scene); files in it are relative
// to `base_dir`; `where` names it in warnings. A terrain that cannot be rebuilt gives a warning and
// the plane z = 0.
nlohmann::json terrainPayload(const nlohmann::json& config, const std::string& base_dir, const std::string& where,
                              const nlohmann::json& default_model, const GridBounds& bounds, std::vector<std::string>& warnings);

// The terrain of `config` rebuilt, or the plane z = 0 with a warning when it cannot be.
std::unique_ptr<Terrain> rebuildTerrain(const nlohmann::json& config, const std::string& base_dir, const std::string& where,
                                        std::vector<std::string>& warnings);
// z of the surface above (x, y).
double surfaceHeight(const Terrain& terrain, double x, double y);

// The colour of a ground material by its contact model type: rigid (coulomb) grey, sand (a learned
// granular model) yellow-brown, others distinct.
std::vector<double> materialColor(const nlohmann::json& model, int index);

}  // namespace nmdp::app
