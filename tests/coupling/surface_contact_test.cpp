// Verification of the surface contact (solver/coupling/surface_contact, docs/contact.md) against
// 1D theory and Coulomb's law, in hexahedra (FE) and particles (SPH) alike:
// - equal bars struck end on end at ±v: contact lasts 2L/c₀, the bars rebound as the same bars
//   glued into one (the discretisation's own limit, below 1D theory's v; see the test);
// - unequal bars: the shorter leaves at −v, the longer keeps v (2 L₁/L₂ − 1), and once the
//   shorter has left, the faces that move apart at the same speed ("kissing") push no more —
//   where the kernel contact keeps pushing for another contact time (its test at the end);
// - a block pressed on a plate and sliding with friction μ decelerates at μ F_n / m;
// - penetration stays below Δp/10, momentum is conserved to round-off and energy within 1%;
// - eroded elements expose the faces behind them; a restart continues bit for bit;
// - a particle the contact pushes drifts with its velocity (no XSPH correction), which closes
//   the energy balance of an oblique strike on particles.
#include "bar_impact_fixture.hpp"
#include "solver/core/error.hpp"
#include "solver/io/checkpoint.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

using namespace sphfem;
using test::Bar;
using test::BarImpact;
namespace fs = std::filesystem;

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
  ::testing::Test::RecordProperty(what + "_overlap_per_dp", std::to_string(r.worst_overlap / dp));
  ::testing::Test::RecordProperty(what + "_balance", std::to_string(r.balance_error));
}

} // namespace

// Contact time within 3% of 2L/c₀ (force above 1% of its peak); rebound within 1% of the glued
// bars. Measured (section 4 × 4 mm, Δp 1 mm, L 50 mm; c₀ = 5142 m/s, 2L/c₀ = 19.45 µs): contact
// 0.994, 0.986, 0.975 × 2L/c₀ (FE–FE, SPH–FE, SPH–SPH); rebound 191.9, 188.4, 183.6 m/s against
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
    RecordProperty(pair + "_contact_per_2L_c0", std::to_string((r.last_force - r.first_force) / T));
  }
}

// 1D theory for bars of lengths L₁ < L₂ meeting at ±v: the shorter is stress-free at −v after
// 2L₁/c₀, when the longer's struck end also moves at −v, so the faces part without force; the
// longer then keeps the momentum left, v (2 L₁/L₂ − 1) — 0 for L₂ = 2L₁. Measured: shorter
// −203.7, −201.1, −200.0 m/s, longer 1.84, 0.55, −0.02 m/s (FE–FE, SPH–FE, SPH–SPH).
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
    RecordProperty(pair + "_shorter", std::to_string(r.v_a.z()));
    RecordProperty(pair + "_longer", std::to_string(r.v_b.z()));
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

