// Rollout throughput (sim/rollout.hpp): entry-steps per second of a batch of B runs of S steps with 1
// and 2 threads, and their ratio, on the planar quadruped trotting on sand (RBF), the floating-base
// quadruped trotting on flat ground (Coulomb) and a foot dropped into sand with a small random MLP
// (libtorch on every thread), its Jacobian by forward-mode autograd (the default, which libtorch 1.13
// serializes across the process: contact_models/mlp/mlp_function.hpp) and by hand-coded tangents. The entries start from the states of one run at its first B steps, so
// they differ in pose and contacts. Each figure is the best of --repeats interleaved runs of the
// whole rollout call (building the simulations included, as a caller sees it); the two results are
// checked to be the same bits. CPU/wall is the process's CPU time over the wall time of that run:
// below 2 with 2 threads, the threads did not both have a core (other load on the machine, or
// something serializing them). Output: a markdown table on stdout.
//
// Usage: bench_rollout [--batch B] [--steps S] [--repeats N]
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_clock.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/registry.hpp"
#include "sim/rollout.hpp"

using namespace nmdp;

namespace {

struct Options {
  int batch = 16, steps = 50, repeats = 3;
};

struct Case {
  const char* label;
  SceneConfig scene;
};

SceneConfig sceneWith(const std::string& name, const std::vector<std::string>& overrides) {
  const std::string path = std::string(NMDP_SOURCE_DIR) + "/models/scenes/" + name;
  nlohmann::json scene = loadSceneJson(path);
  for (const std::string& assignment : overrides) applyOverride(scene, assignment, path + ": --set");
  return parseScene(scene, path);
}

// A small random MLP (2-8-15 tanh, five vertices, forces of tens of N) for the foot.
std::string writeRandomMlp(const std::string& path) {
  PlanarGeometry g;
  g.torque_centre = 0.1;
  g.cutoff = 0.1;
  g.cutoff_width = 0.02;
  MlpParameters p = randomMlpParameters(1, 8, 5, MlpActivation::Tanh, 7);
  p.output_scale.setConstant(50.0);
  saveMlpModel(path, p, g);
  return path;
}

// The flat states of one run of the scene at steps 0 .. batch − 1 (a step that fails repeats the last).
RowMajorMatrix startStates(const SceneConfig& scene, const ContactModelRegistry& models, int batch) {
  Simulation sim = buildSimulation(scene, models);
  const StateLayout layout = stateLayout(sim.system());
  RowMajorMatrix starts(batch, layout.size());
  Eigen::VectorXd x;
  for (int b = 0; b < batch; ++b) {
    if (b > 0) sim.step();
    flattenState(layout, sim.state(), x);
    starts.row(b) = x.transpose();
  }
  return starts;
}

// CPU seconds of every thread of this process so far (user and system).
double processCpuSeconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Timed {
  double best = 1e300;
  double cpu_per_wall = 0;  // of the best run: about the number of threads that ran at once
  RolloutResult result;
};

void runCase(const Case& c, const ContactModelRegistry& models, const Options& o) {
  RolloutRequest request;
  request.initial_states = startStates(c.scene, models, o.batch);
  request.steps = o.steps;
  Timed timed[2];
  for (int r = 0; r < o.repeats; ++r)
    for (int t = 0; t < 2; ++t) {
      request.threads = t + 1;
      const double start = bench::wallSeconds(), cpu_start = processCpuSeconds();
      timed[t].result = rollout(c.scene, models, request);
      const double wall = bench::wallSeconds() - start;
      if (wall < timed[t].best) {
        timed[t].best = wall;
        timed[t].cpu_per_wall = (processCpuSeconds() - cpu_start) / wall;
      }
    }
  const std::vector<double>& a = timed[0].result.states;
  const std::vector<double>& b = timed[1].result.states;
  const bool same = a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
  long done = 0;
  for (int steps : timed[0].result.steps_done) done += steps;
  const double work = static_cast<double>(o.batch) * o.steps;
  const double one = work / timed[0].best, two = work / timed[1].best;
  std::printf("| %s | %ld / %.0f | %.0f | %.0f | %.2f | %.2f / %.2f | %s |\n", c.label, done, work, one, two,
              two / one, timed[0].cpu_per_wall, timed[1].cpu_per_wall, same ? "yes" : "NO");
  std::fflush(stdout);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const int value = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--batch")) o.batch = value;
    else if (!std::strcmp(argv[i], "--steps")) o.steps = value;
    else if (!std::strcmp(argv[i], "--repeats")) o.repeats = value;
    else {
      std::fprintf(stderr, "usage: bench_rollout [--batch B] [--steps S] [--repeats N]\n");
      std::exit(2);
    }
  }
  if (o.batch < 1 || o.steps < 1 || o.repeats < 1) {
    std::fprintf(stderr, "bench_rollout: --batch, --steps and --repeats must be at least 1\n");
    std::exit(2);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const ContactModelRegistry models = ContactModelRegistry::withBuiltins();
  char tmp[] = "/tmp/bench_rollout_XXXXXX";
  if (!mkdtemp(tmp)) {
    std::perror("bench_rollout: mkdtemp");
    return 1;
  }
  const std::string mlp = writeRandomMlp(std::string(tmp) + "/foot_mlp.h5");
  const nlohmann::json mlp_model = {{"type", "mlp"}, {"file", mlp}};
  const nlohmann::json mlp_tangents = {{"type", "mlp"}, {"file", mlp}, {"jacobian", "tangents"}};
  const std::vector<Case> cases = {
      {"planar quadruped trot, sand (RBF, pbd-pgm)", sceneWith("quadruped_trot_sand.json", {})},
      {"floating quadruped trot, flat (Coulomb, ne-pgm)", sceneWith("quadruped_trot_flat.json", {})},
      {"foot drop, sand (random MLP, forward-mode Jacobian, ne-pgm)",
       sceneWith("quadruped_foot_drop_sand.json", {"contacts.model=" + mlp_model.dump()})},
      {"foot drop, sand (random MLP, tangents Jacobian, ne-pgm)",
       sceneWith("quadruped_foot_drop_sand.json", {"contacts.model=" + mlp_tangents.dump()})},
  };
  std::printf("Rollout: B = %d entries x %d steps, best of %d\n\n", o.batch, o.steps, o.repeats);
  std::printf("| scene | entry-steps done | 1 thread (entry-steps/s) | 2 threads (entry-steps/s) | ratio | "
              "CPU/wall 1 / 2 threads | same bits |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases) runCase(c, models, o);
  std::remove(mlp.c_str());
  rmdir(tmp);
  return 0;
}
