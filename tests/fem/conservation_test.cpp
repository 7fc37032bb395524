// Verification: a free elastic block struck by two short pressure pulses (end and side) then
// left to vibrate, tumble and fly. Momentum must equal the applied impulse to round-off, and
// energy must balance: E_kin + E_int + E_hg − W_ext within 0.5% of the energy put in.
#include "fem_case.hpp"

#include <gtest/gtest.h>

using namespace sphfem;

namespace {

const char* block_case = R"(
name: free_block
time: {end: 6.0e-5, cfl: 0.9, output_interval: 6.0e-5}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  block:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.01, 0.01, 0.02]}}
    element_size: 0.002
    material: steel
    velocity: [1.0, 0, 0]
loads:
  - {type: pressure, body: block, face: zmin, pressure: 2.0e8, function: [[0, 0], [4.0e-6, 1], [8.0e-6, 0]]}
  - {type: pressure, body: block, face: xmax, pressure: 1.0e8, function: [[0, 0], [2.0e-6, 1], [4.0e-6, 0]]}
)";

} // namespace

TEST(FreeBlock, ConservesMomentumAndEnergy) {
  test::FemCase run(block_case);
  double max_drift = 0;
  run.run([&] { max_drift = std::max(max_drift, run.sim.momentum_drift()); });
  EXPECT_LT(max_drift, 1e-12);

  const Energies e = run.sim.energies();
  EXPECT_GT(e.internal, 0.01 * e.external_work); // the block really deforms
  EXPECT_LT(run.sim.balance_error(e), 0.005)
      << "kinetic " << e.kinetic << " internal " << e.internal << " work " << e.external_work;

  // Independent check of the impulse: ∫p dt over the triangle pulse is p·4 µs on 1 cm × 1 cm
  // (follower load: the face stretches by Poisson, and the load is sampled once per step, so
  // allow 1%); m v0 along x minus the side pulse p·2 µs on 1 cm × 2 cm.
  const double mass = 7830 * 0.01 * 0.01 * 0.02;
  const Vec3 p = run.sim.momentum();
  EXPECT_NEAR(p.z(), 2.0e8 * 4e-6 * 1e-4, 0.01 * 2.0e8 * 4e-6 * 1e-4);
  EXPECT_NEAR(p.x(), mass * 1.0 - 1.0e8 * 2e-6 * 2e-4, 0.01 * 1.0e8 * 2e-6 * 2e-4);
}
