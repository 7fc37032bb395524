// Test helper for contact against 1D theory: two slender steel bars of square section meeting
// end to end at ±v, each in hexahedra or particles, through a contact pair of the given model.
// Records what the theory predicts — the contact force's duration, the bodies' end velocities —
// and what a contact must keep: the surfaces' worst overlap, momentum and the energy balance.
#pragma once

#include "coupled_fixture.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace sphfem::test {

struct Bar {
  Method method = Method::Fem;
  double length = 0; // m
};

struct BarImpact {
  double c0 = 0;            // √(E/ρ), m/s
  double peak_force = 0;    // largest contact force on bar b, N
  double first_force = -1;  // time the force first exceeds 1% of its peak, s
  double last_force = -1;   // time it last exceeds 1% of its peak, s
  double half_start = -1;   // time it first exceeds half its plateau (ρ c0 v A), s
  double half_end = -1;     // time it last exceeds half its plateau, s
  double late_force = 0;    // largest force `quiet_after` or later after first_force, N
  double worst_overlap = 0; // largest overlap of the two physical surfaces, m
  double momentum_error = 0;
  double balance_error = 0;                    // largest over the run
  Vec3 v_a = Vec3::Zero(), v_b = Vec3::Zero(); // end centre-of-mass velocities, m/s
  double dt_min = 1, dt_max = 0;
};

// Bars of section `side` × `side` on the z axis, a's struck end at z = −gap/2 moving +v, b's at
// +gap/2 moving −v; spacing / element size `dp`; run to `end`. contact: the pair's YAML keys
// after the bodies (e.g. "model: surface" or "model: kernel, penalty: 1e11").
inline BarImpact impact_bars(Bar a, Bar b, double side, double dp, double v, double end,
                             const std::string& contact, double quiet_after = 1.0, double cfl = 0.6,
                             const std::string& options = "", double gap = 0) {
  const auto num = [](double x) {
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", x);
    return std::string(text);
  };
  if (gap == 0)
    gap = 0.5 * dp;
  const auto body = [&](const char* name, const Bar& bar, double z0, double z1, double vz) {
    std::string s = std::string("  ") + name +
                    ":\n    method: " + (bar.method == Method::Fem ? "fem" : "sph") + "\n" +
                    "    geometry: {box: {min: [0, 0, " + num(z0) + "], max: [" + num(side) + ", " +
                    num(side) + ", " + num(z1) + "]}}\n";
    s += bar.method == Method::Fem ? "    element_size: " + num(dp) + "\n"
                                   : "    spacing: " + num(dp) + "\n";
    return s + "    material: steel\n    velocity: [0, 0, " + num(vz) + "]\n";
  };
  const std::string yaml = "name: bars\ntime: {end: " + num(end) + ", cfl: " + num(cfl) +
                           ", output_interval: 1.0}\n"
                           "materials:\n"
                           "  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, "
                           "poisson_ratio: 0.3}\n"
                           "bodies:\n" +
                           body("a", a, -0.5 * gap - a.length, -0.5 * gap, v) +
                           body("b", b, 0.5 * gap, 0.5 * gap + b.length, -v) +
                           "contact:\n  - {bodies: [a, b], " + contact + "}\n" + options;
  Coupled c(yaml, {}, read_case_text(yaml, "bars.yaml").contacts);
  Simulation sim(c.spec, c.model);
  BarImpact out;
  out.c0 = std::sqrt(207.0e9 / 7830);
  const double plateau = 7830 * out.c0 * v * side * side;
  const Vec3 P0 = sim.momentum();
  const auto& p = sim.particle_system().particles();
  const auto& nodes = sim.nodes();
  // A particle's surface lies Δp/2 beyond it (cell-centred lattice), a node's on it.
  const auto face = [&](int body, bool top) {
    double z = top ? -1e9 : 1e9;
    for (Index i = 0; i < p.size(); ++i)
      if (p.body_p[i] == body)
        z = top ? std::max(z, p.x_p[i].z() + 0.5 * dp) : std::min(z, p.x_p[i].z() - 0.5 * dp);
    for (Index i = 0; i < nodes.size(); ++i)
      if (nodes.body_n[i] == body)
        z = top ? std::max(z, nodes.x_n[i].z()) : std::min(z, nodes.x_n[i].z());
    return z;
  };
  std::vector<std::pair<double, double>> force; // (t, F on b)
  while (sim.time() < end) {
    const double dt = std::min(sim.stable_dt(), end - sim.time());
    out.dt_min = std::min(out.dt_min, dt);
    out.dt_max = std::max(out.dt_max, dt);
    sim.step(dt);
    out.worst_overlap = std::max(out.worst_overlap, face(0, true) - face(1, false));
    const auto totals = sim.bodies();
    force.emplace_back(sim.time(), totals[1].contact_force.z());
    out.balance_error = std::max(out.balance_error, sim.balance_error(sim.energies()));
  }
  for (const auto& [t, f] : force)
    out.peak_force = std::max(out.peak_force, f);
  for (const auto& [t, f] : force) {
    if (f > 0.01 * out.peak_force) {
      if (out.first_force < 0)
        out.first_force = t;
      out.last_force = t;
    }
    if (f > 0.5 * plateau) {
      if (out.half_start < 0)
        out.half_start = t;
      out.half_end = t;
    }
    if (out.first_force >= 0 && t > out.first_force + quiet_after)
      out.late_force = std::max(out.late_force, std::abs(f));
  }
  const double scale = v * (7830 * side * side * (a.length + b.length));
  out.momentum_error = (sim.momentum() - P0).norm() / scale;
  const auto totals = sim.bodies();
  out.v_a = totals[0].com_velocity;
  out.v_b = totals[1].com_velocity;
  return out;
}

} // namespace sphfem::test
