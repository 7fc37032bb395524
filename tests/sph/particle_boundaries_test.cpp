// Loads and boundary conditions on particle faces (solver/time/particle_boundaries): a
// pressure pulse on the end of a free SPH block gives it exactly the impulse p A ∫f dt
// (momentum balance closed to round-off, energy balanced), and a fixed face does not move.
#include "sph_fixture.hpp"

#include "solver/time/simulation.hpp"

#include <gtest/gtest.h>

using namespace sphfem;

namespace {

const double dp = 1e-3;

// The top layer (z = 9.5 mm) of a 4 × 4 × 10 mm centred lattice as the face "block/zmax".
Model block_with_top_face() {
  Model m = test::lattice_block(Vec3(4e-3, 4e-3, 10e-3), dp, 1.2);
  ParticleFace top;
  for (Index i = 0; i < m.particle_count(); ++i)
    if (m.x_p[i].z() > 9e-3) {
      top.particles.push_back(i);
      top.area.push_back(dp * dp);
    }
  top.normal = Vec3::UnitZ();
  m.particle_faces["block/zmax"] = top;
  return m;
}

void run(Simulation& sim, double end) {
  while (sim.time() < end * (1 - 1e-12))
    sim.step(std::min(sim.stable_dt(), end - sim.time()));
}

} // namespace

TEST(ParticleBoundaries, PressurePulseGivesItsImpulse) {
  Case c = test::block_case(dp, 1.2);
  c.loads.push_back({"block", "zmax", 1e8, TimeFunction({{0, 0}, {2e-6, 1}, {4e-6, 0}})});
  Simulation sim(c, block_with_top_face());
  run(sim, 8e-6);
  // ∫ p dt = 1e8 Pa × 2 µs over 16 mm², pushing down; sampled once per step (≈ 50 samples
  // over the pulse), so the discrete impulse matches within 0.5%.
  const double expected = -1e8 * 2e-6 * 16e-6;
  EXPECT_NEAR(sim.momentum().z(), expected, 0.005 * std::abs(expected));
  EXPECT_LT(sim.momentum_drift(), 1e-12);
  const Energies e = sim.energies();
  EXPECT_GT(e.external_work, 0.0);
  EXPECT_LT(sim.balance_error(e), 0.02);
}

TEST(ParticleBoundaries, FixedFaceStaysPut) {
  Case c = test::block_case(dp, 1.2);
  c.bodies[0].velocity = Vec3(0, 0, 5.0); // the rest of the block runs into its fixed end
  BoundaryConditionSpec fixed;
  fixed.type = BoundaryType::Fixed;
  fixed.body = "block";
  fixed.face = "zmax";
  c.boundary_conditions.push_back(fixed);
  const Model m = block_with_top_face();
  Simulation sim(c, m);
  run(sim, 2e-6);
  const auto& p = sim.particle_system().particles();
  for (Index id : m.particle_faces.at("block/zmax").particles) {
    const Index i = sim.particle_system().index_of(id);
    EXPECT_LT((p.x_p[i] - p.x0_p[i]).norm(), 1e-15) << "particle " << id;
  }
  // The block is stopped against the fixed end: compression there.
  double top_pressure = 0;
  for (Index id : m.particle_faces.at("block/zmax").particles)
    top_pressure += p.p_p[sim.particle_system().index_of(id)];
  EXPECT_GT(top_pressure, 0.0);
}
