// Particle kill (METHOD.md §6): a failed particle keeps its mass and momentum, drops out of
// its neighbours' sums while in tension and stays in them while compressed. A block of
// Johnson–Cook particles (yield never reached) with its centre particle failed is stretched or
// squeezed uniformly; the same block without the failure is the reference.
#include "sph_fixture.hpp"

#include "solver/sph/particle_system.hpp"

#include <gtest/gtest.h>

using namespace sphfem;

namespace {

const double dp = 1e-3;
const Vec3 centre = Vec3::Constant(4 * dp);

Case plastic_block() {
  Case c = test::block_case(dp, 1.2);
  MaterialSpec& m = c.materials[0];
  m.model = "johnson_cook";
  m.johnson_cook = JohnsonCook{.A = 1e12, .B = 0, .n = 1, .C = 0};
  m.damage = DuctileDamage{.D1 = 1, .critical_damage = 1};
  return c;
}

struct Block {
  Case spec = plastic_block();
  Model model = test::lattice_block(Vec3::Constant(8 * dp), dp, 1.2);
  ParticleSystem system{spec, model, {Material::from(spec.materials[0])}};
  Index failed = -1; // current index of the failed particle

  // rate > 0: uniform expansion about the centre; < 0: compression.
  Block(double rate, bool fail) {
    Particles& p = system.particles();
    for (Index i = 0; i < p.size(); ++i) {
      p.v_p[i] = rate * (p.x_p[i] - centre);
      if ((p.x_p[i] - centre).norm() < dp)
        failed = p.id_p[i];
    }
    if (fail)
      p.point_p[system.index_of(failed)].failed = true;
  }
  Particles& p() { return system.particles(); }
  Index index(Index id) const { return system.index_of(id); }
  void step(double dt, long long n) {
    system.kick(0.5 * dt);
    system.drift(dt);
    system.update(dt);
    for (long long k = 1; k < n; ++k) {
      system.kick(dt);
      system.drift(dt);
      system.update(dt);
    }
  }
  Vec3 momentum() {
    Vec3 sum = Vec3::Zero();
    for (Index i = 0; i < p().size(); ++i)
      sum += p().m_p[i] * p().v_p[i];
    return sum;
  }
};

const double dt = 2e-9, rate = 200.0;

} // namespace

TEST(ParticleKill, InTensionOutOfAllSumsAndBallistic) {
  Block killed(rate, true), intact(rate, false);
  const Index f = killed.failed;
  const double mass = killed.p().m_p[killed.index(f)];
  const Vec3 momentum0 = killed.momentum();
  // The first step's material update finds it failed and in tension; from then on it is out.
  killed.step(dt, 2);
  intact.step(dt, 2);
  Particles &p = killed.p(), &q = intact.p();
  const Index i = killed.index(f);
  ASSERT_EQ(p.kill_p[i], Kill::Tension);
  EXPECT_EQ(p.excluded, 1);
  EXPECT_TRUE(p.S_p[i].isZero());
  EXPECT_EQ(p.p_p[i], 0.0);
  // No pair force on it, and none from it: each neighbour counts one neighbour fewer.
  EXPECT_TRUE(p.f_p[i].isZero());
  int neighbours = 0;
  for (Index k = 0; k < p.size(); ++k) {
    const Index r = intact.index(p.id_p[k]);
    if (k == i)
      continue;
    const bool near = (p.x_p[k] - p.x_p[i]).norm() < 2 * p.h_p[i];
    EXPECT_EQ(p.neighbours_p[k], q.neighbours_p[r] - (near ? 1 : 0)) << "particle " << p.id_p[k];
    neighbours += near;
  }
  EXPECT_GT(neighbours, 20);
  // It moves ballistically with its mass and momentum; the total momentum is conserved.
  const Vec3 v0 = p.v_p[i];
  killed.step(dt, 50);
  const Index j = killed.index(f);
  EXPECT_EQ(p.kill_p[j], Kill::Tension);
  EXPECT_EQ(p.m_p[j], mass);
  EXPECT_LT((p.v_p[j] - v0).norm(), 1e-12 * (1 + v0.norm()));
  EXPECT_LT((killed.momentum() - momentum0).norm(), 1e-12 * mass * rate * 8 * dp * p.size());
}

TEST(ParticleKill, InCompressionStillCarriesPressure) {
  Block killed(-rate, true), intact(-rate, false);
  killed.step(dt, 3);
  intact.step(dt, 3);
  Particles &p = killed.p(), &q = intact.p();
  const Index i = killed.index(killed.failed), r = intact.index(killed.failed);
  ASSERT_EQ(p.kill_p[i], Kill::Compressed);
  EXPECT_EQ(p.excluded, 0);
  // No strength left, but the pressure of its density, the same as the intact particle's.
  EXPECT_TRUE(p.S_p[i].isZero());
  EXPECT_GT(p.p_p[i], 0.0);
  EXPECT_NEAR(p.p_p[i], q.p_p[r], 1e-6 * q.p_p[r]);
  EXPECT_EQ(p.neighbours_p[i], q.neighbours_p[r]);
  for (Index k = 0; k < p.size(); ++k)
    EXPECT_EQ(p.neighbours_p[k], q.neighbours_p[intact.index(p.id_p[k])]);
  // Uniform compression leaves no deviator in the intact block either, so the forces on the
  // failed particle are those on its intact twin (scale: its pressure on a lattice face).
  EXPECT_LT((p.f_p[i] - q.f_p[r]).norm(), 1e-6 * q.p_p[r] * dp * dp);
}
