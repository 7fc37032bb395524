// Verification of the SPH half on its own (solver/sph): conservation, objectivity, the plane
// wave speed, energy of an oscillating block, the tensile instability and its cure, and
// density under strong compression. Particle blocks are built directly (sph_fixture.hpp).
#include "sph_fixture.hpp"

#include "solver/sph/particle_system.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

using namespace sphfem;

namespace {

// The particle half of Simulation::step with a constant step: kick, drift, update.
struct Block {
  Case spec;
  ParticleSystem system;
  double time = 0;
  long long steps = 0;

  Block(const Case& c, const Model& m) : spec(c), system(c, m, {Material::from(c.materials[0])}) {}
  Particles& p() { return system.particles(); }

  void set_velocity(const std::function<Vec3(const Vec3&)>& v) {
    for (Index i = 0; i < p().size(); ++i)
      p().v_p[i] = v(p().x_p[i]);
  }
  void step(double dt) {
    system.kick(steps == 0 ? 0.5 * dt : dt);
    system.drift(dt);
    system.update(dt);
    time += dt;
    ++steps;
  }
  Vec3 momentum() {
    Vec3 sum = Vec3::Zero();
    for (Index i = 0; i < p().size(); ++i)
      sum += p().m_p[i] * p().v_p[i];
    return sum;
  }
  Vec3 angular_momentum() {
    Vec3 sum = Vec3::Zero();
    for (Index i = 0; i < p().size(); ++i)
      sum += p().m_p[i] * p().x_p[i].cross(p().v_p[i]);
    return sum;
  }
  double kinetic() {
    double sum = 0;
    for (Index i = 0; i < p().size(); ++i)
      sum += 0.5 * p().m_p[i] * p().v_p[i].squaredNorm();
    return sum;
  }
  double internal() {
    double sum = 0;
    for (Index i = 0; i < p().size(); ++i)
      sum += p().e_p[i] - 0.5 * p().de_p[i]; // at the half step, as Simulation reports it
    return sum;
  }
  double min_pair_distance() {
    double best = std::numeric_limits<double>::infinity();
    for (Index i = 0; i < p().size(); ++i)
      for (Index j = i + 1; j < p().size(); ++j)
        best = std::min(best, (p().x_p[i] - p().x_p[j]).norm());
    return best;
  }
};

const double dp = 1e-3;

} // namespace

TEST(Sph, FreeSpinningDeformingBodyConservesMomentum) {
  // Spin plus a non-uniform stretching field: stress, artificial viscosity and stress all
  // act. Linear momentum must stay at its initial value to round-off. Angular momentum is not
  // conserved exactly: the corrected momentum equation (Bonet & Lok) conserves it, but the
  // artificial stress pair force (R_i + R_j) ∇W is not central — its drift is measured and
  // bounded.
  Block b(test::block_case(dp, 1.2), test::lattice_block(Vec3(6e-3, 8e-3, 10e-3), dp, 1.2));
  const Vec3 centre(3e-3, 4e-3, 5e-3), omega(2e4, -1e4, 3e4);
  b.set_velocity([&](const Vec3& x) -> Vec3 {
    const Vec3 r = x - centre;
    return Vec3(50, -20, 10) + omega.cross(r) + Vec3(0, 0, 5e3 * r.z() * r.x() / dp);
  });
  const Vec3 P0 = b.momentum(), L0 = b.angular_momentum();
  double mass_speed = 0;
  for (Index i = 0; i < b.p().size(); ++i)
    mass_speed += b.p().m_p[i] * b.p().v_p[i].norm();
  for (int s = 0; s < 300; ++s)
    b.step(2e-8);
  EXPECT_LT((b.momentum() - P0).norm(), 1e-13 * mass_speed);
  // Observed: 4e-5 of |L0| after 300 steps (6 µs, 0.2 rad of spin); 3e-6 without the
  // artificial stress, the same with half the step; 1.5e-3 with the plain kernel gradient in
  // the momentum equation. Asserted below 2e-4.
  const double drift = (b.angular_momentum() - L0).norm() / L0.norm();
  RecordProperty("angular_momentum_drift", std::to_string(drift));
  EXPECT_LT(drift, 2e-4);
}

