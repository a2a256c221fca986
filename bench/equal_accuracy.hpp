// Speed at equal accuracy, as bench_mujoco reports it: a run is "within 5 %" of its configuration's
// finest run when both are stable, its horizontal displacement |Δ(x, y)| is within 5 % of the finest
// run's, its RMS torso deviation from that run is below 5 % of that distance, and its final |yaw| is
// below 0.3 rad (the same definition as scripts/evaluation/measure.py). For each engine the cheapest
// run within 5 % (least wall time per simulated second) is its cost at equal accuracy.
#pragma once
#include <cmath>
#include <string>
#include <vector>

namespace nmdp::bench {

constexpr double kDistanceTolerance = 0.05;  // relative to the finest run's |Δ(x, y)|
constexpr double kRmsTolerance = 0.05;       // RMS torso deviation relative to the same
constexpr double kYawMax = 0.3;              // rad, |final yaw|

struct Accuracy {
  bool stable = false;
  double displacement = NAN;  // |Δ(x, y)| of the torso, start to end, m
  double yaw = NAN;           // final yaw from the start, unwrapped, rad
};

// rms: the run's RMS torso deviation from the finest run (NaN if it could not be computed).
inline bool withinTolerance(const Accuracy& run, double rms, const Accuracy& finest) {
  const double scale = std::abs(finest.displacement);
  return run.stable && finest.stable && scale > 0 &&
         std::abs(run.displacement - finest.displacement) <= kDistanceTolerance * scale && rms < kRmsTolerance * scale &&
         std::abs(run.yaw) < kYawMax;
}

// One benchmarked configuration of an engine: its family (e.g. "MuJoCo, implicit kd", "ne-pgm",
// or a list of integrator settings), dt, cost, and whether it is within tolerance of its family's
// finest run. A candidate is a timed row (not a one-off convergence check).
struct Configuration {
  std::string engine;  // "MuJoCo" or "nmdp"
  std::string family;
  double dt = 0;
  double wall_per_s = NAN, cpu_per_s = NAN;  // per simulated second
  bool within = false;
  bool candidate = true;
};

// The cheapest configuration of `engine` within tolerance, or nullptr if there is none.
inline const Configuration* cheapestWithin(const std::vector<Configuration>& configurations, const std::string& engine) {
  const Configuration* best = nullptr;
  for (const Configuration& c : configurations)
    if (c.engine == engine && c.candidate && c.within && std::isfinite(c.wall_per_s) &&
        (!best || c.wall_per_s < best->wall_per_s))
      best = &c;
  return best;
}

}  // namespace nmdp::bench
