// The cost of TrajectoryWriter::append for the quadruped's sizes (18 coordinates, 4 contacts), per
// step, at several flush intervals; nominally a few µs against a 0.3 ms integrator step.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "sim/trajectory_writer.hpp"

namespace {

using nmdp::TrajectoryLayout;
using nmdp::TrajectoryWriter;

void Append(benchmark::State& state) {
  const int n = 18, contacts = 4;
  TrajectoryLayout layout;
  for (int j = 0; j < n; ++j) layout.joint_names.push_back("joint" + std::to_string(j));
  for (int c = 0; c < contacts; ++c) layout.contact_names.push_back("foot" + std::to_string(c));
  layout.flush_every = static_cast<int>(state.range(0));
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("nmdp_bench_writer_" + std::to_string(::getpid()) + ".h5")).string();
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(n, 0.0, 1.0), qd = q * 0.5;
  const std::vector<nmdp::Vec6> wrench(contacts, nmdp::Vec6::Constant(1.0));
  nmdp::StepStats stats;
  stats.converged = true;
  {
    TrajectoryWriter w(path, layout);
    double t = 0.0;
    for (auto _ : state) {
      w.append(t, q, qd, nmdp::Vec3(t, 0.0, 0.3), nmdp::Vec3::Zero(), wrench, stats);
      t += 0.05;
    }
    w.finish();
  }
  std::filesystem::remove(path);
}
BENCHMARK(Append)->Arg(1)->Arg(10)->Arg(50)->Arg(100)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
