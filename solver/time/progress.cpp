#include "solver/time/progress.hpp"

#include <cstdio>
#include <unistd.h>

namespace sphfem {

Progress::Progress(double end_time, RunLog& log)
    : end_time_(end_time), log_(log), terminal_(log.echo() && isatty(STDERR_FILENO)),
      start_(Clock::now()), last_(start_) {}

void Progress::update(long long steps, double time, double dt) {
  const auto now = Clock::now();
  const double since_last = std::chrono::duration<double>(now - last_).count();
  if (since_last < (terminal_ ? 0.25 : 5.0))
    return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = steps / elapsed;
  const double eta = time > 0 ? elapsed * (end_time_ - time) / time : 0.0;
  char text[160];
  std::snprintf(text, sizeof text,
                "step %lld  t %.4e s (%.0f%%)  dt %.3e s  %.0f steps/s  ETA %.0f s", steps, time,
                100.0 * time / end_time_, dt, rate, eta);
  if (terminal_) {
    std::fprintf(stderr, "\r%s\033[K", text);
    drawn_ = true;
  } else {
    log_.line(text);
  }
}

void Progress::finish() {
  if (drawn_)
    std::fprintf(stderr, "\r\033[K");
}

} // namespace sphfem
