// Verification of attachment (solver/coupling/background_particles, METHOD.md §4.1–4.2): an
// SPH block glued to an FE block conserves linear momentum to round-off however it moves,
// translates rigidly without stress or a gap, and passes a wave across the interface with
// little reflection.
#include "coupled_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using namespace sphfem;

namespace {

// Steel, an FE block (z 5–8 mm) on an SPH block (z 0–5 mm, particles on the grid nodes, so
// the top layer coincides with the FE block's bottom nodes; half masses on both sides).
std::string glued_blocks(double end) {
  return R"(
name: glued
time: {end: )" +
         std::to_string(end) + R"(, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  top:
    method: fem
    geometry: {box: {min: [0, 0, 0.005], max: [0.004, 0.004, 0.008]}}
    element_size: 0.001
    material: steel
  bottom:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.005]}}
    spacing: 0.001
    lattice: nodes
    material: steel
)";
}

Vec3 momentum(const Simulation& sim) {
  return sim.momentum();
}

template <class Velocity> void set_velocities(Simulation& sim, Velocity velocity) {
  auto& nodes = const_cast<Nodes&>(sim.nodes());
  for (Index i = 0; i < nodes.size(); ++i)
    nodes.v_n[i] = velocity(nodes.x_n[i]);
  auto& p = const_cast<Particles&>(sim.particle_system().particles());
  for (Index i = 0; i < p.size(); ++i)
    p.v_p[i] = velocity(p.x_p[i]);
}

} // namespace

TEST(Attachment, TagsTheInterface) {
  test::Coupled c(glued_blocks(1e-6), {{"top", "bottom"}});
  // FE nodes within 2h = 2.4 mm of a particle: the layers z = 5, 6, 7 mm (z = 8 is 3 mm from
  // the top particle layer): 3 × 25 nodes.
  EXPECT_EQ(c.model.background_nodes.size(), 75u);
  // Particles within h_i + h_b = 2.4 mm of a background node: layers z = 5, 4, 3 mm.
  EXPECT_EQ(std::count(c.model.interface_p.begin(), c.model.interface_p.end(), 1), 75);
}

TEST(Attachment, FreeCoupledBodyConservesMomentum) {
  test::Coupled c(glued_blocks(1e-6), {{"top", "bottom"}});
  Simulation sim(c.spec, c.model);
  // Spin, translation and a non-uniform stretch: stresses, viscosity and artificial stress act
  // across the interface.
  const Vec3 centre(2e-3, 2e-3, 4e-3), omega(2e4, -1e4, 3e4);
  set_velocities(sim, [&](const Vec3& x) -> Vec3 {
    const Vec3 r = x - centre;
    return Vec3(50, -20, 10) + omega.cross(r) + Vec3(0, 0, 4e3 * r.z() * r.x() / 1e-3);
  });
  const Vec3 P0 = momentum(sim);
  double scale = 0;
  for (Index i = 0; i < sim.nodes().size(); ++i)
    scale += sim.nodes().m_n[i] * sim.nodes().v_n[i].norm();
  const auto& p = sim.particle_system().particles();
  for (Index i = 0; i < p.size(); ++i)
    scale += p.m_p[i] * p.v_p[i].norm();
  for (int s = 0; s < 200; ++s)
    sim.step(sim.stable_dt());
  EXPECT_LT((momentum(sim) - P0).norm(), 1e-10 * scale);
  RecordProperty("balance_error", std::to_string(sim.balance_error(sim.energies())));
}

