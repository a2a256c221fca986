// The issue-4 benchmark: the project's quadruped trotting on flat ground with the Coulomb model,
// dt = 50 ms, one core, every method. Per method: median and 90th-percentile wall time per step, the
// median CPU time of the thread per step (what one core spends, whatever else the machine runs),
// outer iterations and sub-steps per step, the smallest sub-step, failed steps, heap allocations
// inside steps after warm-up (counted by replacing malloc), and where the robot went (forward
// distance, torso height range). Runs are repeated and interleaved so the figures share the VM's
// noise. Output: a markdown table on stdout.
//
// Usage: bench_integrator [--repeats N] [--duration S] [--dt S]
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "bench_clock.hpp"
#include "contact_models/coulomb_model.hpp"
#include "control/gait.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/integrator.hpp"
#include "terrain/plane.hpp"

#define NMDP_COUNT_MALLOC
#include "tests/support/test_allocation_counter.hpp"

using namespace nmdp;

namespace {

struct RunResult {
  std::vector<double> wall;  // per step, s
  std::vector<double> cpu;   // per step, s: this thread's CPU time (less sensitive to other load)
  long outer = 0, substeps = 0, failed = 0, allocations = 0;
  double min_substep = 1e9;
  double forward = 0, z_min = 1e9, z_max = -1e9;
  int steps = 0;
};

using bench::threadCpuSeconds;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5));
  return v[i];
}

struct Configuration {
  Method method;
  KineticEnergyMeasure kinetic_energy;
  ZerothOrderJacobian zeroth_order = ZerothOrderJacobian::FiniteDifference;
  int repeats = 0;  // 0: --repeats
  std::string name() const {
    std::string n = methodName(method);
    if (isZeroOrder(method)) n += std::string(" (") + zerothOrderJacobianName(zeroth_order) + ")";
    return n;
  }
};

