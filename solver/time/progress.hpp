// Progress of a long run: on a terminal a line rewritten in place a few times a second, else
// a plain line every few seconds (into the run log too): step, time, Δt, steps/s, ETA.
#pragma once

#include "solver/io/run_log.hpp"

#include <chrono>

namespace sphfem {

class Progress {
public:
  Progress(double end_time, RunLog& log);
  void update(long long steps, double time, double dt);
  void finish();

private:
  using Clock = std::chrono::steady_clock;
  double end_time_;
  RunLog& log_;
  bool terminal_;
  Clock::time_point start_, last_;
  bool drawn_ = false;
};

} // namespace sphfem
