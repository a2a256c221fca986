// nmdp simulate SCENE.json [--set key.path=value ...] [--out FILE.h5] [--quiet]
//
// Loads the scene (sim/scene.hpp), builds the robot, contacts, contact model (registry), terrain,
// gains and gait, and steps the integrator for the scene's duration, writing every recorded step
// to HDF5 as it goes (sim/trajectory_writer.hpp). The file only ever holds completed steps, each
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

#include "app/commands.hpp"
#include "app/progress_bar.hpp"
#include "app/stop_signals.hpp"
#include "common/input_error.hpp"
#include "contact_models/registry.hpp"
#include "io/output_path.hpp"
#include "sim/scene.hpp"
#include "sim/trajectory_writer.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/integrator.hpp"
#include "terrain/terrain_factory.hpp"

namespace nmdp::app {

const char* const kSimulateHelp =
    "usage: nmdp simulate SCENE.json [--set key.path=value ...] [--out FILE.h5] [--quiet]\n"
    "\n"
    "Simulates the scene and writes the run to HDF5 as it goes (layout: DESIGN.md 11; /steps is the\n"
    "number of rows, each a completed step; a killed run keeps NaN rows after them and opens with\n"
    "h5py.File(path, 'r', swmr=True)). Scene keys: robot, contacts, terrain, integrator, controller,\n"
    "duration, output; everything but robot.urdf has a default (see README). Paths in a scene are\n"
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

// Library builders report unusable values with std::invalid_argument; at the edge they become
// input errors naming the scene.
template <class F>
auto asInputError(const std::string& where, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw InputError(where + ": " + e.what());
  }
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

// The completed step a run ends with: what a row is written from.
struct LastStep {
  double time = 0.0;
  Eigen::VectorXd q, qd;
  Mat3 base_chart = Mat3::Identity();
  std::vector<Vec6> wrench;
  StepStats stats;
  bool recorded = false;
};

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
  nlohmann::json scene_json = loadSceneJson(opt.scene);
  for (const std::string& assignment : opt.overrides) applyOverride(scene_json, assignment, opt.scene + ": --set");
  SceneConfig config = parseScene(scene_json, opt.scene);
  if (!opt.out.empty()) {
    config.output_file = std::filesystem::absolute(opt.out).lexically_normal().string();
    config.resolved["output"]["file"] = config.output_file;  // the config records the file written
  }
  checkOutputFile(config.output_file, runInputs(config), opt.out.empty() ? opt.scene + ": output.file" : "--out");
  if (stop.received()) return interruptedWhile("loading the scene");

  // Everything that can be wrong with the input is checked before the output file is created.
  const Model model = loadUrdf(config.urdf, urdfOptionsFor(config));
  validateAgainstModel(config, model);
  if (stop.received()) return interruptedWhile("loading the robot");
  const ConfigContext model_ctx{opt.scene + ": contacts.model", config.base_dir};
  const std::unique_ptr<ContactModel> contact_model = ContactModelRegistry::withBuiltins().build(config.contact_model, model_ctx);
  const std::unique_ptr<Terrain> terrain = makeTerrain(config.terrain, ConfigContext{opt.scene + ": terrain", config.base_dir});
  System system;
  system.model = &model;
  system.contacts = contactPointsFor(config, model);
  system.contact_model = contact_model.get();
  system.terrain = terrain.get();
  system.gains = gainsFor(config, model);
  const std::unique_ptr<PdTargetSource> target = asInputError(opt.scene + ": controller.gait", [&] { return gaitFor(config, model); });
  const IntegratorOptions& options = config.integrator;
  asInputError(opt.scene, [&] { validateSystem(system, options); });
  const Eigen::VectorXd q0 = initialConfiguration(config, model);
  const Eigen::VectorXd qd0 = initialVelocity(config, model);
  StepWorkspace workspace(system, options);
  SimulationState state = initialState(system, options, q0, qd0, config.dt);
  if (stop.received()) return interruptedWhile("building the simulation");

