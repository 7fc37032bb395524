#include "solver/time/energy_guard.hpp"

#include "solver/core/error.hpp"
#include "solver/core/format.hpp"
#include "solver/parallel/ranks.hpp"

#include <array>
#include <cmath>
#include <string>
#include <utility>

namespace sphfem {

namespace {

// "eroded energy -6.02e+03 J since t = 5.81e-04 s": the term that changed most.
std::string largest_change(const Energies& now, const std::optional<Energies>& before,
                           double before_time) {
  if (!before)
    return "no earlier check to compare with";
  const std::array<std::pair<const char*, double>, 7> change{{
      {"kinetic energy", now.kinetic - before->kinetic},
      {"internal energy", now.internal - before->internal},
      {"hourglass energy", now.hourglass - before->hourglass},
      {"contact energy", now.contact - before->contact},
      {"eroded energy", now.eroded - before->eroded},
      {"friction energy", now.friction - before->friction},
      {"external work", now.external_work - before->external_work},
  }};
  auto largest = change[0];
  for (const auto& c : change)
    if (std::abs(c.second) > std::abs(largest.second))
      largest = c;
  return detail::concat(largest.first, " ", format("%+.3g", largest.second),
                        " J since t = ", format("%.4e", before_time), " s");
}

// "node 1234 of plate at (x, y, z) m, |v| = 1.6e+04 m/s": the fastest node or live particle.
std::string fastest_entity(const Simulation& sim) {
  const Nodes& n = sim.nodes();
  const Particles& p = sim.particle_system().particles();
  double fastest = -1;
  Vec3 at = Vec3::Zero();
  std::string what;
  for (Index i = 0; i < n.size(); ++i)
    if (const double v = n.v_n[i].norm(); v > fastest) {
      fastest = v, at = n.x_n[i];
      what = detail::concat("node ", i, " of ", sim.body_names()[n.body_n[i]]);
    }
  // The particles each rank steps (all on one process); the fastest over the ranks, the first
  // rank's on a tie.
  std::array<double, 6> mine{-1, 0, 0, 0, 0, 0}; // |v|, x, y, z, model id, body
  for (Index i = 0; i < p.size(); ++i)
    if (const double v = p.v_p[i].norm();
        sim.owns_row(i) && p.kill_p[i] == Kill::None && v > mine[0])
      mine = {v, p.x_p[i].x(), p.x_p[i].y(), p.x_p[i].z(), double(p.id_p[i]), double(p.body_p[i])};
  const std::vector<double> all = ranks::gather_all(mine);
  for (std::size_t r = 0; r < all.size(); r += mine.size())
    if (all[r] > fastest) {
      fastest = all[r], at = {all[r + 1], all[r + 2], all[r + 3]};
      what = detail::concat("particle ", Index(all[r + 4]), " of ",
                            sim.body_names()[static_cast<std::size_t>(all[r + 5])]);
    }
  if (fastest < 0)
    return "no node or live particle";
  return detail::concat("fastest: ", what, " at (", format("%.4g", at.x()), ", ",
                        format("%.4g", at.y()), ", ", format("%.4g", at.z()),
                        ") m, |v| = ", format("%.3g", fastest), " m/s");
}

} // namespace

void EnergyGuard::check(const Simulation& sim, const Energies& e) {
  if (trips(sim, e)) {
    const double error = sim.balance_error(e);
    const double excess = e.total() - e.external_work - sim.initial_energy();
    throw Error(detail::concat(
        "energy balance error ", format("%.3g", 100 * error),
        "% at t = ", format("%.6e", sim.time()), " s (step ", sim.steps(),
        ") passes time.energy_limit (", format("%.3g", 100 * limit_), "%): the run is unstable, ",
        format("%.3g", std::abs(excess)), " J ", excess > 0 ? "created" : "lost", " (",
        largest_change(e, previous_, previous_time_), "; ", fastest_entity(sim),
        "); the frames, the history to here and any checkpoint kept (docs/stability.md, ",
        "\"Guards\")"));
  }
  previous_ = e;
  previous_time_ = sim.time();
}

} // namespace sphfem
