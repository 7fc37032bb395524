// Element erosion (METHOD.md §6 for hexahedra): a bar of a Johnson–Cook material with
// damage and `erosion: true`, fixed at one end and pulled at the other, fails; its failed
// elements are removed while their mass stays lumped at the nodes, and the energy they held
// is reported as eroded energy so that the energy balance still closes.
#include "fem_case.hpp"

#include <gtest/gtest.h>

#include <numeric>

using namespace sphfem;

namespace {

const char* bar = R"(
name: eroding_bar
time: {end: 4.0e-5, cfl: 0.6, output_interval: 1.0e-5}
materials:
  soft:
    model: johnson_cook
    density: 7850
    youngs_modulus: 200.0e9
    poisson_ratio: 0.3
    johnson_cook: {A: 2.0e8, B: 2.0e8, n: 0.5, C: 0, rate_form: power, reference_strain_rate: 1}
    damage: {D1: 0.05, D2: 0, D3: 0, D4: 0, critical_damage: 1}
    erosion: true
bodies:
  bar:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.002, 0.002, 0.02]}}
    element_size: 0.001
    material: soft
boundary_conditions:
  - {type: fixed, body: bar, face: zmin}
  - {type: velocity, body: bar, face: zmax, velocity: [~, ~, 50.0]}
)";

double nodal_mass(const Simulation& sim) {
  const auto& m = sim.nodes().m_n;
  return std::accumulate(m.begin(), m.end(), 0.0);
}

} // namespace

TEST(Erosion, FailedElementsRemovedMassKeptEnergyBalanced) {
  test::FemCase run(bar);
  const Simulation& sim = run.sim;
  const double mass0 = nodal_mass(sim);
  EXPECT_NEAR(mass0, 7850 * 0.002 * 0.002 * 0.02, 1e-12);
  run.run([] {});
  const HexElements& e = sim.elements();
  Index eroded = 0;
  for (Index k = 0; k < e.size(); ++k) {
    if (!e.eroded_e[k])
      continue;
    ++eroded;
    EXPECT_TRUE(e.point_e[k].failed);
    EXPECT_TRUE(e.S_e[k].isZero());
    for (const Vec3& f : e.f_e[k])
      EXPECT_TRUE(f.isZero()); // no force on its nodes
  }
  ASSERT_GT(eroded, 0);
  EXPECT_EQ(sim.bodies()[0].eroded_elements, eroded);
  EXPECT_EQ(nodal_mass(sim), mass0);
  EXPECT_NEAR(sim.bodies()[0].mass, mass0, 1e-15);
  const Energies energy = sim.energies();
  EXPECT_GT(energy.eroded, 0.0);
  EXPECT_LT(sim.balance_error(energy), 0.02);
}
