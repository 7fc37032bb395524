// Verification: a uniaxial-strain plane wave in a laterally constrained column (symmetry
// planes on the four sides), driven by a prescribed velocity V0 at one end. 1D elastic wave
// theory: the front travels at c_p = √((K + 4G/3)/ρ) and carries σ_zz = −ρ c_p V0.
#include "fem_case.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sphfem;

namespace {

const char* column_case = R"(
name: plane_wave
time: {end: 1.5e-5, cfl: 0.9, output_interval: 1.5e-5}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  column:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.001, 0.001, 0.1]}}
    element_size: 0.0005
    material: steel
boundary_conditions:
  - {type: symmetry, body: column, face: xmin}
  - {type: symmetry, body: column, face: xmax}
  - {type: symmetry, body: column, face: ymin}
  - {type: symmetry, body: column, face: ymax}
  - {type: velocity, body: column, face: zmin, velocity: [~, ~, 10.0], function: [[0, 0], [2.0e-7, 1]]}
probes:
  - {name: near, body: column, point: [0.0005, 0.0005, 0.025]}
  - {name: far, body: column, point: [0.0005, 0.0005, 0.075]}
)";

// Time at which a sampled signal first reaches `level`, linearly interpolated.
double crossing(const std::vector<double>& t, const std::vector<double>& y, double level) {
  for (std::size_t i = 1; i < y.size(); ++i)
    if (y[i - 1] < level && y[i] >= level)
      return t[i - 1] + (level - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1]);
  return NAN;
}

} // namespace

TEST(PlaneWave, TravelsAtPWaveSpeedWithImpedanceStress) {
  test::FemCase run(column_case);
  const double rho = 7830, E = 207e9, nu = 0.3, V0 = 10.0;
  const double K = E / (3 * (1 - 2 * nu)), G = E / (2 * (1 + nu));
  const double c_p = std::sqrt((K + 4 * G / 3) / rho); // ≈ 6.0 km/s

  std::vector<double> t, v_near, v_far, s_near;
  std::vector<double> row;
  run.run([&] {
    row.clear();
    probe_values(run.probes, run.sim, row);
    t.push_back(run.sim.time());
    v_near.push_back(row[5]); // near.vz
    s_near.push_back(row[8]); // near.szz
    v_far.push_back(row[14 + 5]);
  });
  ASSERT_NEAR(run.probes[0].position.z(), 0.025, 1e-12);
  ASSERT_NEAR(run.probes[1].position.z(), 0.075, 1e-12);

  // Front speed from the half-amplitude crossings at the two probes (the ramp cancels).
  const double t_near = crossing(t, v_near, 0.5 * V0), t_far = crossing(t, v_far, 0.5 * V0);
  const double speed = 0.05 / (t_far - t_near);
  EXPECT_NEAR(speed, c_p, 0.02 * c_p) << "measured " << speed << " m/s, theory " << c_p;

  // Behind the front: particle velocity V0 and σ_zz = −ρ c_p V0 (mean over the plateau).
  double s_mean = 0, v_mean = 0;
  int n = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] > t_near + 2e-6) {
      s_mean += s_near[i];
      v_mean += v_near[i];
      ++n;
    }
  ASSERT_GT(n, 10);
  s_mean /= n;
  v_mean /= n;
  EXPECT_NEAR(v_mean, V0, 0.03 * V0);
  EXPECT_NEAR(s_mean, -rho * c_p * V0, 0.03 * rho * c_p * V0)
      << "σ_zz " << s_mean << " Pa, ρ c_p V0 " << rho * c_p * V0 << " Pa";
}
