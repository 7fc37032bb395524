// SIGINT and SIGTERM during a run: while a StopSignals lives, either signal only sets a flag;
// the run loop finishes the current step, writes a checkpoint and stops with a message saying
// how to continue (run.cpp). The previous handlers come back when it dies. StopSignals nest: a
// sweep's outlives its runs', and a signal received between two runs (while one meshes) is still
// there for the next run's to see; only the outermost one starts with no signal received.
#pragma once

#include <csignal>

namespace sphfem {

class StopSignals {
public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The signal received (SIGINT or SIGTERM), 0 if none.
  int received() const;

private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

} // namespace sphfem
