// The process's peak resident memory so far (getrusage's ru_maxrss: kB on Linux), reported in
// summary.json so that a user can size a job: what one rank needed, libraries included.
#pragma once

#include <sys/resource.h>

namespace sphfem {

inline double peak_resident_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

} // namespace sphfem
