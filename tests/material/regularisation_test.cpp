// The fracture strain's regularisation in a run (ductile_damage.hpp, `regularisation_length`):
// the solver gives each point its band width — 2 h0 for a particle, ∛V0 for a hexahedron — so
// p_f becomes p_f L / width. With D2 = D4 = D5 = 0, p_f = D1 whatever the stress and rate, and
// with p_d = 0 and D_C = 1 the damage of a point that has not failed is exactly p / (D1 L / w):
// a plate of particles struck against a symmetry plane and a bar of hexahedra pulled apart
// must show that ratio at every point that has flowed.
#include "tests/fem/fem_case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace sphfem;

namespace {

constexpr double D1 = 0.05;

std::string material(const std::string& regularisation) {
  return R"(
materials:
  soft:
    model: johnson_cook
    density: 7850
    youngs_modulus: 200.0e9
    poisson_ratio: 0.3
    johnson_cook: {A: 2.0e8, B: 2.0e8, n: 0.5, C: 0, rate_form: power, reference_strain_rate: 1}
    damage: {D1: 0.05, D2: 0, D3: 0, D4: 0, critical_damage: 1)" +
         regularisation + "}\n";
}

std::string block(const std::string& regularisation) {
  return "name: struck_block\ntime: {end: 2.0e-6, cfl: 0.6, output_interval: 1.0}\n" +
         material(regularisation) + R"(bodies:
  block:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.004]}}
    spacing: 0.001
    material: soft
    velocity: [-300, 0, 0]
boundary_conditions:
  - {type: symmetry, body: block, face: xmin}
)";
}

std::string bar(const std::string& regularisation) {
  return "name: pulled_bar\ntime: {end: 2.0e-5, cfl: 0.6, output_interval: 1.0}\n" +
         material(regularisation) + R"(bodies:
  bar:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.002, 0.002, 0.02]}}
    element_size: 0.001
    material: soft
boundary_conditions:
  - {type: fixed, body: bar, face: zmin}
  - {type: velocity, body: bar, face: zmax, velocity: [~, ~, 50.0]}
)";
}

// Checks damage = p / p_f(w) at every point that flowed and has not failed; returns how many.
int expect_scaled_damage(const MaterialPoint& point, double fracture_strain) {
  if (point.failed || !(point.plastic_strain > 0))
    return 0;
  EXPECT_NEAR(point.damage, point.plastic_strain / fracture_strain, 1e-12 * point.damage)
      << "p_f " << fracture_strain;
  return 1;
}

TEST(Regularisation, ParticlesScaleByTwiceTheirInitialSmoothingLength) {
  for (const double L : {0.0, 3.6e-3, 9.6e-3}) {
    test::FemCase run(block(L > 0 ? ", regularisation_length: " + std::to_string(L) : ""));
    run.run([] {});
    const Particles& p = run.sim.particle_system().particles();
    int flowed = 0;
    for (Index i = 0; i < p.size(); ++i) {
      const double width = 2.0 * p.h0_p[i]; // 2.4 mm: h = 1.2 × the 1 mm spacing
      flowed += expect_scaled_damage(p.point_p[i], L > 0 ? D1 * L / width : D1);
    }
    EXPECT_GT(flowed, 0) << "L " << L;
  }
}

TEST(Regularisation, HexahedraScaleByTheirInitialSize) {
  for (const double L : {0.0, 0.5e-3, 2.0e-3}) {
    test::FemCase run(bar(L > 0 ? ", regularisation_length: " + std::to_string(L) : ""));
    run.run([] {});
    const HexElements& e = run.sim.elements();
    int flowed = 0;
    for (Index k = 0; k < e.size(); ++k)
      flowed += expect_scaled_damage(e.point_e[k], L > 0 ? D1 * L / std::cbrt(e.V0_e[k]) : D1);
    EXPECT_GT(flowed, 0) << "L " << L;
  }
}

} // namespace
