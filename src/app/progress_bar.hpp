// A one-line progress display for `nmdp simulate`: a bar, the step count, the simulated time out of
// the duration and the real-time factor (simulated seconds per wall-clock second), redrawn in place
// with '\r'. It belongs to the application: the library never prints.
//
// update() is meant to be called every step. It redraws at most once per kMinRedrawInterval of the
// wall time it is given, so between redraws it costs one comparison and reads no clock itself.
#pragma once
#include <cstdio>

namespace nmdp::app {

class ProgressBar {
 public:
  static constexpr double kMinRedrawInterval = 0.1;  // s of wall time: at most 10 redraws a second

  // True when `stream` is a terminal and the user did not ask for quiet output: a bar written with
  // '\r' into a file or a pipe is only noise.
  static bool shouldShow(std::FILE* stream, bool quiet);

  // duration: the simulated time the run aims for, s. A disabled bar writes nothing at all.
  ProgressBar(std::FILE* stream, double duration, bool enabled);
  // Ends a drawn, unfinished line so that an error message after an aborted run starts on its own line.
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // steps taken, simulated time reached (s) and wall time since the start of the run (s).
  void update(int steps, double sim_time, double wall_seconds);
  // Draws the last state given to update() and ends the line. Later calls do nothing.
  void finish();

 private:
  void draw();

  std::FILE* stream_;
  double duration_;
  bool enabled_;
  bool finished_ = false;
  bool drawn_ = false;             // a line is on the screen
  double last_draw_wall_ = 0.0;    // wall time of the last redraw
  int steps_ = 0;
  double sim_time_ = 0.0;
  double wall_seconds_ = 0.0;
  int last_length_ = 0;            // characters of the last line, to blank a longer old one
};

}  // namespace nmdp::app
