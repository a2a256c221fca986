// The clocks the benchmarks read: this thread's CPU time (what one core spends on the work, whatever
// else the machine runs) and the monotonic wall clock.
#pragma once
#include <chrono>
#include <ctime>

namespace nmdp::bench {

inline double threadCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

inline double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace nmdp::bench
