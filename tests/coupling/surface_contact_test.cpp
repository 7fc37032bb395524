// Verification of the surface contact (solver/coupling/surface_contact, docs/contact.md) against
// 1D theory and Coulomb's law, in hexahedra (FE) and particles (SPH) alike:
// - equal bars struck end on end at ±v: contact lasts 2L/c₀, the bars rebound as the same bars
//   glued into one (the discretisation's own limit, below 1D theory's v; see the test);
// - unequal bars: the shorter leaves at −v, the longer keeps v (2 L₁/L₂ − 1), and once the
//   shorter has left, the faces that move apart at the same speed ("kissing") push no more —
//   where the kernel contact keeps pushing for another contact time (its test at the end);
// - a block pressed on a plate and sliding with friction μ decelerates at μ F_n / m;
// - penetration stays below Δp/10, momentum is conserved to round-off and energy within 1%.
#include "bar_impact_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace sphfem;
using test::Bar;
using test::BarImpact;

namespace {

const double dp = 1e-3, side = 4e-3, v = 200;
const double c0 = std::sqrt(207.0e9 / 7830);

const char* name(Method m) {
  return m == Method::Fem ? "FE" : "SPH";
}

// The rebound of bars of `method`, length L, glued into one bar of length 2L whose halves start
// at ±v: at t = 2L/c₀ each half moves at −v in 1D theory, which the discretised bar misses by
// its own dispersion. The largest |v| of a half over [0.9, 1.1] × 2L/c₀: the best any contact
// between two such bars could give.
double glued_rebound(Method method, double L) {
  const char* size = method == Method::Fem ? "element_size" : "spacing";
  char yaml[512];
  std::snprintf(yaml, sizeof yaml,
                "name: glued\ntime: {end: 1.0, cfl: 0.6, output_interval: 1.0}\n"
                "materials:\n  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, "
                "poisson_ratio: 0.3}\n"
                "bodies:\n  bar: {method: %s, geometry: {box: {min: [0, 0, %.17g], max: [%.17g, "
                "%.17g, %.17g]}}, %s: %.17g, material: steel}\n",
                method == Method::Fem ? "fem" : "sph", -L, side, side, L, size, dp);
  const Case spec = read_case_text(yaml, "glued.yaml");
  Simulation sim(spec, mesh_case(spec));
  auto& nodes = const_cast<Nodes&>(sim.nodes());
  auto& p = const_cast<Particles&>(sim.particle_system().particles());
  const auto half = [](double z) { return z < -1e-9 ? 1.0 : z > 1e-9 ? 0.0 : 0.5; }; // lower
  for (Index i = 0; i < nodes.size(); ++i)
    nodes.v_n[i] = Vec3(0, 0,
                        half(nodes.x_n[i].z()) == 1   ? v
                        : half(nodes.x_n[i].z()) == 0 ? -v
                                                      : 0);
  for (Index i = 0; i < p.size(); ++i)
    p.v_p[i] = Vec3(0, 0, p.x_p[i].z() < 0 ? v : -v);
  const double T = 2 * L / c0;
  double best = 0;
  while (sim.time() < 1.1 * T) {
    sim.step(sim.stable_dt());
    if (sim.time() < 0.9 * T)
      continue;
    double m = 0, mv = 0;
    for (Index i = 0; i < nodes.size(); ++i) {
      const double w = half(nodes.x0_n[i].z()) * nodes.m_n[i];
      m += w;
      mv += w * nodes.v_n[i].z();
    }
    for (Index i = 0; i < p.size(); ++i)
      if (p.x0_p[i].z() < 0) {
        m += p.m_p[i];
        mv += p.m_p[i] * p.v_p[i].z();
      }
    best = std::max(best, -mv / m);
  }
  return best;
}

void expect_kept(const BarImpact& r, const std::string& what) {
  SCOPED_TRACE(what);
  // The surfaces' worst overlap anywhere on the struck faces, at any time.
  EXPECT_LT(r.worst_overlap, 0.1 * dp);
  // Equal and opposite pair forces: round-off only (≈ 1e-16 measured).
  EXPECT_LT(r.momentum_error, 1e-12);
  EXPECT_LT(r.balance_error, 0.01);
}

} // namespace

