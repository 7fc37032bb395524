// Symmetry planes of particles (solver/sph/mirror_particles): a half block with a symmetry
// plane moves exactly as the matching half of the whole block, and in a column held to
// uniaxial strain by four planes a pulse travels at c_p; the planes' push enters the momentum
// balance as an external reaction; the images' rows are stored without the vectors' doubling.
#include "sph_fixture.hpp"

#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/sph/particle_system.hpp"
#include "solver/time/simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sphfem;

namespace {

const double dp = 1e-3;

// A steel block [0, size] on a centred lattice; symmetry on the listed faces.
struct Block {
  Case spec;
  ParticleSystem system;

  Block(const Vec3& size, const std::vector<std::string>& symmetric, double alpha = 1.0)
      : spec(make_case(size, symmetric, alpha)),
        system(spec, test::lattice_block(size, dp, 1.2), {Material::from(spec.materials[0])}) {}

  static Case make_case(const Vec3& size, const std::vector<std::string>& symmetric, double alpha) {
    Case c = test::block_case(dp, 1.2);
    c.sph.alpha = alpha;
    c.sph.beta = 2 * alpha;
    c.bodies[0].geometry.box = {Vec3::Zero(), size};
    for (const std::string& face : symmetric) {
      BoundaryConditionSpec bc;
      bc.type = BoundaryType::Symmetry;
      bc.body = "block";
      bc.face = face;
      c.boundary_conditions.push_back(bc);
    }
    return c;
  }
  Particles& p() { return system.particles(); }
  long long steps_taken = 0;
  void run(int steps, double dt) {
    for (int s = 0; s < steps; ++s, ++steps_taken) {
      system.kick(steps_taken == 0 ? 0.5 * dt : dt);
      system.drift(dt);
      system.update(dt);
    }
  }
};

} // namespace

TEST(MirrorParticles, HalfBlockMovesAsHalfTheWhole) {
  // The whole block spans x 0–8 mm; the half 0–4 mm with a symmetry plane at x = 4 mm. A
  // velocity field symmetric about that plane (vx odd, vy and vz even in x − 4 mm) keeps the
  // whole block's motion symmetric, so each particle of the half must follow its twin.
  const auto field = [](const Vec3& x) -> Vec3 {
    const double s = x.x() - 4e-3;
    return Vec3(3e4 * s, 20.0 * std::cos(800 * s), 4e4 * (x.z() - 3e-3) + 2e7 * s * s);
  };
  Block whole(Vec3(8e-3, 4e-3, 6e-3), {});
  Block half(Vec3(4e-3, 4e-3, 6e-3), {"xmax"});
  for (Block* b : {&whole, &half})
    for (Index i = 0; i < b->p().size(); ++i)
      b->p().v_p[i] = field(b->p().x_p[i]);
  whole.run(150, 2e-8);
  half.run(150, 2e-8);
  double worst = 0, largest = 0;
  for (Index i = 0; i < half.p().size(); ++i) {
    const Index id = half.p().id_p[i];
    // Both lattices are numbered x fastest: (ix, iy, iz) in the half is (ix, iy, iz) in the
    // whole, which has 8 instead of 4 along x.
    const Index ix = id % 4, rest = id / 4;
    const Index twin = whole.system.index_of(rest * 8 + ix);
    worst = std::max(worst, (half.p().v_p[i] - whole.p().v_p[twin]).norm());
    largest = std::max(largest, whole.p().v_p[twin].norm());
  }
  // Same sums, other order: agreement to round-off.
  EXPECT_LT(worst, 1e-9 * largest);
}

