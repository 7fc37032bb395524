// The particle phase on its own with rows attached by its caller (solver/sph/particle_system.hpp):
// what the step does with the background particles of FE nodes (METHOD.md §4.1–4.2), here with
// a layer of rows the test fills itself — no elements. The pair forces the attached rows take
// are what the step returns to their owner, so the real particles and the attached rows together
// must conserve linear momentum to round-off, and the layer must carry the block's push.
#include "sph_fixture.hpp"

#include "solver/sph/particle_system.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sphfem;

namespace {

const double dp = 1e-3, h_factor = 1.2;

// Row b as a steel particle of spacing dp at rest at x, unstressed, in body 0.
void fill_row(Particles& p, Index b, const Vec3& x, const Material& steel) {
  const double rho = steel.elastic.density;
  p.start_row(b, {x, Vec3::Zero(), rho * dp * dp * dp, rho, h_factor * dp, dp, 0, 0, -1,
                  MaterialPoint::initial(steel)});
}

// A 6 × 6 × 4 block moving down at `speed` onto a 6 × 6 × 2 layer of attached rows at rest
// below it, the layer in the same body (an attachment, as an FE body's surface nodes are).
ParticleSystem block_on_layer(double speed, Index& layer_rows) {
  Case c = test::block_case(dp, h_factor);
  c.bodies[0].velocity = Vec3(0, 0, -speed);
  const Model block = test::lattice_block(Vec3(6 * dp, 6 * dp, 4 * dp), dp, h_factor);
  const Model layer = test::lattice_block(Vec3(6 * dp, 6 * dp, 2 * dp), dp, h_factor);
  layer_rows = layer.particle_count();
  const Material steel = Material::from(c.materials[0]);
  return ParticleSystem(c, block, {steel}, layer_rows, [&](Particles& p) {
    for (Index k = 0; k < layer_rows; ++k)
      fill_row(p, p.real + k, layer.x_p[k] - Vec3(0, 0, 2 * dp), steel);
  });
}

struct ForceSums {
  Vec3 real = Vec3::Zero(), attached = Vec3::Zero();
  double scale = 0; // Σ |f| over every row, N
};

ForceSums force_sums(const Particles& p) {
  ForceSums s;
  for (Index i = 0; i < p.rows(); ++i) {
    (i < p.size() ? s.real : s.attached) += p.f_p[i];
    s.scale += p.f_p[i].norm();
  }
  return s;
}

} // namespace

TEST(AttachedRows, TakeTheReactionOfThePairForcesOnTheRealParticles) {
  Index layer_rows = 0;
  ParticleSystem system = block_on_layer(10.0, layer_rows);
  ASSERT_EQ(system.particles().background, layer_rows);
  const double dt = 0.3 * h_factor * dp / 6000.0;
  for (int step = 0; step < 20; ++step) {
    system.kick(step == 0 ? 0.5 * dt : dt);
    system.drift(dt);
    system.update(dt); // the layer's rows stay as the test left them: a support at rest
    const ForceSums s = force_sums(system.particles());
    ASSERT_GT(s.scale, 0);
    EXPECT_LT((s.real + s.attached).norm(), 1e-12 * s.scale) << "step " << step;
  }
  // The block pushes into the layer: the layer is pushed down, the block held up.
  const ForceSums s = force_sums(system.particles());
  EXPECT_GT(s.real.z(), 0.05 * s.scale);
  EXPECT_LT(s.attached.z(), -0.05 * s.scale);
}

TEST(AttachedRows, OutOfReachChangeNothing) {
  // Attached rows far from every real particle (moved 10 h away) leave the real particles'
  // forces bit for bit as without them.
  Case c = test::block_case(dp, h_factor);
  c.bodies[0].velocity = Vec3(0, 0, -10.0);
  const Model block = test::lattice_block(Vec3(6 * dp, 6 * dp, 4 * dp), dp, h_factor);
  const Material steel = Material::from(c.materials[0]);
  ParticleSystem alone(c, block, {steel});
  ParticleSystem with_far(c, block, {steel}, 1, [&](Particles& p) {
    fill_row(p, p.real, Vec3(0, 0, -10 * h_factor * dp), steel);
  });
  const double dt = 1e-8;
  for (ParticleSystem* s : {&alone, &with_far}) {
    s->kick(0.5 * dt);
    s->drift(dt);
    s->update(dt);
  }
  for (Index id = 0; id < block.particle_count(); ++id) {
    const Vec3& a = alone.particles().f_p[alone.index_of(id)];
    const Vec3& b = with_far.particles().f_p[with_far.index_of(id)];
    EXPECT_EQ(a, b) << "particle " << id;
  }
}