RunResult run(const Model& model, const Configuration& configuration, double dt, double duration) {
  CoulombModel contact_model;
  PlaneTerrain terrain;
  System system = systemOnFeet(model, contact_model, terrain, massScaledPdGains(model));
  IntegratorOptions options;
  options.method = configuration.method;
  options.kinetic_energy = configuration.kinetic_energy;
  options.zeroth_order_jacobian = configuration.zeroth_order;
  options.accuracy = 0;  // the cost of one step of the method at dt, as its history in docs/BENCHMARKS.md
  const KeyframePdTarget trot = makeTrotTarget(model);
  const StandingPose pose = standingPose(model, identifyQuadrupedLegs(model), {});
  StepWorkspace ws(system, options);
  SimulationState state = initialState(system, options, pose.q, Eigen::VectorXd::Zero(model.nq), dt);
  RunResult r;
  const int steps = static_cast<int>(duration / dt + 0.5);
  const int warm_up = std::min(5, steps / 10);
  const double x0 = pose.q[0];
  for (int i = 0; i < steps; ++i) {
    test::alloc::counting = i >= warm_up;
    const long before = test::alloc::malloc_calls.load();
    const double cpu_before = threadCpuSeconds();
    const StepStats s = advance(system, options, trot, state, dt, ws);
    const double cpu = threadCpuSeconds() - cpu_before;
    test::alloc::counting = false;
    r.cpu.push_back(cpu);
    if (i >= warm_up) r.allocations += test::alloc::malloc_calls.load() - before;
    r.wall.push_back(s.wall_time);
    r.outer += s.outer_iterations;
    r.substeps += s.substeps;
    if (s.substeps > 0) r.min_substep = std::min(r.min_substep, s.min_substep);
    ++r.steps;
    if (!s.converged) {
      ++r.failed;
      break;  // the state is where the failed step left it
    }
    r.z_min = std::min(r.z_min, state.q[2]);
    r.z_max = std::max(r.z_max, state.q[2]);
  }
  r.forward = state.q[0] - x0;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 3;
  double duration = 10.0, dt = 0.05;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--repeats")) repeats = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--duration")) duration = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--dt")) dt = std::atof(argv[i + 1]);
  }
  const Model model = loadUrdf(std::string(NMDP_SOURCE_DIR) + "/models/quadruped/quadruped.urdf", {});
  const StandingPose pose = standingPose(model, identifyQuadrupedLegs(model), {});
  const KineticEnergyMeasure body = KineticEnergyMeasure::FullBody, points = KineticEnergyMeasure::ContactPoints,
                             body_pd = KineticEnergyMeasure::FullBodyPd;
  const ZerothOrderJacobian dropped = ZerothOrderJacobian::Dropped;
  std::vector<Configuration> methods;
  for (const KineticEnergyMeasure k : {body, points, body_pd}) {
    for (const Method m : {Method::NePgm, Method::NeZopgm, Method::PbdPgm, Method::PbdZopgm}) methods.push_back({m, k});
    if (k == body) methods.push_back({Method::NeMdp, body});
  }
  // The paper's zeroth-order Jacobian takes minutes per run: once each.
  methods.push_back({Method::NeZopgm, body, dropped, 1});
  methods.push_back({Method::PbdZopgm, body, dropped, 1});
  std::vector<std::vector<RunResult>> results(methods.size());
  for (int rep = 0; rep < repeats; ++rep)
    for (size_t m = 0; m < methods.size(); ++m)
      if (methods[m].repeats == 0 || rep < methods[m].repeats)
        results[m].push_back(run(model, methods[m], dt, duration));

  std::printf("Quadruped (%s, %d DOF, %.2f kg) trotting on flat ground, Coulomb contact, dt = %g s, %g s simulated, "
              "%d interleaved runs per method (the dropped-Jacobian rows: one); standing torso height %.3f m.\n\n",
              model.robot_name.c_str(), model.nq, model.total_mass, dt, duration, repeats, pose.height);
  std::printf("| method | K | median wall / step | range of run medians | p90 wall / step | median CPU / step | "
              "outer it. / step | sub-steps / step | smallest sub-step | failed steps | allocations in steps | forward | "
              "torso height |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (size_t m = 0; m < methods.size(); ++m) {
    std::vector<double> all, medians, cpu;
    long outer = 0, substeps = 0, failed = 0, allocations = 0, steps = 0;
    double min_substep = 1e9;
    for (const RunResult& r : results[m]) {
      all.insert(all.end(), r.wall.begin(), r.wall.end());
      cpu.insert(cpu.end(), r.cpu.begin(), r.cpu.end());
      medians.push_back(percentile(r.wall, 0.5));
      outer += r.outer;
      substeps += r.substeps;
      failed += r.failed;
      allocations += r.allocations;
      steps += r.steps;
      min_substep = std::min(min_substep, r.min_substep);
    }
    const RunResult& last = results[m].back();
    char where[160];
    if (last.failed)
      std::snprintf(where, sizeof where, "failed at t = %.2f s | —", last.steps * dt);
    else
      std::snprintf(where, sizeof where, "%.2f m | %.3f–%.3f m", last.forward, last.z_min, last.z_max);
    std::printf("| %s | %s | %.3f ms | %.3f–%.3f ms | %.3f ms | %.3f ms | %.2f | %.2f | %.2g s | %ld | %ld | %s |\n",
                methods[m].name().c_str(), kineticEnergyName(methods[m].kinetic_energy), 1e3 * percentile(all, 0.5),
                1e3 * *std::min_element(medians.begin(), medians.end()),
                1e3 * *std::max_element(medians.begin(), medians.end()), 1e3 * percentile(all, 0.9),
                1e3 * percentile(cpu, 0.5), double(outer) / steps, double(substeps) / steps, min_substep, failed, allocations, where);
  }
  std::printf("\nforward: base x travelled in the last run; torso height: range of base z over it (standing %.3f m).\n"
              "A failed run stops at its failed step (ne-mdp is explicit and is expected to blow up at 50 ms).\n",
              pose.height);
  return 0;
}
