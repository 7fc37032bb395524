// The wall time a run will take, estimated before it starts from what it holds: a cost per
// element-step, node-step, particle-step and neighbour-list entry per step (both pair loops),
// measured by bench/ on the 2-core machine of bench/README.md (1 thread, the Børvik standard
// quarter shot and the block benchmarks), a parallel efficiency of 75% per thread beyond the
// first (the same benchmarks at 2 threads), and a fixed cost per step (history row, energy
// sums, thread start-ups: 2 ms, from the small verification cases). On other machines it scales
// with their speed; it is meant to tell a minute from an hour, and is checked against real runs
// in bench/README.md.
#pragma once

#include "solver/core/types.hpp"

namespace sphfem {

// Seconds of one thread per step of each entity (bench/README.md). The domain decomposition
// weighs entities by the same figures (solver/parallel/decomposition.hpp).
struct StepCost {
  static constexpr double element = 500e-9;
  static constexpr double node = 40e-9;
  static constexpr double particle = 600e-9;
  static constexpr double entry = 30e-9; // one neighbour-list entry, both pair loops
  // What a yielding material point (material/material_point.hpp: yielding) adds to its element
  // or particle: the radial return with damage and heating. Measured 2026-12-07 on a block of
  // 50 000 hexahedra, 1 thread, two rounds: 483 ns per element-step elastic, 515 of Weldox 460 E
  // below yield, 783 yielding throughout (docs/scaling.md). The decomposition weighs the run's
  // current state by it; the wall-time estimate, made before anything yields, does not.
  static constexpr double yielding_point = 300e-9;
  // A distributed run's new cut, per particle and element of the whole model: the gather of
  // every rank's state, the bisection and the new share with its neighbour lists. Measured
  // 2026-12-07 on the Børvik shots at 2 ranks × 1 thread (median of 10 cuts of the coarse
  // shot, 15 040 entities: 40 ms; of 23 of the standard one, 50 189: 80 ms); a cut is made
  // only when the work it saves pays for it (time/simulation.hpp: Simulation::rebalance).
  static constexpr double new_cut = 2e-6;
};

struct RunSize {
  Index elements = 0;
  Index nodes = 0;
  Index particles = 0;
  long long neighbour_entries = 0; // neighbour-list entries of real and background particles
  double steps = 0;
  int threads = 1;
};

inline double estimated_wall_s(const RunSize& s) {
  constexpr double parallel_efficiency = 0.75, fixed_step = 2e-3;
  const double one_thread = StepCost::element * s.elements + StepCost::node * s.nodes +
                            StepCost::particle * s.particles +
                            StepCost::entry * static_cast<double>(s.neighbour_entries);
  const double speedup = s.threads > 1 ? parallel_efficiency * s.threads : 1.0;
  return s.steps * (fixed_step + one_thread / speedup);
}

} // namespace sphfem
