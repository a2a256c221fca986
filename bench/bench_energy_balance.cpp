// The divergence check's margins (solver/energy_balance.hpp): runs scenes with every method at
// several time steps, the check measuring but never firing, and reports per run, over its converged
// steps, the largest ratio of a sub-step's energy excess (gain beyond what the PD targets,
// feed-forward and external forces supply) to its turnover, and the largest ratio of the excess to
// what the default tolerance allows (ρ · turnover + ½ m (‖g‖h)²; above 1 the check fires), with the
// step and time of each; and the first step past the default tolerance, if any. Scenes are built
// by buildSimulation, as `nmdp simulate` builds them. Output: a markdown table on stdout.
//
// Usage: bench_energy_balance [--duration S] [--methods a,b] [--dts 0.05,0.02] [--set key=value ...]
//                             SCENE.json...
//   (default: every scene under models/scenes, and the Solo-12 trot of ../shared if present)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "contact_models/registry.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"

using namespace nmdp;

namespace {

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

struct Outcome {
  int steps = 0, converged = 0;
  double worst_ratio = 0.0, worst_excess = 0.0, worst_time = 0.0;
  int worst_step = 0;
  double worst_margin = 0.0, worst_margin_time = 0.0;  // excess / allowed
  int worst_margin_step = 0;
  int first_over = 0;  // first step past the default tolerance (0: none)
  double first_over_time = 0.0, first_over_ratio = 0.0;
  std::string end;  // why the run ended early
};

Outcome run(const std::string& scene_path, const std::string& method, double dt, double duration,
            const std::vector<std::string>& overrides) {
  nlohmann::json scene = loadSceneJson(scene_path);
  for (const std::string& o : overrides) applyOverride(scene, o, scene_path);
  applyOverride(scene, "integrator.method=" + method, scene_path);
  applyOverride(scene, "integrator.dt=" + std::to_string(dt), scene_path);
  SceneConfig config = parseScene(scene, scene_path);
  const double tolerance = config.integrator.energy_tolerance;
  config.integrator.energy_tolerance = 1e300;  // the check measures but never fires (infinity would skip it)
  Simulation sim = buildSimulation(config, ContactModelRegistry::withBuiltins());
  Outcome o;
  const long steps = std::lround(std::min(duration, config.duration) / config.dt);
  for (long i = 0; i < steps; ++i) {
    const StepStats s = sim.step();
    ++o.steps;
    if (!s.converged) {
      o.end = toString(s.status);
      break;
    }
    ++o.converged;
    const double ratio = s.energy.turnover > 0 ? s.energy.excess / s.energy.turnover : 0.0;
    if (ratio > o.worst_ratio || o.converged == 1) {
      o.worst_ratio = ratio;
      o.worst_excess = s.energy.excess;
      o.worst_step = static_cast<int>(i + 1);
      o.worst_time = sim.time();
    }
    const double allowed = tolerance * s.energy.turnover + s.energy.free_fall;
    const double margin = s.energy.excess / allowed;
    if (margin > o.worst_margin || o.converged == 1) {
      o.worst_margin = margin;
      o.worst_margin_step = static_cast<int>(i + 1);
      o.worst_margin_time = sim.time();
    }
    if (!o.first_over && margin > 1.0) {
      o.first_over = static_cast<int>(i + 1);
      o.first_over_time = sim.time();
      o.first_over_ratio = ratio;
    }
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  double duration = 10.0;
  std::vector<std::string> methods = {"ne-pgm", "ne-zopgm", "pbd-pgm", "pbd-zopgm", "ne-mdp"};
  std::vector<double> dts = {0.05, 0.02, 0.01, 0.005};
  std::vector<std::string> scenes, overrides;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--set") && i + 1 < argc) {
      overrides.push_back(argv[++i]);
      continue;
    }
    if (!std::strcmp(argv[i], "--duration") && i + 1 < argc) {
      duration = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--methods") && i + 1 < argc) {
      methods = split(argv[++i]);
    } else if (!std::strcmp(argv[i], "--dts") && i + 1 < argc) {
      dts.clear();
      for (const std::string& d : split(argv[++i])) dts.push_back(std::atof(d.c_str()));
    } else {
      scenes.push_back(argv[i]);
    }
  }
  namespace fs = std::filesystem;
  if (scenes.empty()) {
    for (const auto& entry : fs::directory_iterator(std::string(NMDP_SOURCE_DIR) + "/models/scenes"))
      scenes.push_back(entry.path().string());
    std::sort(scenes.begin(), scenes.end());
    const std::string solo = std::string(NMDP_SHARED_DIR) + "/robots/solo12/urdf/solo12.urdf";
    if (fs::exists(solo)) {
      const std::string path = (fs::temp_directory_path() / "bench_energy_balance_solo12_trot.json").string();
      std::ofstream(path) << R"({"robot": {"urdf": ")" << solo
                          << R"("}, "controller": {"gait": {"type": "trot"}}, "duration": 10.0})";
      scenes.push_back(path);
    }
  }
  std::printf("| scene | method | dt (s) | steps (converged) | largest excess/turnover | at step (t) | excess (J) | "
              "largest excess/allowed | at step (t) | first step past the tolerance | ended |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& scene : scenes) {
    for (const std::string& method : methods) {
      for (double dt : dts) {
        try {
          const Outcome o = run(scene, method, dt, duration, overrides);
          char first[96] = "none";
          if (o.first_over)
            std::snprintf(first, sizeof first, "%d (t = %.3g s, ratio %.3g)", o.first_over, o.first_over_time,
                          o.first_over_ratio);
          std::printf("| %s | %s | %g | %d (%d) | %.3g | %d (%.3g s) | %.3g | %.3g | %d (%.3g s) | %s | %s |\n",
                      fs::path(scene).stem().string().c_str(), method.c_str(), dt, o.steps, o.converged, o.worst_ratio,
                      o.worst_step, o.worst_time, o.worst_excess, o.worst_margin, o.worst_margin_step,
                      o.worst_margin_time, first, o.end.empty() ? "-" : o.end.c_str());
        } catch (const std::exception& e) {
          std::printf("| %s | %s | %g | error: %s |\n", fs::path(scene).stem().string().c_str(), method.c_str(), dt,
                      e.what());
        }
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