TEST(Sph, RigidRotationProducesNoStress) {
  // A quarter turn in 400 steps with exact chord velocities (set before every step, as a
  // rigid body would have them): the velocity gradient on the mid-step geometry is exactly
  // skew, so no strain and no stress arise, at the surface as well as inside.
  Case c = test::block_case(dp, 1.2);
  c.sph.xsph = false;
  Block b(c, test::lattice_block(Vec3(5e-3, 5e-3, 5e-3), dp, 1.2));
  const int steps = 400;
  const double dt = 1e-8, angle = M_PI / 2;
  const Eigen::AngleAxisd turn(angle / steps, Vec3(1, 2, 3).normalized());
  const Vec3 centre(2.5e-3, 2.5e-3, 2.5e-3);
  for (int s = 0; s < steps; ++s) {
    b.set_velocity(
        [&](const Vec3& x) -> Vec3 { return Vec3((turn * (x - centre) + centre - x) / dt); });
    b.system.drift(dt);
    b.system.update(dt);
  }
  double worst = 0;
  for (Index i = 0; i < b.p().size(); ++i)
    worst = std::max({worst, b.p().S_p[i].norm(), std::abs(b.p().p_p[i])});
  // A 1e-12 strain would give 0.2 Pa: demand less than 1 Pa against 207 GPa.
  EXPECT_LT(worst, 1.0);
}

namespace {

// z where v_z along the particle column at (x, y) first falls to `level` going up from z0.
double front(Block& b, double x, double y, double z0, double level) {
  std::vector<std::pair<double, double>> column; // z, vz
  for (Index i = 0; i < b.p().size(); ++i) {
    const Vec3& p = b.p().x0_p[i];
    if (std::abs(p.x() - x) < 1e-9 && std::abs(p.y() - y) < 1e-9 && p.z() > z0)
      column.emplace_back(b.p().x_p[i].z(), b.p().v_p[i].z());
  }
  std::sort(column.begin(), column.end());
  for (std::size_t k = 1; k < column.size(); ++k)
    if (column[k - 1].second > level && column[k].second <= level)
      return column[k - 1].first + (level - column[k - 1].second) /
                                       (column[k].second - column[k - 1].second) *
                                       (column[k].first - column[k - 1].first);
  return NAN;
}

double p_wave_speed() {
  const auto c = ElasticConstants::from(test::steel());
  return std::sqrt(c.p_wave_modulus() / c.density);
}

} // namespace

TEST(Sph, PlaneWaveTravelsAtPWaveSpeed) {
  // Two halves of one block meet head on (±V/2): a compression wave runs from the middle both
  // ways at c_p, leaving the material at rest under σ_zz = −ρ c_p V/2 (1D uniaxial strain).
  // The block is 24 mm wide and the measurement ends at 1.5 µs: the release from the free
  // sides needs 12 mm / c_p = 2 µs to reach the axis behind the front, so the axis is still
  // in uniaxial strain. (Further on, a free bar carries the step at the bar speed c0.)
  Block b(test::block_case(dp, 1.2), test::lattice_block(Vec3(24e-3, 24e-3, 24e-3), dp, 1.2));
  const double V = 20.0, c_p = p_wave_speed();
  b.set_velocity([&](const Vec3& x) -> Vec3 { return Vec3(0, 0, x.z() < 12e-3 ? V / 2 : -V / 2); });
  const double dt = 2.5e-8;
  while (b.time < 0.5e-6 - 1e-12)
    b.step(dt);
  const double z1 = front(b, 11.5e-3, 11.5e-3, 12e-3, -V / 4), t1 = b.time;
  while (b.time < 1.5e-6 - 1e-12)
    b.step(dt);
  const double z2 = front(b, 11.5e-3, 11.5e-3, 12e-3, -V / 4), t2 = b.time;
  const double speed = (z2 - z1) / (t2 - t1);
  EXPECT_NEAR(speed, c_p, 0.03 * c_p) << "front at " << z1 << " and " << z2 << " m";

  // 2–4 mm behind the front on the axis: at rest under the impedance stress.
  double szz = 0, vz = 0;
  int n = 0;
  for (Index i = 0; i < b.p().size(); ++i) {
    const Vec3& x0 = b.p().x0_p[i];
    const double behind = z2 - b.p().x_p[i].z();
    if (std::abs(x0.x() - 11.5e-3) < 1e-9 && std::abs(x0.y() - 11.5e-3) < 1e-9 && behind > 2e-3 &&
        behind < 4e-3) {
      szz += b.p().S_p[i](2, 2) - b.p().p_p[i];
      vz += b.p().v_p[i].z();
      ++n;
    }
  }
  ASSERT_GT(n, 0);
  const double expected = -7830 * c_p * V / 2;
  EXPECT_NEAR(szz / n, expected, 0.05 * std::abs(expected));
  EXPECT_NEAR(vz / n, 0.0, 0.05 * V);
}

