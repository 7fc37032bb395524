// Shared by the step benchmarks: the command line ([steps] [threads...]) and the timed run —
// a fresh Simulation per repetition, one warm-up step, then `steps` steps at the stable step;
// the best wall time of three is kept, since single timings on a shared VM scatter by ±20%.
#pragma once

#include "bench/command_line.hpp"
#include "solver/time/simulation.hpp"

#include <omp.h>

#include <chrono>
#include <limits>
#include <string>
#include <vector>

namespace sphfem::bench {

struct Options {
  int steps;
  std::vector<int> threads;
};

inline Options parse(int argc, char** argv, int default_steps, const char* usage) {
  help(argc, argv, usage);
  Options o{argc > 1 ? whole_number(argv[1], usage) : default_steps, {}};
  for (int i = 2; i < argc; ++i)
    o.threads.push_back(whole_number(argv[i], usage));
  if (o.threads.empty())
    o.threads = {1, 2};
  return o;
}

// Best wall time (s) of three runs of `steps` steps with `threads` threads; `inspect` sees
// each finished simulation (e.g. to count neighbours).
template <class Inspect>
double best_wall(const Case& c, const Model& model, int steps, int threads, Inspect inspect) {
  omp_set_num_threads(threads);
  double wall = std::numeric_limits<double>::infinity();
  for (int repetition = 0; repetition < 3; ++repetition) {
    Simulation sim(c, model);
    sim.step(sim.stable_dt()); // warm-up
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s)
      sim.step(sim.stable_dt());
    const auto stop = std::chrono::steady_clock::now();
    wall = std::min(wall, std::chrono::duration<double>(stop - start).count());
    inspect(sim);
  }
  return wall;
}

} // namespace sphfem::bench
