#include "solver/time/stop_signals.hpp"

namespace sphfem {

namespace {

volatile std::sig_atomic_t received_signal = 0;
int alive = 0; // StopSignals objects alive, nested

extern "C" void record_signal(int signal) {
  received_signal = signal;
}

} // namespace

StopSignals::StopSignals() {
  if (alive++ == 0)
    received_signal = 0;
  struct sigaction action {};
  action.sa_handler = record_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previous_int_);
  sigaction(SIGTERM, &action, &previous_term_);
}

StopSignals::~StopSignals() {
  --alive;
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
}

int StopSignals::received() const {
  return received_signal;
}

} // namespace sphfem
