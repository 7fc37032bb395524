// Verification of penalty contact (solver/coupling/contact, METHOD.md §4.3): an SPH block and
// an FE block colliding at 200 m/s each conserve momentum to round-off, never interpenetrate
// by more than Δp/2, and rebound; without a declared contact pair they pass through each other.
#include "coupled_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sphfem;

namespace {

const double dp = 1e-3;

// SPH block A (z 0–4 mm, centred lattice, +200 m/s) and FE block B (z 7–11 mm, −200 m/s).
const std::string blocks = R"(
name: impact
time: {end: 1.6e-5, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  a:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.004]}}
    spacing: 0.001
    material: steel
    velocity: [0, 0, 200]
  b:
    method: fem
    geometry: {box: {min: [0, 0, 0.007], max: [0.004, 0.004, 0.011]}}
    element_size: 0.001
    material: steel
    velocity: [0, 0, -200]
)";

struct Impact {
  double worst_overlap = -1; // max over time of (A's surface) − (B's surface), m
  double momentum_error = 0; // |P − P0| / Σ m |v0|
  Vec3 v_a = Vec3::Zero(), v_b = Vec3::Zero();
};

Impact collide(bool contact) {
  test::Coupled c(blocks, {},
                  contact ? std::vector<ContactSpec>{{{"a", "b"}, ContactModel::Kernel, 1e11, 2}}
                          : std::vector<ContactSpec>{});
  Simulation sim(c.spec, c.model);
  const Vec3 P0 = sim.momentum();
  Impact out;
  while (sim.time() < c.spec.time.end) {
    sim.step(std::min(sim.stable_dt(), c.spec.time.end - sim.time()));
    // A's surface lies Δp/2 beyond its outer particles (centred lattice), B's on its nodes.
    double top_a = -1, bottom_b = 1;
    const auto& p = sim.particle_system().particles();
    for (Index i = 0; i < p.size(); ++i)
      top_a = std::max(top_a, p.x_p[i].z() + 0.5 * dp);
    for (Index i = 0; i < sim.nodes().size(); ++i)
      bottom_b = std::min(bottom_b, sim.nodes().x_n[i].z());
    out.worst_overlap = std::max(out.worst_overlap, top_a - bottom_b);
  }
  const double scale = 2 * 200.0 * (7830 * 64e-9);
  out.momentum_error = (sim.momentum() - P0).norm() / scale;
  for (const BodyTotals& b : sim.bodies())
    (b.name == "a" ? out.v_a : out.v_b) = b.com_velocity;
  return out;
}

} // namespace

TEST(Contact, BodiesRepelWithoutInterpenetrating) {
  const Impact r = collide(true);
  RecordProperty("worst_overlap_mm", std::to_string(r.worst_overlap * 1e3));
  EXPECT_LT(r.momentum_error, 1e-10);
  EXPECT_LT(r.worst_overlap, 0.5 * dp);
  // Elastic blocks of equal mass rebound: each ends moving away from the other.
  EXPECT_LT(r.v_a.z(), 0.0);
  EXPECT_GT(r.v_b.z(), 0.0);
}

TEST(Contact, IsOptIn) {
  // No contact pair: the blocks pass through each other untouched.
  const Impact r = collide(false);
  EXPECT_GT(r.worst_overlap, 2e-3);
  EXPECT_NEAR(r.v_a.z(), 200.0, 1e-9);
  EXPECT_NEAR(r.v_b.z(), -200.0, 1e-9);
}