namespace {

struct Slide {
  double deceleration = 0; // least-squares slope of the block's −v_x over the window, m/s²
  double expected = 0;     // μ F_n / m with F_n the pressure's force, m/s²
  double lowest_speed = 0; // m/s, at the window's end: still sliding
  double worst_overlap = 0;
  double balance_error = 0, momentum_drift = 0, friction_energy = 0;
};

// A 5 × 5 × 8 mm steel block (hexahedra or particles, Δp 1 mm; tall enough for the particles'
// pressure load to find its surface weights) on a 2 mm plate fixed at its base, sliding at 10 m/s
// while a pressure, ramped up over 10 µs, presses its top; friction μ.
Slide slide(Method block, double mu) {
  const double P = 5.0e7, area = 25e-6, mass = 7830 * 200e-9;
  const std::string size = block == Method::Fem ? "element_size" : "spacing";
  const std::string yaml =
      std::string(R"(name: slide
time: {end: 3.4e-5, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  plate: {method: fem, geometry: {box: {min: [0, 0, -0.002], max: [0.012, 0.01, 0]}}, element_size: 0.001, material: steel}
  block: {method: )") +
      (block == Method::Fem ? "fem" : "sph") +
      R"(, geometry: {box: {min: [0.002, 0.0025, 0], max: [0.007, 0.0075, 0.008]}}, )" + size +
      R"(: 0.001, material: steel, velocity: [10, 0, 0]}
boundary_conditions:
  - {type: fixed, body: plate, face: zmin}
loads:
  - {type: pressure, body: block, face: zmax, pressure: 5.0e7, function: [[0, 0], [1.0e-5, 1], [1, 1]]}
)";
  char contact[128];
  std::snprintf(contact, sizeof contact, "contact:\n  - {bodies: [block, plate], friction: %g}\n",
                mu);
  test::Coupled c(yaml + contact, {}, read_case_text(yaml + contact, "slide.yaml").contacts);
  Simulation sim(c.spec, c.model);
  Slide out;
  out.expected = mu * P * area / mass;
  // Least squares of v(t) over t ∈ [14, 34] µs, when the load has settled.
  double n = 0, st = 0, sv = 0, stt = 0, stv = 0;
  const auto& p = sim.particle_system().particles();
  const auto& nodes = sim.nodes();
  while (sim.time() < c.spec.time.end) {
    sim.step(std::min(sim.stable_dt(), c.spec.time.end - sim.time()));
    double bottom = 1;
    for (Index i = 0; i < p.size(); ++i)
      bottom = std::min(bottom, p.x_p[i].z() - 0.5e-3);
    for (Index i = 0; i < nodes.size(); ++i)
      if (nodes.body_n[i] == 1)
        bottom = std::min(bottom, nodes.x_n[i].z());
    double top = -1; // the plate's top under the block
    for (Index i = 0; i < nodes.size(); ++i)
      if (nodes.body_n[i] == 0 && nodes.x0_n[i].x() > 0.0015 && nodes.x0_n[i].x() < 0.0085)
        top = std::max(top, nodes.x_n[i].z());
    out.worst_overlap = std::max(out.worst_overlap, top - bottom);
    out.balance_error = std::max(out.balance_error, sim.balance_error(sim.energies()));
    const double t = sim.time(), vx = sim.bodies()[1].com_velocity.x();
    if (t >= 14e-6) {
      n += 1, st += t, sv += vx, stt += t * t, stv += t * vx;
      out.lowest_speed = vx;
    }
  }
  out.deceleration = -(n * stv - st * sv) / (n * stt - st * st);
  out.momentum_drift = sim.momentum_drift();
  out.friction_energy = sim.energies().friction;
  return out;
}

} // namespace

// Coulomb: a block pressed with F_n and sliding decelerates at μ F_n / m (no gravity here, the
// pressure is the only normal load): 2.39e5 m/s² for μ = 0.3. Measured: FE 2.414e5 (+0.8%),
// SPH 2.408e5 (+0.6%), the normal force still ringing a little after its 10 µs ramp.
TEST(SurfaceContact, FrictionDeceleratesASlidingBlockAtMuTimesTheNormalForce) {
  for (const Method block : {Method::Fem, Method::Sph}) {
    SCOPED_TRACE(name(block));
    const Slide r = slide(block, 0.3);
    EXPECT_NEAR(r.deceleration, r.expected, 0.02 * r.expected);
    EXPECT_GT(r.lowest_speed, 1.0); // sliding throughout: Coulomb's kinetic regime
    EXPECT_GT(r.friction_energy, 0.0);
    EXPECT_LT(r.worst_overlap, 0.1e-3);
    EXPECT_LT(r.balance_error, 0.01);
    EXPECT_LT(r.momentum_drift, 1e-10);
    RecordProperty(std::string(name(block)) + "_deceleration", std::to_string(r.deceleration));
  }
  // Frictionless, the block keeps its speed (the load is normal to its path).
  const Slide free = slide(Method::Fem, 0.0);
  EXPECT_NEAR(free.deceleration, 0.0, 0.002 * 0.3 * 5.0e7 * 25e-6 / (7830 * 200e-9));
  EXPECT_EQ(free.friction_energy, 0.0);
}

// An eroded surface exposes the material behind it: a block whose top layer of elements has
// eroded is struck by another; the faces under the eroded layer become surface and stop it there,
// not at the eroded layer's old top (the mesher gave every node of the eroding body a background
// particle, so the exposed nodes can meet the striker).
TEST(SurfaceContact, ErodedElementsExposeTheFacesBehindThem) {
  const std::string yaml = R"(name: exposed
time: {end: 9.0e-6, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
  eroding:
    model: johnson_cook
    density: 7830
    youngs_modulus: 207.0e9
    poisson_ratio: 0.3
    johnson_cook: {A: 2.0e9, B: 0, n: 1, C: 0, rate_form: power, reference_strain_rate: 1}
    damage: {D1: 10, D2: 0, D3: 0, D4: 0, critical_damage: 1}
    erosion: true
bodies:
  target: {method: fem, geometry: {box: {min: [0, 0, 0], max: [0.003, 0.003, 0.003]}}, element_size: 0.001, material: eroding}
  striker: {method: fem, geometry: {box: {min: [0.0005, 0.0005, 0.00325], max: [0.0025, 0.0025, 0.00525]}}, element_size: 0.001, material: steel, velocity: [0, 0, -200]}
contact:
  - {bodies: [target, striker]}
)";
  const Case spec = read_case_text(yaml, "exposed.yaml");
  const Model model = mesh_case(spec);
  EXPECT_EQ(model.background_nodes.size(),
            64u + 27u - 1u); // every target node; the striker's surface
  Simulation sim(spec, model);
  auto& elements = const_cast<HexElements&>(sim.elements());
  Index eroded = 0;
  for (Index e = 0; e < elements.size(); ++e) {
    double z = 0;
    for (Index n : elements.nodes_e[e])
      z += sim.nodes().x_n[n].z() / 8;
    if (elements.body_e[e] == 0 && z > 0.002) {
      elements.eroded_e[e] = 1;
      ++eroded;
    }
  }
  ASSERT_EQ(eroded, 9);
  double lowest = 1;
  while (sim.time() < spec.time.end) {
    sim.step(std::min(sim.stable_dt(), spec.time.end - sim.time()));
    for (Index i = 0; i < sim.nodes().size(); ++i)
      if (sim.nodes().body_n[i] == 1)
        lowest = std::min(lowest, sim.nodes().x_n[i].z());
  }
  EXPECT_LT(lowest, 0.0025);         // through the eroded layer (its top was z = 3 mm)
  EXPECT_GT(lowest, 0.002 - 0.1e-3); // stopped at the exposed faces, z = 2 mm
  EXPECT_GT(sim.bodies()[1].com_velocity.z(), 0.0); // and rebounding
}

// A surface that changes under its slaves — here the plate lifted 0.3 mm into the striker between
// two steps, as an eroded element, a face turning into a node's view or a pinched corner changes
// it — adds an overlap that no motion made: the contact ignores it (coupling/ignored_overlap.hpp)
// and creates no energy from it, then resists every motion further in as before: the striker
// stops and rebounds, no deeper than Δp/10 beyond the overlap it ignores.
TEST(SurfaceContact, ASurfaceThatChangesUnderItsSlavesCreatesNoEnergy) {
  const std::string yaml = R"(name: lifted
time: {end: 6.0e-6, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  plate: {method: fem, geometry: {box: {min: [0, 0, -0.002], max: [0.008, 0.006, 0]}}, element_size: 0.001, material: steel}
  striker: {method: fem, geometry: {box: {min: [0.002, 0.001, 0.00005], max: [0.006, 0.005, 0.00405]}}, element_size: 0.001, material: steel, velocity: [0, 0, -50]}
boundary_conditions:
  - {type: fixed, body: plate, face: zmin}
contact:
  - {bodies: [plate, striker]}
)";
  const Case spec = read_case_text(yaml, "lifted.yaml");
  Simulation sim(spec, mesh_case(spec));
  const double lift = 0.3e-3;
  auto& nodes = const_cast<Nodes&>(sim.nodes());
  double before = 0, after = 0, lowest = 1;
  bool lifted = false;
  while (sim.time() < spec.time.end) {
    sim.step(std::min(sim.stable_dt(), spec.time.end - sim.time()));
    if (lifted && after == 0)
      after = sim.energies().contact;
    if (!lifted && sim.time() > 1.5e-6) { // in mid-contact: the striker is slowing down
      before = sim.energies().contact;
      ASSERT_GT(before, 0.0);
      for (Index i = 0; i < nodes.size(); ++i)
        if (nodes.body_n[i] == 0)
          nodes.x_n[i].z() += lift;
      lifted = true;
    }
    if (lifted)
      for (Index i = 0; i < nodes.size(); ++i)
        if (nodes.body_n[i] == 1)
          lowest = std::min(lowest, nodes.x_n[i].z());
  }
  // One step's change of the stored energy (before: 0.02 J), not ½ k (0.3 mm)² = 12 J on each
  // of the striker's bottom nodes and the plate's nodes under it: 420 J were created without
  // the rule. Once the striker has left, the balance is as good as without the lift (0.2%).
  EXPECT_LT(after, 2 * before) << "before " << before << " J";
  EXPECT_LT(sim.balance_error(sim.energies()), 0.01);
  EXPECT_GT(lowest, -0.1 * dp); // the plate's top was z = 0 before it was lifted
  EXPECT_GT(sim.bodies()[1].com_velocity.z(), 0.0); // and rebounding
}

// A run continued from a checkpoint taken in mid-contact goes on bit for bit: the candidates and
// faces are collected again from the restored state, and friction's power and the contact energy
// come back with it. A particle block sliding with friction on an FE plate, through a rebuild of
// the neighbour lists.
TEST(SurfaceContact, RestartContinuesBitForBit) {
  const std::string yaml = R"(name: restart
time: {end: 1.0, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  plate: {method: fem, geometry: {box: {min: [0, 0, -0.002], max: [0.008, 0.006, 0]}}, element_size: 0.001, material: steel}
  block: {method: sph, geometry: {box: {min: [0.001, 0.001, 0], max: [0.005, 0.005, 0.004]}}, spacing: 0.001, material: steel, velocity: [40, 0, -20]}
boundary_conditions:
  - {type: fixed, body: plate, face: zmin}
contact:
  - {bodies: [block, plate], friction: 0.3}
)";
  const Case spec = read_case_text(yaml, "restart.yaml");
  const Model model = mesh_case(spec);
  const auto steps = [](Simulation& sim, int n) {
    for (int k = 0; k < n; ++k)
      sim.step(sim.stable_dt());
  };
  Simulation first(spec, model);
  steps(first, 150);
  ASSERT_GT(first.energies().friction, 0.0); // in contact, sliding
  const fs::path file = fs::temp_directory_path() / "sphfem_surface_contact_restart.h5";
  write_checkpoint(file, CheckpointMeta{}, [&](StateArchive& a) { first.persist(a); });
  Simulation second(spec, model);
  read_checkpoint(file, [&](StateArchive& a) { second.persist(a); });
  fs::remove(file);
  steps(first, 150);
  steps(second, 150);
  const auto& p = first.particle_system().particles();
  const auto& q = second.particle_system().particles();
  ASSERT_EQ(p.total(), q.total());
  for (Index i = 0; i < p.total(); ++i) {
    EXPECT_EQ(p.x_p[i], q.x_p[i]) << "particle " << i;
    EXPECT_EQ(p.v_p[i], q.v_p[i]) << "particle " << i;
  }
  for (Index i = 0; i < first.nodes().size(); ++i)
    EXPECT_EQ(first.nodes().v_n[i], second.nodes().v_n[i]) << "node " << i;
  EXPECT_EQ(first.energies().friction, second.energies().friction);
  EXPECT_EQ(first.energies().contact, second.energies().contact);
  EXPECT_GT(first.particle_system().rebuilds(), 1);
}

// The contact's forces do work on the particles' velocities v, so a particle the contact pushes
// must move with v, not with v plus its XSPH correction (the mean velocity of its neighbours):
// else its spring's overlap changes by a motion no force did work on. A block of particles
// struck obliquely by a hexahedral striker: after each step, a particle pressed by the contact
// drifts in the next step with exactly its velocity, while particles elsewhere keep their
// XSPH correction; 10 µs after the impact, when the striker has rebounded, the energy balance
// closes to 0.08% (1.73% when pressed particles kept their correction; 92 J created by 100 µs in
// the oblique Børvik shot, docs/contact.md).
TEST(SurfaceContact, PressedParticlesDriftWithTheirVelocity) {
  const std::string yaml = R"(name: pressed
time: {end: 1.0, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  plate: {method: sph, geometry: {box: {min: [0, 0, -0.004], max: [0.012, 0.012, 0]}}, spacing: 0.001, material: steel}
  striker: {method: fem, geometry: {box: {min: [0.004, 0.004, 0.0001], max: [0.008, 0.008, 0.0041]}}, element_size: 0.001, material: steel, velocity: [150, 0, -150]}
contact:
  - {bodies: [plate, striker]}
)";
  const Case spec = read_case_text(yaml, "pressed.yaml");
  Simulation sim(spec, mesh_case(spec));
  const auto& p = sim.particle_system().particles();
  int pressed_checked = 0, free_with_xsph = 0;
  while (sim.time() < 1.0e-5) {
    std::vector<Index> pressed; // by model id
    for (Index i = 0; i < p.size(); ++i)
      if (p.fc_p[i] != Vec3::Zero())
        pressed.push_back(p.id_p[i]);
    sim.step(sim.stable_dt());
    for (const Index id : pressed) {
      const Index i = sim.particle_system().index_of(id);
      EXPECT_EQ(p.u_p[i], p.v_p[i]) << "pressed particle " << id << " at step " << sim.steps();
      ++pressed_checked;
    }
    for (Index i = 0; i < p.size(); ++i)
      if (p.fc_p[i] == Vec3::Zero() && p.u_p[i] != p.v_p[i])
        ++free_with_xsph;
  }
  EXPECT_GT(pressed_checked, 100);
  EXPECT_GT(free_with_xsph, 0);
  EXPECT_GT(sim.bodies()[1].com_velocity.z(), 0.0); // the striker has rebounded
  EXPECT_LT(sim.balance_error(sim.energies()), 0.005);
}

// Candidates come through the faces' corner nodes: an h too small to reach half a face's
// diagonal is refused, naming the body and the key.
TEST(SurfaceContact, TooSmallAReachIsAnError) {
  const std::string yaml = R"(name: reach
time: {end: 1.0e-6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  a: {method: fem, geometry: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.004]}}, element_size: 0.001, h_factor: 0.3, material: steel}
  b: {method: fem, geometry: {box: {min: [0, 0, 0.005], max: [0.004, 0.004, 0.009]}}, element_size: 0.001, h_factor: 0.3, material: steel}
contact:
  - {bodies: [a, b]}
)";
  const Case spec = read_case_text(yaml, "reach.yaml");
  try {
    Simulation sim(spec, mesh_case(spec));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("surface contact of 'a'"), std::string::npos) << what;
    EXPECT_NE(what.find("h_factor"), std::string::npos) << what;
  }
}
