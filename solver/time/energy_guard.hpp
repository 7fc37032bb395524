// Energy guard: stops a run whose energy balance error — the figure summary.json reports,
// |E − E0 − W_ext| / max(E_kin + E_int, |W_ext|, E0) — passes `time.energy_limit`. An instability
// that creates or loses energy (a needle element ringing with a growing amplitude, a contact
// pumping) does so for thousands of steps before anything is NaN; a run that goes on past it
// reports numbers that mean nothing. Not checked in the first 5% of the run, where the energies
// are too small for a relative error to mean much (docs/stability.md). The message names the
// energy that moved most since the previous check and the fastest node or live particle: where
// to look in the last frame.
#pragma once

#include "solver/time/simulation.hpp"

#include <optional>

namespace sphfem {

class EnergyGuard {
public:
  // `limit`: the largest balance error let through (a fraction); `quiet_until`: the time (s)
  // before which nothing is checked.
  EnergyGuard(double limit, double quiet_until) : limit_(limit), quiet_until_(quiet_until) {}

  // Whether check(sim, e) throws.
  bool trips(const Simulation& sim, const Energies& e) const {
    return sim.time() >= quiet_until_ && sim.balance_error(e) > limit_;
  }
  // Throws Error when e's balance error passes the limit; otherwise remembers e.
  void check(const Simulation& sim, const Energies& e);

private:
  double limit_, quiet_until_;
  std::optional<Energies> previous_;
  double previous_time_ = 0;
};

} // namespace sphfem
