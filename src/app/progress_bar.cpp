#include "app/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace nmdp::app {

namespace {
constexpr int kBarWidth = 24;
}

bool ProgressBar::shouldShow(std::FILE* stream, bool quiet) {
  return !quiet && stream != nullptr && ::isatty(::fileno(stream)) == 1;
}

ProgressBar::ProgressBar(std::FILE* stream, double duration, bool enabled)
    : stream_(stream), duration_(duration), enabled_(enabled && stream != nullptr) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && drawn_ && !finished_) {
    std::fputc('\n', stream_);
    std::fflush(stream_);
  }
}

void ProgressBar::update(int steps, double sim_time, double wall_seconds) {
  if (!enabled_ || finished_) return;
  steps_ = steps;
  sim_time_ = sim_time;
  wall_seconds_ = wall_seconds;
  if (drawn_ && wall_seconds - last_draw_wall_ < kMinRedrawInterval) return;
  last_draw_wall_ = wall_seconds;
  draw();
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  draw();
  std::fputc('\n', stream_);
  std::fflush(stream_);
  finished_ = true;
}

void ProgressBar::draw() {
  const double fraction =
      duration_ > 0.0 && std::isfinite(sim_time_) ? std::clamp(sim_time_ / duration_, 0.0, 1.0) : 0.0;
  const int filled = static_cast<int>(fraction * kBarWidth);
  char bar[kBarWidth + 1];
  for (int i = 0; i < kBarWidth; ++i) bar[i] = i < filled ? '=' : (i == filled ? '>' : ' ');
  bar[kBarWidth] = '\0';

  char factor[32];
  if (wall_seconds_ > 0.0)
    std::snprintf(factor, sizeof factor, "%.2fx real time", sim_time_ / wall_seconds_);
  else
    std::snprintf(factor, sizeof factor, "--x real time");
  char line[160];
  const int length = std::snprintf(line, sizeof line, "[%s] %3d%%  step %d  t %.2f / %.2f s  %s", bar,
                                   static_cast<int>(fraction * 100.0), steps_, sim_time_, duration_, factor);
  const int printed = std::min(length, static_cast<int>(sizeof line) - 1);
  // Spaces over the tail of a longer previous line (the step count and the factor change width).
  std::fprintf(stream_, "\r%s%*s", line, std::max(0, last_length_ - printed), "");
  std::fflush(stream_);
  last_length_ = printed;
  drawn_ = true;
}

}  // namespace nmdp::app
