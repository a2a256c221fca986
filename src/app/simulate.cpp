// nmdp simulate SCENE.json [--set key.path=value ...] [--out FILE.h5] [--quiet]
//
// Loads the scene (sim/scene.hpp), builds its simulation (sim/simulation.hpp: robot, contacts,
// contact model from the built-in registry, terrain, gains and gait) and steps it for the scene's
// duration, writing every recorded step to HDF5 as it goes (sim/trajectory_recorder.hpp). The file only ever holds completed steps, each
// what the solver converged to: a step that fails even at the smallest sub-step, or diverges
// (solver/energy_balance.hpp), or a disk that fills ends the run with the file keeping every
// completed step and saying why, and so does stderr. SIGINT and SIGTERM are honoured in every phase
// (app/stop_signals.hpp): before the file exists the command ends with nothing written, after it
// the run ends as an interrupted one.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "app/build_version.hpp"
#include "app/commands.hpp"
#include "app/progress_bar.hpp"
#include "app/stop_signals.hpp"
#include "common/input_error.hpp"
#include "contact_models/registry.hpp"
#include "io/output_path.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"
#include "sim/step_quantities.hpp"
#include "sim/trajectory_layout.hpp"
#include "sim/trajectory_recorder.hpp"
#include "sim/trajectory_writer.hpp"

namespace nmdp::app {

const char* const kSimulateHelp =
    "usage: nmdp simulate SCENE.json [--set key.path=value ...] [--out FILE.h5] [--quiet]\n"
    "\n"
    "Simulates the scene and writes the run to HDF5 as it goes (layout: README \"Usage\"; /rows is the\n"
    "number of complete rows, the first at t = 0, /steps the time steps they cover; a killed run keeps\n"
    "NaN rows after them and opens with h5py.File(path, 'r', swmr=True)). Scene keys: robot,\n"
    "contacts, terrain, integrator, controller, duration, output; everything but robot.urdf has a\n"
    "default (see README). Paths in a scene are\n"
    "relative to it. The output never replaces an input of the run or a file nmdp did not write.\n"
    "\n"
    "  --set key.path=value  override one key, e.g. --set integrator.method=ne-zopgm\n"
    "                        --set integrator.dt=0.02 --set contacts.model.file=sand.h5\n"
    "                        (the value is JSON if it parses as JSON, else a string)\n"
    "  --out FILE.h5         output file (default: the scene's output.file)\n"
    "  --quiet               no progress bar and no summary line\n"
    "  --schema              print every scene key with its type, default, range, unit and use, and stop\n"
    "\n"
    "Exit status: 0 the run completed; 1 bad input, or no room for the file (nothing written);\n"
    "4 a step failed or diverged, the disk filled, or SIGINT/SIGTERM interrupted the run (the file\n"
    "keeps every completed step and /status says why; interrupted before the file existed: nothing\n"
    "written). A second SIGINT/SIGTERM ends the process at once.\n";

namespace {

struct Options {
  std::string scene;
  std::vector<std::string> overrides;
  std::string out;
  bool quiet = false;
};

Options parseArgs(const Args& args) {
  Options o;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--set" || a == "--out") {
      if (i + 1 >= args.size()) throw InputError(a + " needs a value (see nmdp simulate --help)");
      (a == "--set" ? o.overrides.push_back(args[++i]) : void(o.out = args[++i]));
    } else if (a.rfind("--set=", 0) == 0) {
      o.overrides.push_back(a.substr(6));
    } else if (a.rfind("--out=", 0) == 0) {
      o.out = a.substr(6);
    } else if (a == "--quiet" || a == "-q") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw InputError("unknown option '" + a + "' (see nmdp simulate --help)");
    } else if (o.scene.empty()) {
      o.scene = a;
    } else {
      throw InputError("one scene file expected, got '" + o.scene + "' and '" + a + "'");
    }
  }
  if (o.scene.empty()) throw InputError("a scene file is required (see nmdp simulate --help)");
  return o;
}

// The files a run reads, which its output may not replace (io/output_path.hpp).
std::vector<RunInput> runInputs(const SceneConfig& config) {
  std::vector<RunInput> inputs = {{config.path, "the scene"}, {config.urdf, "the URDF"}};
  if (!config.keyframe_file.empty()) inputs.push_back({config.keyframe_file, "the keyframe file"});
  // Every "file" or "*_file" string of the contact model and the terrain (resolved absolute by parseScene).
  const auto addFiles = [&](const nlohmann::json& object, const std::string& role, const auto& self) -> void {
    if (!object.is_object()) return;
    for (const auto& [key, value] : object.items()) {
      const bool file_key = key == "file" || (key.size() > 5 && key.compare(key.size() - 5, 5, "_file") == 0);
      if (value.is_string() && file_key)
        inputs.push_back({value.template get<std::string>(), role + " (" + key + ")"});
      else if (value.is_object())
        self(value, role, self);
    }
  };
  addFiles(config.contact_model, "a contact-model file", addFiles);
  addFiles(config.terrain, "the terrain file", addFiles);
  return inputs;
}

std::string seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", t);
  return text;
}

