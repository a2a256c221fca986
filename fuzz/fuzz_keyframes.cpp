// Keyframe files (CSV or JSON, src/sim/scene.hpp) of a scene's "keyframes" gait on the project's
// quadruped: validated, built into PD targets, sampled over two cycles, and the start pose solved.
#include "fuzz/fuzz_support.hpp"
#include "sim/scene.hpp"
#include "multibody/urdf_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace nmdp;
  static const Model model = loadUrdf(fuzz::sourcePath("models/quadruped/quadruped.urdf"));
  fuzz::Scratch& scratch = fuzz::Scratch::fresh();
  const std::string file = scratch.write("keyframes.txt", fuzz::asText(data, size));
  for (const bool cyclic : {false, true}) {
    fuzz::acceptingInputErrors([&] {
      const nlohmann::json scene = {{"robot", {{"urdf", model.source}}},
                                    {"controller", {{"gait", {{"type", "keyframes"}, {"file", file}, {"cyclic", cyclic}}}}}};
      const SceneConfig config = parseScene(scene, scratch.path("scene.json"));
      validateAgainstModel(config, model);
      const std::unique_ptr<PdTargetSource> gait = gaitFor(config, model);
      PdTarget target{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
      for (double t : {0.0, 0.013, 0.5, 1.7, 3.0, 1e4}) gait->evaluate(t, target);
      initialConfiguration(config, model);
    });
  }
  return 0;
}
