// Simulations of the repository's scenes for the tests of the simulation layer: the scene file with
// --set style overrides, built with the Coulomb and RBF contact models only (no libtorch to load;
// tests of the MLP use ContactModelRegistry::withBuiltins and link nmdp_mlp).
#pragma once
#include <string>
#include <vector>

#include "contact_models/coulomb_model.hpp"
#include "contact_models/rbf_model.hpp"
#include "contact_models/registry.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

namespace nmdp::test {

inline ContactModelRegistry coulombAndRbf() {
  ContactModelRegistry r;
  r.add("coulomb", kCoulombParameters, makeCoulombModel);
  r.add("rbf", kRbfParameters, makeRbfModel);
  return r;
}

// models/scenes/<name> with overrides as `--set key=value` gives them.
inline SceneConfig repositoryScene(const std::string& name, const std::vector<std::string>& overrides = {}) {
  const std::string path = sourcePath("models/scenes/" + name);
  nlohmann::json scene = loadSceneJson(path);
  for (const std::string& assignment : overrides) applyOverride(scene, assignment, path + ": --set");
  return parseScene(scene, path);
}

inline Simulation repositorySimulation(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return buildSimulation(repositoryScene(name, overrides), coulombAndRbf());
}

// Scenes that together exercise what a step carries to the next: a planar robot on sand (RBF, PBD),
// a floating-base trot and a jump on rigid ground (Coulomb, NE form, impacts, chart rebases), and
// second order with error control (sub-step history, the controller's next step size).
struct SceneCase {
  const char* name;
  std::vector<std::string> overrides;
};
inline std::vector<SceneCase> carryOverScenes() {
  return {{"quadruped_trot_sand.json", {}},
          {"quadruped_trot_flat.json", {}},
          {"quadruped_jump_flat.json", {}},
          {"quadruped_trot_flat.json", {"integrator.order=2", "integrator.accuracy=0.01"}}};
}

}  // namespace nmdp::test