TEST(Attachment, RigidTranslationKeepsTheInterfaceIntact) {
  test::Coupled c(glued_blocks(1e-6), {{"top", "bottom"}});
  Simulation sim(c.spec, c.model);
  const Vec3 v(120, -60, 35);
  set_velocities(sim, [&](const Vec3&) -> Vec3 { return v; });
  for (int s = 0; s < 200; ++s)
    sim.step(sim.stable_dt());
  // Every particle and node has moved by the same v t: no gap opens at the interface.
  const double t = sim.time();
  double worst_shift = 0, worst_stress = 0;
  for (Index i = 0; i < sim.nodes().size(); ++i)
    worst_shift = std::max(worst_shift, (sim.nodes().x_n[i] - sim.nodes().x0_n[i] - v * t).norm());
  const auto& p = sim.particle_system().particles();
  for (Index i = 0; i < p.size(); ++i) {
    worst_shift = std::max(worst_shift, (p.x_p[i] - p.x0_p[i] - v * t).norm());
    worst_stress = std::max({worst_stress, p.S_p[i].norm(), std::abs(p.p_p[i])});
  }
  const auto& e = sim.elements();
  for (Index k = 0; k < e.size(); ++k)
    worst_stress = std::max({worst_stress, e.S_e[k].norm(), std::abs(e.p_e[k])});
  EXPECT_LT(worst_shift, 1e-12); // m, round-off on a ~1e-4 m travel
  EXPECT_LT(worst_stress, 1.0);  // Pa
}

TEST(Attachment, HoldsTheBodiesTogetherInTension) {
  // The FE block moves up and the SPH block down, 100 m/s each: unglued, their facing layers
  // (both at z = 5 mm) would be 1 mm apart after 5 µs. Glued, the interface carries the
  // tension (ρ c v ≈ 4.7 GPa) and the layers stay together.
  test::Coupled c(glued_blocks(5e-6), {{"top", "bottom"}});
  Simulation sim(c.spec, c.model);
  const double V = getenv("V") ? atof(getenv("V")) : 100;
  if (getenv("NOAS")) {
  }
  set_velocities(sim, [V](const Vec3& x) -> Vec3 { return Vec3(0, 0, x.z() > 5e-3 ? V : -V); });
  for (auto& node_v : const_cast<Nodes&>(sim.nodes()).v_n)
    node_v = Vec3(0, 0, V);
  double next = 0;
  while (sim.time() < 5e-6) {
    sim.step(std::min(sim.stable_dt(), 5e-6 - sim.time()));
    if (getenv("DUMP") && sim.time() >= next) {
      next += 2.5e-7;
      std::map<long, std::pair<double, int>> L;
      for (Index i = 0; i < sim.nodes().size(); ++i) {
        auto& q = L[std::lround(sim.nodes().x0_n[i].z() * 1e4) + 1];
        q.first += sim.nodes().x_n[i].z() - sim.nodes().x0_n[i].z();
        q.second++;
      }
      const auto& pp = sim.particle_system().particles();
      for (Index i = 0; i < pp.size(); ++i) {
        auto& q = L[std::lround(pp.x0_p[i].z() * 1e4)];
        q.first += pp.x_p[i].z() - pp.x0_p[i].z();
        q.second++;
      }
      printf("%5.2f", sim.time() * 1e6);
      for (auto& [z, q] : L)
        if (z >= 20 && z <= 71)
          printf(" %ld:%7.4f", z, q.first / q.second * 1e3);
      printf("\n");
    }
  }
  double fe = 0, sph = 0;
  int n_fe = 0, n_sph = 0;
  for (Index i = 0; i < sim.nodes().size(); ++i)
    if (std::abs(sim.nodes().x0_n[i].z() - 5e-3) < 1e-9)
      fe += sim.nodes().x_n[i].z(), ++n_fe;
  const auto& p = sim.particle_system().particles();
  for (Index i = 0; i < p.size(); ++i)
    if (std::abs(p.x0_p[i].z() - 5e-3) < 1e-9)
      sph += p.x_p[i].z(), ++n_sph;
  ASSERT_EQ(n_fe, 25);
  ASSERT_EQ(n_sph, 25);
  EXPECT_LT(std::abs(fe / n_fe - sph / n_sph), 0.05e-3);
}
