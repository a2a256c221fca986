// Scene files with --set overrides (src/sim/scene.hpp): the scene JSON, then any number of lines
// "--set key.path=value". Built as `nmdp simulate` builds it (robot, contacts, contact model,
// terrain, gains, gait, start state; paths resolve against models/scenes/, so seeds reach the
// project's robots, models and terrains) and stepped up to three times, without an output file.
#include <algorithm>

#include "common/json_text.hpp"
#include "contact_models/registry.hpp"
#include "fuzz/fuzz_support.hpp"
#include "sim/scene.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/integrator.hpp"
#include "terrain/terrain_factory.hpp"

namespace {

// `nmdp simulate` turns a builder's std::invalid_argument into an input error naming the scene.
template <class F>
auto asInputError(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw nmdp::InputError(e.what());
  }
}

void simulate(const std::string& text) {
  using namespace nmdp;
  const std::string scene_path = fuzz::sourcePath("models/scenes/fuzz.json");
  const std::vector<std::string> parts = fuzz::split(text, 64, "\n--set ");
  nlohmann::json scene = parseJson(parts[0], scene_path);
  if (!scene.is_object()) throw InputError("not an object");
  for (size_t i = 1; i < parts.size(); ++i) applyOverride(scene, parts[i].substr(0, parts[i].find('\n')), scene_path);
  const SceneConfig config = parseScene(scene, scene_path);
  const Model model = loadUrdf(config.urdf, urdfOptionsFor(config));
  validateAgainstModel(config, model);
  const std::unique_ptr<ContactModel> contact_model =
      ContactModelRegistry::withBuiltins().build(config.contact_model, ConfigContext{"contacts.model", config.base_dir});
  const std::unique_ptr<Terrain> terrain = makeTerrain(config.terrain, ConfigContext{"terrain", config.base_dir});
  System system;
  system.model = &model;
  system.contacts = contactPointsFor(config, model);
  system.contact_model = contact_model.get();
  system.terrain = terrain.get();
  system.gains = gainsFor(config, model);
  const std::unique_ptr<PdTargetSource> target = asInputError([&] { return gaitFor(config, model); });
  asInputError([&] { validateSystem(system, config.integrator); });
  const Eigen::VectorXd q0 = initialConfiguration(config, model);
  const Eigen::VectorXd qd0 = initialVelocity(config, model);
  (void)resolvedWithModel(config, model).dump(2);  // the root attribute `config` of the output
  StepWorkspace workspace(system, config.integrator);
  SimulationState state = initialState(system, config.integrator, q0, qd0, config.dt);
  const long steps = std::min(3L, std::max(1L, std::lround(config.duration / config.dt)));
  for (long i = 0; i < steps; ++i)
    if (!advance(system, config.integrator, *target, state, config.dt, workspace).converged) break;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  nmdp::fuzz::acceptingInputErrors([&] { simulate(nmdp::fuzz::asText(data, size)); });
  return 0;
}
