#include "sim/trajectory_recorder.hpp"

namespace nmdp {

TrajectoryRecorder::TrajectoryRecorder(TrajectoryWriter& writer, const Simulation& sim)
    : writer_(writer), quantities_(sim), every_(sim.scene().output_every), scheduled_(sim.scheduledSteps()) {
  last_.resize(trajectoryLayout(sim));
  StepStats initial;
  initial.converged = true;
  keep(sim, initial);
}

void TrajectoryRecorder::keep(const Simulation& sim, const StepStats& stats) {
  quantities_.compute(sim, last_);
  last_.step = completed_;
  last_.stats = stats;
  recorded_ = false;
}

void TrajectoryRecorder::record() {
  writer_.append(last_);
  recorded_ = true;
}

void TrajectoryRecorder::start() { record(); }

void TrajectoryRecorder::observe(const Simulation& sim, const StepStats& stats) {
  ++completed_;
  keep(sim, stats);
  if (completed_ % every_ == 0 || completed_ == scheduled_) record();
}

void TrajectoryRecorder::finish() {
  if (!recorded_) record();
}

}  // namespace nmdp