TEST(MirrorParticles, SymmetryPlanesMakeAColumnCarryAPlaneWaveAtCp) {
  // A 2 × 2 × 40 mm column with symmetry on its four sides is a slice of an unbounded medium:
  // a velocity pulse started at its free top end runs down at c_p = √((K + 4G/3)/ρ)
  // (5966 m/s). Measured from its front's passage at two heights; within 3%.
  // α = 0.2 (the FE bars' linear bulk viscosity, cases/bar_pressed_sph/README.md): α = 1 would
  // smear this smooth pulse and delay its peak.
  Block b(Vec3(2e-3, 2e-3, 60e-3), {"xmin", "xmax", "ymin", "ymax"}, 0.2);
  for (Index i = 0; i < b.p().size(); ++i) {
    const double z = b.p().x_p[i].z() - 60e-3;
    b.p().v_p[i] = Vec3(0, 0, -20.0 * std::exp(-z * z / (2 * 4e-3 * 4e-3)));
  }
  const auto layer_speed = [&](double z0) {
    double sum = 0;
    int count = 0;
    for (Index i = 0; i < b.p().size(); ++i)
      if (std::abs(b.p().x0_p[i].z() - z0) < 0.1 * dp)
        sum += b.p().v_p[i].z(), ++count;
    return sum / count;
  };
  // The front: when a layer's velocity first reaches 5 m/s (a quarter of the pulse's 20 m/s),
  // interpolated within the step; at z = 45.5 and 25.5 mm, 20 mm apart.
  double t45 = 0, t25 = 0, t = 0, last45 = 0, last25 = 0;
  const double dt = 2e-8, level = 5.0;
  while (t < 8e-6 && t25 == 0) {
    b.run(1, dt);
    t += dt;
    const double v45 = -layer_speed(45.5e-3), v25 = -layer_speed(25.5e-3);
    if (t45 == 0 && v45 >= level)
      t45 = t - dt * (v45 - level) / (v45 - last45);
    if (t25 == 0 && v25 >= level)
      t25 = t - dt * (v25 - level) / (v25 - last25);
    last45 = v45, last25 = v25;
  }
  ASSERT_GT(t25, 0.0);
  const double E = 207e9, nu = 0.3, rho = 7830;
  const double c_p = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / rho);
  RecordProperty("speed", std::to_string(20e-3 / (t25 - t45)));
  EXPECT_NEAR(20e-3 / (t25 - t45), c_p, 0.03 * c_p);
}

TEST(MirrorParticles, PlaneReactionEntersTheMomentumBalance) {
  // A block driven into its symmetry plane at 50 m/s is stopped and thrown back by it: its
  // momentum changes by exactly the impulse the plane's mirror images give it, so the
  // momentum balance (which counts that reaction as external) closes to round-off.
  const Case c = read_case_text(R"(
name: plane
time: {end: 4.0e-6, cfl: 0.6, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  block:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.004]}}
    spacing: 0.001
    material: steel
    velocity: [-50, 0, 0]
boundary_conditions:
  - {type: symmetry, body: block, face: xmin}
)",
                                "plane.yaml");
  Simulation sim(c, mesh_case(c));
  const Vec3 P0 = sim.momentum();
  while (sim.time() < c.time.end * (1 - 1e-12))
    sim.step(std::min(sim.stable_dt(), c.time.end - sim.time()));
  EXPECT_GT(sim.momentum().x() - P0.x(), 0.1 * std::abs(P0.x())); // the plane pushed back
  EXPECT_LT(sim.momentum_drift(), 1e-12);
}

TEST(MirrorParticles, ImagesAreStoredWithoutTheVectorsDoubling) {
  // A row of every particle field is ≈ 0.9 KB. The images follow the rows, and the arrays grow
  // for them once: by what they need and a sixteenth more, not to twice the rows, which a plain
  // resize makes when fewer are added than there are (the Børvik quarter held 22 182 rows for
  // 13 392: 9% of its heap). A block with one symmetry plane: half its rows have an image.
  Block block(Vec3(6e-3, 6e-3, 6e-3), {"xmin"});
  Particles& p = block.p();
  const Index images = p.total() - p.rows();
  ASSERT_GT(images, 0);
  ASSERT_LT(images, p.rows()); // where a doubling would show
  const auto most = static_cast<std::size_t>(p.total() + p.total() / 16);
  p.for_each_field([&](const char* name, auto& field) {
    EXPECT_EQ(field.size(), static_cast<std::size_t>(p.total())) << name;
    EXPECT_LE(field.capacity(), most) << name;
  });
}
