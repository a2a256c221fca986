// The trajectory writer's hook on a Simulation (sim/simulation.hpp): records a run into a
// TrajectoryWriter as `nmdp simulate` writes it. The initial state is the first row (step 0), then
// every output.every-th completed step and the last scheduled one, each with the quantities of
// sim/step_quantities.hpp and its step number (/steps of the file: the last row's). A run that ends early (a step that
// fails or is interrupted, a full disk) ends with its last completed step as the last row, never
// with the state a failed step left.
//
//   TrajectoryWriter writer(scene.output_file, trajectoryLayout(sim));
//   TrajectoryRecorder recorder(writer, sim);
//   sim.addObserver([&](const Simulation& s, const StepStats& stats) { recorder.observe(s, stats); });
//   recorder.start();
//   ... sim.step() ...
//   recorder.finish();
#pragma once
#include <Eigen/Core>
#include <vector>

#include "sim/simulation.hpp"
#include "sim/step_quantities.hpp"
#include "sim/trajectory_writer.hpp"

namespace nmdp {

class TrajectoryRecorder {
 public:
  // Keeps the simulation's current state as the first completed step. `writer` must outlive this.
  TrajectoryRecorder(TrajectoryWriter& writer, const Simulation& sim);
  TrajectoryRecorder(const TrajectoryRecorder&) = delete;
  TrajectoryRecorder& operator=(const TrajectoryRecorder&) = delete;

  void start();  // writes the first row (TrajectoryWriter::OutOfSpace as append())
  void observe(const Simulation& sim, const StepStats& stats);  // a Simulation::Observer
  void finish();  // writes the last completed step if it is not yet a row

  long completedSteps() const { return completed_; }
  double lastTime() const { return last_.time; }  // s, of the last completed step

 private:
  void keep(const Simulation& sim, const StepStats& stats);
  void record();

  TrajectoryWriter& writer_;
  StepQuantities quantities_;
  long every_, scheduled_;
  long completed_ = 0;
  TrajectoryRow last_;  // the last completed step, kept while it is not yet a row (output.every > 1)
  bool recorded_ = false;
};

}  // namespace nmdp
