// Scene files with --set overrides (src/sim/scene.hpp): the scene JSON, then any number of lines
// "--set key.path=value". Built by buildSimulation as `nmdp simulate` builds it (robot, contacts,
// contact model, terrain, gains, gait, start state, the resolved scene; paths resolve against
// models/scenes/, so seeds reach the project's robots, models and terrains) and stepped up to three
// times, without an output file.
#include <algorithm>

#include "common/json_text.hpp"
#include "contact_models/registry.hpp"
#include "fuzz/fuzz_support.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"

namespace {

void simulate(const std::string& text) {
  using namespace nmdp;
  const std::string scene_path = fuzz::sourcePath("models/scenes/fuzz.json");
  const std::vector<std::string> parts = fuzz::split(text, 64, "\n--set ");
  nlohmann::json scene = parseJson(parts[0], scene_path);
  if (!scene.is_object()) throw InputError("not an object");
  for (size_t i = 1; i < parts.size(); ++i) applyOverride(scene, parts[i].substr(0, parts[i].find('\n')), scene_path);
  Simulation sim = buildSimulation(parseScene(scene, scene_path), ContactModelRegistry::withBuiltins());
  (void)sim.resolvedScene().dump(2);  // the root attribute `config` of the output
  const long steps = std::min(3L, sim.scheduledSteps());
  for (long i = 0; i < steps; ++i)
    if (!sim.step().converged) break;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  nmdp::fuzz::acceptingInputErrors([&] { simulate(nmdp::fuzz::asText(data, size)); });
  return 0;
}
