#include "app/stop_signals.hpp"

#include <signal.h>

namespace nmdp::app {

namespace {
// A signal handler can only reach static storage; StopSignals allows one instance at a time.
volatile std::sig_atomic_t g_received = 0;

extern "C" void onStopSignal(int signal) {
  if (g_received) {  // the second one: the default action, at once
    ::signal(signal, SIG_DFL);
    ::raise(signal);
    return;
  }
  g_received = signal;
}
}  // namespace

StopSignals::StopSignals() {
  g_received = 0;
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // system calls in progress (file writes) resume
  ::sigaction(SIGINT, &action, &previous_int_);
  ::sigaction(SIGTERM, &action, &previous_term_);
}

StopSignals::~StopSignals() {
  ::sigaction(SIGINT, &previous_int_, nullptr);
  ::sigaction(SIGTERM, &previous_term_, nullptr);
}

int StopSignals::received() const { return g_received; }

const volatile std::sig_atomic_t* StopSignals::flag() const { return &g_received; }

const char* StopSignals::name(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal";
}

}  // namespace nmdp::app