  TrajectoryLayout layout;
  layout.joint_names = model.dof_names;
  for (const ContactPoint& c : system.contacts) layout.contact_names.push_back(c.name);
  nlohmann::json resolved = resolvedWithModel(config, model);
  // The model's own account of its parameters lists the defaults it filled in, not only the keys given.
  if (nlohmann::json used = contact_model->configuration(); !used.is_null()) resolved["contacts"]["model"] = std::move(used);
  layout.config_json = resolved.dump(2);
  layout.string_attributes = {{"robot", model.robot_name},
                              {"method", methodName(options.method)},
                              {"contact_model", contact_model->describe()},
                              {"terrain", terrain->describe()}};
  layout.number_attributes = {{"dt", config.dt}, {"duration", config.duration}};
  TrajectoryWriter writer(config.output_file, layout);  // its first chunk only: it grows as the run goes

  Data pose_data(model);
  Vec3 base_position, base_rpy;
  // The last completed step, kept while it is not yet a row (output.every > 1) so that a run that
  // ends early still ends with it.
  LastStep last;
  last.q = state.q;
  last.qd = state.qd;
  last.wrench = workspace.contact_wrench;
  auto record = [&](const LastStep& step) {
    pose_data.base_chart = step.base_chart;
    forwardKinematics(model, pose_data, step.q);
    basePose(model, pose_data, base_position, base_rpy);
    writer.append(step.time, step.q, step.qd, base_position, base_rpy, step.wrench, step.stats);
  };
  auto keep = [&](const StepStats& stats) {
    last.time = state.time;
    last.q = state.q;
    last.qd = state.qd;
    last.base_chart = state.base_chart;
    last.wrench = workspace.contact_wrench;
    last.stats = stats;
    last.recorded = false;
  };
  StepStats initial;
  initial.converged = true;
  keep(initial);
  std::string failure, interruption;  // why the run ended early (writer status "failed: ..." or "interrupted ...")
  const long steps = std::max(1L, std::lround(config.duration / config.dt));
  ProgressBar bar(stderr, config.duration, ProgressBar::shouldShow(stderr, opt.quiet));
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  long done = 0;
  try {
    record(last);  // the first row is the initial state
    last.recorded = true;
    for (long i = 0; i < steps; ++i) {
      if (stop.received()) break;
      const double t0 = state.time;
      const StepStats stats = advance(system, options, *target, state, config.dt, workspace, stop.flag());
      if (!stats.converged) {
        if (stats.status != StepStatus::Cancelled) failure = describeFailure(stats, i + 1, t0, options);
        break;
      }
      ++done;
      keep(stats);
      if (done % config.output_every == 0 || done == steps) {
        record(last);
        last.recorded = true;
      }
      bar.update(static_cast<int>(done), state.time, elapsed());
    }
    if (stop.received() && failure.empty() && done < steps)
      interruption = std::string("by ") + StopSignals::name(stop.received()) + " at t = " + seconds(last.time) + " s";
    if (!last.recorded) {
      record(last);  // the last completed step, not the state a failed or interrupted step left
      last.recorded = true;
    }
  } catch (const TrajectoryWriter::OutOfSpace& e) {
    failure = "stopped at t = " + seconds(last.time) + " s, the disk being full: " + e.what();
  }
  bar.finish();
  const double wall = elapsed();
  const long rows = writer.steps();
  if (!failure.empty() || !interruption.empty()) {
    if (!failure.empty())
      writer.fail(failure);
    else
      writer.interrupt(interruption);
    std::cerr << "nmdp simulate: " << (failure.empty() ? "interrupted " + interruption : failure) << "; "
              << config.output_file << " keeps the " << done << " completed steps (" << rows << " rows)\n";
    return 4;
  }
  writer.finish();
  if (stop.received())
    std::cerr << "nmdp simulate: " << StopSignals::name(stop.received())
              << " arrived as the run was finishing; the run is complete\n";
  if (!opt.quiet)
    std::printf("%s: %ld steps, %.3g s simulated in %.3g s (%.3gx real time), %s, dt %g s\n",
                config.output_file.c_str(), done, state.time, wall, wall > 0 ? state.time / wall : 0.0,
                methodName(options.method), config.dt);
  return 0;
}

}  // namespace nmdp::app