// Why step `index` (from t0) ended the run.
std::string describeFailure(const StepStats& stats, long index, double t0, const IntegratorOptions& options) {
  const std::string step = "step " + std::to_string(index) + " (from t = " + seconds(t0) + " s)";
  if (stats.status == StepStatus::Diverged) {
    char numbers[200];
    std::snprintf(numbers, sizeof numbers,
                  "its energy rose by %.3g J, %.3g J more than the PD targets, feed-forward and external forces "
                  "can supply (allowed: %.3g J)",
                  stats.energy.excess + stats.energy.supplied, stats.energy.excess, stats.energy.tolerance);
    return step + " diverged: " + numbers;
  }
  return step + " failed: " + toString(stats.status) + " at the smallest sub-step " + seconds(options.min_substep) + " s";
}

// The scene with the command line's --set overrides and --out.
SceneConfig loadScene(const Options& opt) {
  nlohmann::json scene_json = loadSceneJson(opt.scene);
  for (const std::string& assignment : opt.overrides) applyOverride(scene_json, assignment, opt.scene + ": --set");
  SceneConfig config = parseScene(scene_json, opt.scene);
  if (!opt.out.empty()) {
    config.output_file = std::filesystem::absolute(opt.out).lexically_normal().string();
    config.resolved["output"]["file"] = config.output_file;  // the config records the file written
  }
  return config;
}

// How a run ended: why it ended early (writer status "failed: ..." or "interrupted ..."), if it did.
struct Ending {
  std::string failure, interruption;
  bool early() const { return !failure.empty() || !interruption.empty(); }
};

// Steps the simulation for the scene's duration, writing as it goes (the recorder observes every
// completed step), until a step fails, a signal arrives or the disk fills.
Ending runSteps(Simulation& sim, TrajectoryRecorder& recorder, const StopSignals& stop) {
  Ending end;
  const long steps = sim.scheduledSteps();
  try {
    recorder.start();  // the first row is the initial state
    for (long i = 0; i < steps; ++i) {
      if (stop.received()) break;
      const double t0 = sim.time();
      const StepStats stats = sim.step(stop.flag());
      if (!stats.converged) {
        if (stats.status != StepStatus::Cancelled) end.failure = describeFailure(stats, i + 1, t0, sim.options());
        break;
      }
    }
    if (stop.received() && end.failure.empty() && recorder.completedSteps() < steps)
      end.interruption = std::string("by ") + StopSignals::name(stop.received()) + " at t = " + seconds(recorder.lastTime()) + " s";
    recorder.finish();  // the last completed step, not the state a failed or interrupted step left
  } catch (const TrajectoryWriter::OutOfSpace& e) {
    end.failure = "stopped at t = " + seconds(recorder.lastTime()) + " s, the disk being full: " + e.what();
  }
  return end;
}

}  // namespace

int runSimulate(const Args& args) {
  if (args.size() == 1 && args[0] == "--schema") return std::cout << sceneSchemaText(), 0;
  const Options opt = parseArgs(args);
  const StopSignals stop;
  // Before the output exists an interruption ends the command with nothing written.
  auto interruptedWhile = [&](const char* phase) {
    std::cerr << "nmdp simulate: interrupted by " << StopSignals::name(stop.received()) << " while " << phase
              << "; nothing was written\n";
    return 4;
  };
  const SceneConfig config = loadScene(opt);
  checkOutputFile(config.output_file, runInputs(config), opt.out.empty() ? opt.scene + ": output.file" : "--out");
  if (stop.received()) return interruptedWhile("loading the scene");

  // Everything that can be wrong with the input is checked before the output file is created.
  Model robot = loadSceneRobot(config);
  if (stop.received()) return interruptedWhile("loading the robot");
  Simulation sim = buildSimulation(config, std::move(robot), ContactModelRegistry::withBuiltins());
  if (stop.received()) return interruptedWhile("building the simulation");

  TrajectoryLayout layout = trajectoryLayout(sim);
  layout.string_attributes["nmdp_version"] = buildVersion().version;
  layout.string_attributes["nmdp_commit"] = buildVersion().commit;
  TrajectoryWriter writer(config.output_file, layout);  // its first chunk only: it grows as the run goes
  TrajectoryRecorder recorder(writer, sim);
  ProgressBar bar(stderr, config.duration, ProgressBar::shouldShow(stderr, opt.quiet));
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  sim.addObserver([&](const Simulation& s, const StepStats& stats) {
    recorder.observe(s, stats);
    bar.update(static_cast<int>(recorder.completedSteps()), s.time(), elapsed());
  });
  const Ending end = runSteps(sim, recorder, stop);
  bar.finish();
  const double wall = elapsed();
  const long done = recorder.completedSteps(), rows = writer.rows();
  if (end.early()) {
    if (!end.failure.empty())
      writer.fail(end.failure);
    else
      writer.interrupt(end.interruption);
    std::cerr << "nmdp simulate: " << (end.failure.empty() ? "interrupted " + end.interruption : end.failure) << "; "
              << config.output_file << " keeps the " << done << " completed steps (" << rows << " rows)\n";
    return 4;
  }
  writer.finish();
  if (stop.received())
    std::cerr << "nmdp simulate: " << StopSignals::name(stop.received())
              << " arrived as the run was finishing; the run is complete\n";
  if (!opt.quiet)
    std::printf("%s: %ld steps, %.3g s simulated in %.3g s (%.3gx real time), %s, dt %g s\n",
                config.output_file.c_str(), done, sim.time(), wall, wall > 0 ? sim.time() / wall : 0.0,
                methodName(sim.options().method), config.dt);
  return 0;
}

}  // namespace nmdp::app
