// SIGINT and SIGTERM while a command runs: the first one only raises a flag, which the command
// polls between its phases and the integrator polls inside a step (CancelFlag), so the command ends
// cleanly at the next check and says so; a second one restores the default action and re-raises
// itself, ending the process at once (an output file then stays as a killed run leaves it).
// One instance at a time (signal handlers are process-wide); the previous handlers come back when
// it is destroyed.
#pragma once
#include <csignal>

namespace nmdp::app {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  int received() const;                    // the first signal received, 0 if none
  const volatile std::sig_atomic_t* flag() const;  // nonzero once one was received
  static const char* name(int signal);     // "SIGINT", "SIGTERM"

 private:
  struct sigaction previous_int_, previous_term_;
};

}  // namespace nmdp::app