// Contact time within 3% of 2L/c₀ (force above 1% of its peak); rebound within 1% of the glued
// bars. Measured (section 4 × 4 mm, Δp 1 mm, L 50 mm; c₀ = 5142 m/s, 2L/c₀ = 19.45 µs): contact
// 0.995, 0.986, 0.974 × 2L/c₀ (FE–FE, SPH–FE, SPH–SPH); rebound 191.9, 188.3, 183.4 m/s against
// glued FE 191.0 and SPH 184.0 m/s. 1D theory's 200 m/s is out of reach of the discretised bar
// itself: glued, it reaches 193.9 m/s at 100 elements along its half and 195.6 at 200 (FE), so
// the bars' own dispersion, not the contact, sets the 4–8% below theory.
TEST(SurfaceContact, EqualBarsMeetForTwoTransitTimesAndReboundAsGluedBars) {
  const double L = 0.05, T = 2 * L / c0;
  const double fe = glued_rebound(Method::Fem, L), sph = glued_rebound(Method::Sph, L);
  for (const auto& [a, b] :
       {std::pair{Method::Fem, Method::Fem}, std::pair{Method::Sph, Method::Fem},
        std::pair{Method::Sph, Method::Sph}}) {
    const std::string pair = std::string(name(a)) + "–" + name(b);
    const BarImpact r = test::impact_bars({a, L}, {b, L}, side, dp, v, 1.5 * T, "model: surface");
    EXPECT_NEAR(r.last_force - r.first_force, T, 0.03 * T) << pair;
    const double glued = 0.5 * ((a == Method::Fem ? fe : sph) + (b == Method::Fem ? fe : sph));
    EXPECT_NEAR(-r.v_a.z(), glued, 0.01 * glued) << pair;
    EXPECT_NEAR(r.v_b.z(), glued, 0.01 * glued) << pair;
    expect_kept(r, pair);
    RecordProperty(pair + "_rebound", std::to_string(r.v_b.z()));
  }
}

// 1D theory for bars of lengths L₁ < L₂ meeting at ±v: the shorter is stress-free at −v after
// 2L₁/c₀, when the longer's struck end also moves at −v, so the faces part without force; the
// longer then keeps the momentum left, v (2 L₁/L₂ − 1) — 0 for L₂ = 2L₁. Measured: shorter
// −203.7, −201.0, −199.7 m/s, longer 1.85, 0.49, −0.16 m/s (FE–FE, SPH–FE, SPH–SPH).
TEST(SurfaceContact, UnequalBarsPartAsOneDTheorySaysAndKissingFacesCarryNoForce) {
  const double L1 = 0.05, L2 = 0.1, T1 = 2 * L1 / c0, T2 = 2 * L2 / c0;
  for (const auto& [a, b] :
       {std::pair{Method::Fem, Method::Fem}, std::pair{Method::Sph, Method::Fem},
        std::pair{Method::Sph, Method::Sph}}) {
    const std::string pair = std::string(name(a)) + "–" + name(b);
    const BarImpact r =
        test::impact_bars({a, L1}, {b, L2}, side, dp, v, 1.2 * T2, "model: surface", 1.1 * T1);
    EXPECT_NEAR(r.v_a.z(), -v, 0.02 * v) << pair;
    EXPECT_NEAR(r.v_b.z(), v * (2 * L1 / L2 - 1), 0.02 * v) << pair;
    // After the shorter bar has left (1D: T1 after the faces met; the force ends by 1.06 T1).
    EXPECT_LT(r.late_force, 0.01 * r.peak_force) << pair;
    expect_kept(r, pair);
  }
}

// The paper's kernel contact on the same bars (its known limit, kept as `model: kernel`): it
// acts within 2h_ij, so it goes on pushing the parting faces — the shorter bar leaves 8% faster
// than −v and the force after 1.1 × 2L₁/c₀ is a third of its peak or more (measured: shorter
// −221.6, −218.2, −216.4 m/s; late force 0.06–0.33 of the peak at this section), the force
// beginning 2h/v early and ending late.
TEST(SurfaceContact, KernelContactKeepsPushingKissingFaces) {
  const double L1 = 0.05, L2 = 0.1, T1 = 2 * L1 / c0, T2 = 2 * L2 / c0;
  // Start beyond the kernel's reach 2h = 2.4 Δp, or the bars begin inside it.
  const BarImpact r = test::impact_bars({Method::Sph, L1}, {Method::Fem, L2}, side, dp, v, 1.2 * T2,
                                        "model: kernel, penalty: 1e11", 1.1 * T1, 0.6, "", 3 * dp);
  EXPECT_LT(r.v_a.z(), -1.05 * v);
  EXPECT_GT(r.late_force, 0.05 * r.peak_force);
}
