// nmdp simulate SCENE.json [--set key.path=value ...] [--out FILE.h5] [--quiet]
//
// Loads the scene (io/scene.hpp), builds the robot, contacts, contact model (registry), terrain,
// gains and gait, and steps the integrator for the scene's duration, writing every recorded step
// to HDF5 as it goes (io/trajectory_writer.hpp). A step that fails even at the smallest sub-step
// ends the run: the file keeps every completed step and says why, and so does stderr.
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "app/commands.hpp"
#include "app/progress_bar.hpp"
#include "contact_models/registry.hpp"
#include "common/input_error.hpp"
#include "io/scene.hpp"
#include "io/trajectory_writer.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/integrator.hpp"
#include "terrain/terrain_factory.hpp"

namespace nmdp::app {

const char* const kSimulateHelp =
    "usage: nmdp simulate SCENE.json [--set key.path=value ...] [--out FILE.h5] [--quiet]\n"
    "\n"
    "Simulates the scene and writes the run to HDF5 as it goes (layout: DESIGN.md 11; /steps rows are\n"
    "complete, = len(/time) for a run that ended; a killed run keeps NaN rows after them). Scene keys: robot, contacts, terrain, integrator, controller, duration, output;\n"
    "everything but robot.urdf has a default (see README). Paths in a scene are relative to it.\n"
    "\n"
    "  --set key.path=value  override one key, e.g. --set integrator.method=ne-zopgm\n"
    "                        --set integrator.dt=0.02 --set contacts.model.file=sand.h5\n"
    "                        (the value is JSON if it parses as JSON, else a string)\n"
    "  --out FILE.h5         output file (default: the scene's output.file)\n"
    "  --quiet               no progress bar and no summary line\n"
    "\n"
    "Exit status: 0 the run completed; 1 bad input (nothing written that looks like a result);\n"
    "4 a step failed or the run was interrupted (the file keeps every completed step and says why).\n";

namespace {

// Set by SIGINT / SIGTERM: the loop stops after the current step and records why.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void onStopSignal(int signal) { g_stop_signal = signal; }

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

}  // namespace

int runSimulate(const Args& args) {
  const Options opt = parseArgs(args);
  nlohmann::json scene_json = loadSceneJson(opt.scene);
  for (const std::string& assignment : opt.overrides) applyOverride(scene_json, assignment, opt.scene + ": --set");
  SceneConfig config = parseScene(scene_json, opt.scene);
  if (!opt.out.empty()) {
    config.output_file = std::filesystem::absolute(opt.out).lexically_normal().string();
    config.resolved["output"]["file"] = config.output_file;  // the config records the file written
  }

  // Everything that can be wrong with the input is checked before the output file is created.
  const Model model = loadUrdf(config.urdf, urdfOptionsFor(config));
  validateAgainstModel(config, model);
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
  const long steps = std::max(1L, std::lround(config.duration / config.dt));
  // Rows reserved up front (the writer changes no metadata while running): the initial state, one row
  // per output_every steps, and a last partial group or failed step.
  layout.capacity = steps / config.output_every + 2;
  TrajectoryWriter writer(config.output_file, layout);

  Data pose_data(model);
  Vec3 base_position, base_rpy;
  auto record = [&](const StepStats& stats) {
    pose_data.base_chart = state.base_chart;
    forwardKinematics(model, pose_data, state.q);
    basePose(model, pose_data, base_position, base_rpy);
    writer.append(state.time, state.q, state.qd, base_position, base_rpy, workspace.contact_wrench, stats);
  };
  StepStats initial;
  initial.converged = true;
  record(initial);  // the first row is the initial state

  g_stop_signal = 0;
  auto previous_int = std::signal(SIGINT, onStopSignal);
  auto previous_term = std::signal(SIGTERM, onStopSignal);
  ProgressBar bar(stderr, config.duration, ProgressBar::shouldShow(stderr, opt.quiet));
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  std::string failure;
  long done = 0;
  for (long i = 0; i < steps; ++i) {
    const StepStats stats = advance(system, options, *target, state, config.dt, workspace);
    if (!stats.converged) {
      failure = std::string("step ") + std::to_string(i + 1) + " (t = " + std::to_string(state.time) + " s) failed: " +
                toString(stats.status) + " at the smallest sub-step " + std::to_string(options.min_substep) + " s";
      record(stats);  // the state where the failed step stopped, marked not converged
      break;
    }
    ++done;
    if (done % config.output_every == 0 || done == steps) record(stats);
    bar.update(static_cast<int>(done), state.time, elapsed());
    if (g_stop_signal) {
      failure = std::string("interrupted by signal ") + std::to_string(g_stop_signal) + " at t = " + std::to_string(state.time) + " s";
      break;
    }
  }
  std::signal(SIGINT, previous_int);
  std::signal(SIGTERM, previous_term);
  bar.finish();
  const double wall = elapsed();
  if (!failure.empty()) {
    writer.fail(failure);
    std::cerr << "nmdp simulate: " << failure << "; " << config.output_file << " keeps the " << done
              << " completed steps\n";
    return 4;
  }
  writer.finish();
  if (!opt.quiet)
    std::printf("%s: %ld steps, %.3g s simulated in %.3g s (%.3gx real time), %s, dt %g s\n",
                config.output_file.c_str(), done, state.time, wall, wall > 0 ? state.time / wall : 0.0,
                methodName(options.method), config.dt);
  return 0;
}

}  // namespace nmdp::app