TEST(Sph, OscillatingBlockConservesEnergy) {
  // The first free–free longitudinal mode, v_z = V cos(π z / L), through about one period:
  // kinetic + internal energy (artificial-viscosity heating included) stays E0 within 1%.
  Block b(test::block_case(dp, 1.2), test::lattice_block(Vec3(6e-3, 6e-3, 12e-3), dp, 1.2));
  b.set_velocity(
      [](const Vec3& x) -> Vec3 { return Vec3(0, 0, 10.0 * std::cos(M_PI * x.z() / 12e-3)); });
  const double E0 = b.kinetic();
  double worst = 0, least_kinetic = E0;
  while (b.time < 5e-6) {
    b.step(5e-8);
    worst = std::max(worst, std::abs(b.kinetic() + b.internal() - E0) / E0);
    least_kinetic = std::min(least_kinetic, b.kinetic());
  }
  EXPECT_LT(least_kinetic, 0.2 * E0); // it really oscillates: energy goes into strain
  EXPECT_LT(worst, 0.01);
}

namespace {

// A soft cube (E = 10 MPa, c_p ≈ 130 m/s) in hydrostatic tension of order E from a dilating
// velocity field, over about four breathing periods; returns the smallest particle distance
// over the run in units of Δp. (Steel at a few GPa of tension, σ/E ~ 2%, stays stable over the
// same time: the instability needs tension comparable to the stiffness.)
double tension_min_distance(bool artificial_stress) {
  Case c = test::block_case(dp, 1.2);
  c.materials[0] = {"soft", "elastic", 1000.0, 1e7, 0.3};
  c.bodies[0].material = "soft";
  c.sph.artificial_stress = artificial_stress;
  c.sph.xsph = false;
  // A 2% random jitter of the lattice seeds the instability (a perfect lattice is symmetric).
  Model m = test::lattice_block(Vec3(8e-3, 8e-3, 8e-3), dp, 1.2);
  std::mt19937 random(42);
  std::uniform_real_distribution<double> jitter(-0.02 * dp, 0.02 * dp);
  for (Index i = 0; i < m.particle_count(); ++i) {
    m.x_p[i] += Vec3(jitter(random), jitter(random), jitter(random));
    m.rho_p[i] = 1000.0;
    m.m_p[i] = 1000.0 * dp * dp * dp;
  }
  Block b(c, m);
  const Vec3 centre(4e-3, 4e-3, 4e-3);
  b.set_velocity([&](const Vec3& x) -> Vec3 { return 1.2e4 * (x - centre); });
  double least = b.min_pair_distance();
  while (b.time < 2e-4) {
    b.step(0.5 * b.system.stable_dt());
    if (b.steps % 10 == 0)
      least = std::min(least, b.min_pair_distance());
  }
  return least / dp;
}

} // namespace

// Measured (min distance / Δp without, with artificial stress ε = 0.3): dilation rate 1.0e4/s
// 0.52, 0.65; 1.2e4/s (this test) 0.46, 0.55; 1.5e4/s 0.36, 0.43 — at the highest tension
// ε = 0.3 only delays the clumping.
TEST(Sph, ArtificialStressPreventsTensileClumping) {
  const double without = tension_min_distance(false), with = tension_min_distance(true);
  RecordProperty("min_distance_without", std::to_string(without));
  RecordProperty("min_distance_with", std::to_string(with));
  EXPECT_LT(without, 0.5); // the tensile instability pairs particles up
  EXPECT_GT(with, 0.5);    // the artificial stress keeps them apart
}

TEST(Sph, DensityStaysPositiveUnderHalfVolumeCompression) {
  // A soft block (E = 1 MPa, c ≈ 40 m/s) crushed from all sides at 100 m/s until its volume
  // has halved: the density rises to about twice ρ0 and stays positive and finite.
  Case c = test::block_case(dp, 1.2);
  c.materials[0] = {"soft", "elastic", 1000.0, 1e6, 0.3};
  c.bodies[0].material = "soft";
  Model m = test::lattice_block(Vec3(10e-3, 10e-3, 10e-3), dp, 1.2);
  for (Index i = 0; i < m.particle_count(); ++i) {
    m.rho_p[i] = 1000.0;
    m.m_p[i] = 1000.0 * dp * dp * dp;
  }
  Block b(c, m);
  const Vec3 centre(5e-3, 5e-3, 5e-3);
  b.set_velocity([&](const Vec3& x) -> Vec3 { return -100.0 * (x - centre) / 5e-3; });
  double largest = 0, smallest = 1e300;
  // Volume 1/2 when the linear size is 2^(-1/3): the surface travels 1.03 mm at 100 m/s.
  while (b.time < 10.3e-6) {
    b.step(std::min(2e-8, b.system.stable_dt()));
    for (Index i = 0; i < b.p().size(); ++i) {
      largest = std::max(largest, b.p().rho_p[i] / 1000.0);
      smallest = std::min(smallest, b.p().rho_p[i] / 1000.0);
    }
  }
  EXPECT_GT(largest, 1.5);
  EXPECT_GT(smallest, 0.0);
  EXPECT_TRUE(std::isfinite(largest));
}
