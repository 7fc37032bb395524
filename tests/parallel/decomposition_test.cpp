// The domain decomposition (solver/parallel/decomposition.hpp, halo.hpp) against counts worked
// out by hand on lattices and blocks: a particle's neighbour-list entries in a cubic lattice,
// the ghost layers a plane cut leaves on each side, the nodes a cut shares, and a cost-weighted
// cut that gives the part with the dearer particles (or the yielding elements) fewer entities,
// and a new cut made only when the steps it saves pay for it;
// and a rank's share of the elements (solver/parallel/subdomain.hpp): the nodes it owns, the
// elements it computes, the halo it reads; and its share of the particles
// (solver/parallel/particle_share.hpp).
#include "solver/core/error.hpp"
#include "solver/parallel/decomposition.hpp"
#include "solver/parallel/halo.hpp"
#include "solver/parallel/particle_share.hpp"
#include "solver/parallel/subdomain.hpp"
#include "solver/time/cost_estimate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

namespace sphfem {
namespace {

constexpr double mm = 1e-3;

// nx × ny × nz particles of spacing 1 mm, h = 1.2 mm, from `origin`.
void add_lattice(Model& m, int nx, int ny, int nz, const Vec3& origin = Vec3::Zero()) {
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        m.x_p.push_back(origin + mm * Vec3(i, j, k));
        m.m_p.push_back(7.85e-6);
        m.rho_p.push_back(7850);
        m.h_p.push_back(1.2 * mm);
        m.body_p.push_back(0);
      }
}

// nx × ny × nz hexahedra of 1 mm from `origin` (gmsh order: bottom face counter-clockwise, then
// the top face).
void add_block(Model& m, int nx, int ny, int nz, const Vec3& origin = Vec3::Zero()) {
  const auto first = static_cast<Index>(m.x_n.size());
  const auto node = [&](int i, int j, int k) {
    return first + static_cast<Index>(i + (nx + 1) * (j + (ny + 1) * k));
  };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        m.x_n.push_back(origin + mm * Vec3(i, j, k));
        m.body_n.push_back(1);
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        m.hex_e.push_back({node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k),
                           node(i, j + 1, k), node(i, j, k + 1), node(i + 1, j, k + 1),
                           node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)});
        m.body_e.push_back(1);
      }
}

#define REQUIRE_PARTITIONER()                                                                      \
  if (!decomposition_available())                                                                  \
  GTEST_SKIP() << "built without MPI and Zoltan"

TEST(EntityCosts, ALatticeParticleCostsItsNeighbourEntries) {
  // Lattice points within 2h = 2.4 spacings of a point: |v|² ≤ 5 → 1 + 6 + 12 + 8 + 6 + 24 = 57,
  // the point itself excluded.
  Model m;
  add_lattice(m, 9, 9, 9);
  const EntityCosts c = entity_costs(m);
  const std::size_t centre = 4 + 9 * (4 + 9 * 4);
  EXPECT_DOUBLE_EQ(c.particle[centre], StepCost::particle + 56 * StepCost::entry);
  EXPECT_LT(c.particle[0], c.particle[centre]); // a corner has fewer neighbours
}

TEST(EntityCosts, MirrorImagesMakeAPlaneParticleAnInteriorOne) {
  // A symmetry plane half a spacing before the first layer: with its images, a particle of
  // that layer (away from the other faces) has the interior's 56 neighbours; without, it lacks
  // the two missing layers' share. Two planes at a corner add the images across both.
  Model m;
  add_lattice(m, 9, 9, 9);
  const std::vector<int> group{0};
  const MirrorParticles::Plane xmin{0, Vec3(-0.5 * mm, 0, 0), Vec3(-1, 0, 0)};
  const MirrorParticles::Plane ymin{0, Vec3(0, -0.5 * mm, 0), Vec3(0, -1, 0)};
  const std::size_t face = 0 + 9 * (4 + 9 * 4), edge = 0 + 9 * (0 + 9 * 4);
  const EntityCosts plain = entity_costs(m);
  const EntityCosts mirrored = entity_costs(m, group, MirrorParticles({xmin}));
  EXPECT_LT(plain.particle[face], mirrored.particle[face]);
  EXPECT_NEAR(mirrored.particle[face], StepCost::particle + 56 * StepCost::entry, 1e-15);
  const EntityCosts corner = entity_costs(m, group, MirrorParticles({xmin, ymin}));
  EXPECT_NEAR(corner.particle[edge], StepCost::particle + 56 * StepCost::entry, 1e-15);
  // A plane of another group mirrors nothing.
  const MirrorParticles::Plane other{1, xmin.point, xmin.normal};
  EXPECT_EQ(entity_costs(m, group, MirrorParticles({other})).particle[face], plain.particle[face]);
}

TEST(EntityCosts, AnElementCarriesItsShareOfTheNodes) {
  // 2 × 1 × 1 block: 8 of each element's nodes, 4 of them shared with the other element.
  Model m;
  add_block(m, 2, 1, 1);
  const EntityCosts c = entity_costs(m);
  ASSERT_EQ(c.element.size(), 2u);
  EXPECT_DOUBLE_EQ(c.element[0], StepCost::element + (4 + 4 * 0.5) * StepCost::node);
  EXPECT_DOUBLE_EQ(c.element[0], c.element[1]);
}

TEST(Decomposition, OnePartNeedsNoPartitioner) {
  Model m;
  add_lattice(m, 3, 3, 3);
  add_block(m, 2, 2, 2, Vec3(10 * mm, 0, 0));
  const Decomposition d = decompose(m, entity_costs(m), 1);
  EXPECT_EQ(d.parts, 1);
  EXPECT_TRUE(std::all_of(d.part_p.begin(), d.part_p.end(), [](int p) { return p == 0; }));
  EXPECT_TRUE(std::all_of(d.part_n.begin(), d.part_n.end(), [](int p) { return p == 0; }));
  EXPECT_TRUE(std::none_of(d.shared_n.begin(), d.shared_n.end(), [](int s) { return s != 0; }));
  const HaloCensus h = halo_census(m, entity_costs(m), d, 0.0);
  EXPECT_EQ(h.parts[0].ghost_points, 0);
  EXPECT_EQ(h.parts[0].foreign_nodes, 0);
  EXPECT_DOUBLE_EQ(h.imbalance, 1.0);
}

TEST(Decomposition, APlaneCutOfALatticeLeavesTwoGhostLayersEachSide) {
  REQUIRE_PARTITIONER();
  Model m; // 8 × 4 × 4: equal costs on either side of x = 3.5 mm
  add_lattice(m, 8, 4, 4);
  const EntityCosts c = entity_costs(m);
  const Decomposition d = decompose(m, c, 2);
  for (std::size_t i = 0; i < m.x_p.size(); ++i) // one side each, cut between the layers
    EXPECT_EQ(d.part_p[i] == d.part_p[0], m.x_p[i].x() < 3.5 * mm) << "particle " << i;

  // Reach h_i + h_j = 2.4 mm: the layers 1 and 2 mm beyond the cut (2 × 16 particles).
  const HaloCensus h0 = halo_census(m, c, d, 0.0);
  for (const PartLoad& p : h0.parts) {
    EXPECT_EQ(p.particles, 64);
    EXPECT_EQ(p.ghost_points, 32);
    EXPECT_DOUBLE_EQ(p.halo_fraction(), 0.5);
  }
  EXPECT_NEAR(h0.imbalance, 1.0, 1e-12);
  // A skin of 0.7 mm reaches 3.1 mm: a third layer.
  const HaloCensus h1 = halo_census(m, c, d, 0.7 * mm);
  for (const PartLoad& p : h1.parts)
    EXPECT_EQ(p.ghost_points, 48);
}

TEST(Decomposition, ElementsTakeTheirNodesAndACutSharesOnePlane) {
  REQUIRE_PARTITIONER();
  Model m; // 6 × 3 × 3 hexahedra
  add_block(m, 6, 3, 3);
  const EntityCosts c = entity_costs(m);
  const Decomposition d = decompose(m, c, 2);
  // Each node belongs to the lowest part of its elements, and is shared when they differ.
  std::vector<std::set<int>> holders(m.x_n.size());
  for (std::size_t e = 0; e < m.hex_e.size(); ++e)
    for (const Index n : m.hex_e[e])
      holders[static_cast<std::size_t>(n)].insert(d.part_e[e]);
  for (std::size_t n = 0; n < m.x_n.size(); ++n) {
    EXPECT_EQ(d.part_n[n], *holders[n].begin());
    EXPECT_EQ(d.shared_n[n] != 0, holders[n].size() > 1);
  }
  // The costs are symmetric about x = 3 mm: the cut is that plane of 4 × 4 nodes.
  const HaloCensus h = halo_census(m, c, d, 0.0);
  const PartLoad& low = h.parts[0];
  const PartLoad& high = h.parts[1];
  EXPECT_EQ(low.elements, 27);
  EXPECT_EQ(high.elements, 27);
  EXPECT_EQ(low.shared_nodes + high.shared_nodes, 16);
  EXPECT_EQ(low.foreign_nodes + high.foreign_nodes, 16);
  EXPECT_EQ(low.nodes + high.nodes, 7 * 4 * 4);
  EXPECT_EQ(low.ghost_points + high.ghost_points, 0); // no particles: nothing within a kernel
}

TEST(Decomposition, EachPhaseIsBalancedOnItsOwn) {
  REQUIRE_PARTITIONER();
  // A lattice of 10 × 6 × 6 particles beside a block of 10 × 6 × 6 hexahedra: one cut of both
  // would give one part the particles and the other the hexahedra (a particle costs ≈ 3–4 × an
  // element), and each would idle through the other's phase. Each part gets half of each kind.
  Model m;
  add_lattice(m, 10, 6, 6, Vec3(0.5 * mm, 0.5 * mm, 0.5 * mm));
  add_block(m, 10, 6, 6, Vec3(10 * mm, 0, 0));
  const EntityCosts c = entity_costs(m);
  const Decomposition d = decompose(m, c, 2);
  const HaloCensus h = halo_census(m, c, d, 0.0);
  EXPECT_LT(h.imbalance, 1.05);
  for (const PartLoad& part : h.parts) {
    EXPECT_NEAR(part.particles, 180, 180 * 0.05);
    EXPECT_NEAR(part.elements, 180, 180 * 0.05);
  }
}

TEST(Decomposition, BackgroundParticlesAreCutWithTheParticles) {
  REQUIRE_PARTITIONER();
  // The lattice of 10 × 6 × 6 particles glued to a block of hexahedra beside it: the block's two
  // node planes within the kernel's reach are background particles. Their pair loops are
  // particle-phase work: each lies in its part's particle region, and the particle phase (the
  // particles' and the background particles' costs) is balanced on its own.
  Model m;
  add_lattice(m, 10, 6, 6);
  add_block(m, 10, 6, 6, Vec3(10 * mm, 0, 0));
  for (Index n = 0; n < static_cast<Index>(m.x_n.size()); ++n)
    if (m.x_n[n].x() < 11.5 * mm) {
      m.background_nodes.push_back(n);
      m.h_background.push_back(1.2 * mm);
    }
  ASSERT_EQ(m.background_nodes.size(), 2u * 7 * 7);
  const EntityCosts c = entity_costs(m);
  ASSERT_EQ(c.background.size(), m.background_nodes.size());
  EXPECT_GT(c.background.front(), 0.0); // it has real neighbours
  const Decomposition d = decompose(m, c, 2);
  ASSERT_EQ(d.part_b.size(), m.background_nodes.size());
  std::vector<double> phase(2, 0.0);
  for (std::size_t i = 0; i < m.x_p.size(); ++i)
    phase[static_cast<std::size_t>(d.part_p[i])] += c.particle[i];
  for (std::size_t k = 0; k < m.background_nodes.size(); ++k) {
    const Vec3& x = m.x_n[static_cast<std::size_t>(m.background_nodes[k])];
    EXPECT_EQ(d.particle_part_at(x, d.part_b[k]), d.part_b[k]) << "background particle " << k;
    phase[static_cast<std::size_t>(d.part_b[k])] += c.background[k];
  }
  EXPECT_NEAR(phase[0], phase[1], 0.05 * (phase[0] + phase[1]) / 2);
  EXPECT_LT(halo_census(m, c, d, 0.0).imbalance, 1.05);
}

TEST(Decomposition, TheElementsPartsAreNamedAfterTheParticlesPartsTheyMeet) {
  REQUIRE_PARTITIONER();
  // A layer of 11 × 9 × 4 particles over a plate of 8 × 9 × 2 hexahedra whose top two node
  // planes are background particles: the particles' box is longer in x, the elements' in y, so
  // the two RCBs into 4 parts cut the same quadrants in another order and number them apart.
  // Renamed, the elements' part of each quadrant is its particles' part: a background particle
  // is filled by its node's rank and stepped by the same rank but near the cuts.
  Model m;
  add_lattice(m, 11, 9, 4, Vec3(0, 0, 3 * mm));
  add_block(m, 8, 9, 2);
  for (Index n = 0; n < static_cast<Index>(m.x_n.size()); ++n)
    if (m.x_n[n].z() > 0.5 * mm) {
      m.background_nodes.push_back(n);
      m.h_background.push_back(1.2 * mm);
    }
  const EntityCosts c = entity_costs(m);
  const Decomposition d = decompose(m, c, 4);
  std::size_t apart = 0;
  for (std::size_t k = 0; k < m.background_nodes.size(); ++k)
    apart += d.part_b[k] != d.part_n[static_cast<std::size_t>(m.background_nodes[k])];
  // Numbered apart, two quadrants of four disagree (103 of the 180); renamed, only the strip
  // between the two cuts' x positions (the particles' box is wider) does.
  EXPECT_LT(apart, m.background_nodes.size() / 4) << apart << " of " << m.background_nodes.size();
  // A renaming: each part still holds a quarter of the elements' cost, and its elements lie in
  // its region.
  std::vector<double> cost(4, 0.0);
  for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
    cost[static_cast<std::size_t>(d.part_e[e])] += c.element[e];
    Vec3 centre = Vec3::Zero();
    for (const Index n : m.hex_e[e])
      centre += m.x_n[static_cast<std::size_t>(n)] / 8.0;
    EXPECT_EQ(d.part_at(centre, d.part_e[e]), d.part_e[e]) << "element " << e;
  }
  for (const double part : cost)
    EXPECT_NEAR(part, cost[0], 0.05 * cost[0]);
}

TEST(Decomposition, ATiedNodeGoesWithItsParticle) {
  REQUIRE_PARTITIONER();
  // A tie (METHOD.md §4.2) between a particle of one part and a node of the other: the node
  // joins the particle's part, whose share then sums the forces of every element around it
  // (received from the elements' part).
  Model m;
  add_lattice(m, 10, 6, 6);
  add_block(m, 10, 6, 6, Vec3(10 * mm, 0, 0));
  Decomposition d = decompose(m, entity_costs(m), 2);
  const auto particle =
      static_cast<Index>(std::find(d.part_p.begin(), d.part_p.end(), 1) - d.part_p.begin());
  const auto node =
      static_cast<Index>(std::find(d.part_n.begin(), d.part_n.end(), 0) - d.part_n.begin());
  ASSERT_LT(particle, static_cast<Index>(m.x_p.size()));
  ASSERT_LT(node, static_cast<Index>(m.x_n.size()));
  d.tie(particle, node);
  EXPECT_EQ(d.part_n[node], 1);
  const Subdomain one = make_subdomain(d, m, 1, false), zero = make_subdomain(d, m, 0, false);
  EXPECT_TRUE(one.owns_n[node]);
  EXPECT_FALSE(zero.owns_n[node]);
  for (Index e = 0; e < static_cast<Index>(m.hex_e.size()); ++e)
    if (std::ranges::find(m.hex_e[e], node) != m.hex_e[e].end()) {
      EXPECT_TRUE(std::ranges::binary_search(one.foreign_elements, e)) << "element " << e;
      EXPECT_EQ(d.part_e[e], 0) << "element " << e;
    }
}

TEST(Decomposition, ThreePartsRepeatBitForBitAndCoverEverything) {
  REQUIRE_PARTITIONER();
  Model m;
  add_lattice(m, 9, 5, 4);
  add_block(m, 9, 5, 3, Vec3(0, 0, 4 * mm));
  const EntityCosts c = entity_costs(m);
  const Decomposition a = decompose(m, c, 3);
  const Decomposition b = decompose(m, c, 3);
  EXPECT_EQ(a.part_p, b.part_p);
  EXPECT_EQ(a.part_e, b.part_e);
  EXPECT_EQ(a.part_n, b.part_n);
  // Each entity lies in its part's region (particles at their positions, elements at their
  // centroids) and keeps it there, also where RCB split a layer lying on a cut; regions tile
  // space, their outer sides unbounded.
  for (std::size_t i = 0; i < m.x_p.size(); ++i)
    EXPECT_EQ(a.particle_part_at(m.x_p[i], a.part_p[i]), a.part_p[i]) << "particle " << i;
  for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
    Vec3 c = Vec3::Zero();
    for (const Index n : m.hex_e[e])
      c += m.x_n[static_cast<std::size_t>(n)] / 8.0;
    EXPECT_EQ(a.part_at(c, a.part_e[e]), a.part_e[e]) << "element " << e;
  }
  for (const Vec3& far : {Vec3(-1e300, -1e300, 1e300), Vec3(1e300, 2e300, -1e300)}) {
    EXPECT_NO_THROW(a.part_at(far));
    EXPECT_NO_THROW(a.particle_part_at(far));
  }
  // A particle moved 1 m along +x belongs to a region unbounded that way.
  const int far_part = a.particle_part_at(m.x_p[0] + Vec3(1.0, 0, 0), a.part_p[0]);
  EXPECT_TRUE(std::isinf(a.particle_regions[static_cast<std::size_t>(far_part)].hi.x()));
  std::set<int> used(a.part_p.begin(), a.part_p.end());
  used.insert(a.part_e.begin(), a.part_e.end());
  EXPECT_EQ(used, (std::set<int>{0, 1, 2}));
  EXPECT_LT(halo_census(m, c, a, 0.0).imbalance, 1.1);
}

TEST(Decomposition, KilledAndErodedEntitiesLeaveTheirPartsCost) {
  Model m;
  add_lattice(m, 4, 4, 4);
  add_block(m, 3, 3, 3, Vec3(10 * mm, 0, 0));
  const EntityCosts c = entity_costs(m);
  Decomposition d = decompose(m, c, 1);
  d.parts = 2; // particles in part 0, elements in part 1, whatever RCB would do
  std::fill(d.part_e.begin(), d.part_e.end(), 1);
  const std::vector<unsigned char> all_p(m.x_p.size(), 1), none_p(m.x_p.size(), 0);
  std::vector<unsigned char> live_e(m.hex_e.size(), 1);
  const std::vector<int> ten(m.x_p.size(), 10);
  const std::vector<double> start = part_costs(d, c, ten, all_p, live_e);
  EXPECT_NEAR(start[0], 64 * (StepCost::particle + 10 * StepCost::entry), 1e-15);
  live_e[0] = 0; // one element eroded, every particle killed
  const std::vector<double> later = part_costs(d, c, ten, none_p, live_e);
  EXPECT_EQ(later[0], 0.0);
  EXPECT_NEAR(later[1], start[1] - c.element[0], 1e-15);
  EXPECT_THROW(part_costs(d, c, std::vector<int>(3, 0), all_p, live_e), Error);
}

TEST(Decomposition, ImbalanceIsTheWorsePhasesAndANewCutOfTheCurrentCostsRestoresIt) {
  // A lattice of particles under a block of hexahedra, cut in two balanced parts. Kill the
  // particles of one part: the particles' phase is then all the other's (imbalance 2, the
  // elements' stays 1), and a new cut at the current costs shares the survivors evenly.
  REQUIRE_PARTITIONER();
  Model m;
  add_lattice(m, 8, 4, 4);
  add_block(m, 8, 4, 4, Vec3(0, 0, 10 * mm));
  const EntityCosts c = entity_costs(m);
  const Decomposition d = decompose(m, c, 2);
  const std::vector<int> ten(m.x_p.size(), 10);
  std::vector<unsigned char> live_p(m.x_p.size(), 1);
  const std::vector<unsigned char> live_e(m.hex_e.size(), 1);
  EXPECT_NEAR(phase_imbalance(d, current_costs(c, ten, live_p, live_e)), 1.0, 1e-12);
  for (std::size_t i = 0; i < m.x_p.size(); ++i)
    live_p[i] = d.part_p[i] == 0 ? 1 : 0;
  const EntityCosts now = current_costs(c, ten, live_p, live_e);
  EXPECT_EQ(now.particle[static_cast<std::size_t>(std::find(live_p.begin(), live_p.end(), 0) -
                                                  live_p.begin())],
            0.0);
  EXPECT_NEAR(phase_imbalance(d, now), 2.0, 1e-12);
  const Decomposition again = decompose(m, now, 2);
  EXPECT_NEAR(phase_imbalance(again, now), 1.0, 1e-12);
  EXPECT_THROW(phase_imbalance(d, entity_costs(Model())), Error);
}

TEST(Decomposition, YieldingEntitiesCostTheirReturnAndACutGivesTheirPartFewer) {
  // A block of 16 × 4 × 4 hexahedra whose half x < 8 mm yields: each of its elements costs
  // StepCost::yielding_point more, and a yielding particle the same more than a quiet one.
  REQUIRE_PARTITIONER();
  Model m;
  add_lattice(m, 2, 2, 2, Vec3(40 * mm, 0, 0));
  add_block(m, 16, 4, 4);
  const EntityCosts c = entity_costs(m);
  const std::vector<int> ten(m.x_p.size(), 10);
  const std::vector<unsigned char> live_p(m.x_p.size(), 1), live_e(m.hex_e.size(), 1);
  std::vector<unsigned char> yielding_p(m.x_p.size(), 0), yielding_e(m.hex_e.size(), 0);
  yielding_p[3] = 1;
  for (std::size_t e = 0; e < m.hex_e.size(); ++e)
    yielding_e[e] = e % 16 < 8; // x fastest in add_block
  const EntityCosts now = current_costs(c, ten, live_p, live_e, yielding_p, yielding_e);
  EXPECT_NEAR(now.particle[3] - now.particle[2], StepCost::yielding_point, 1e-18);
  EXPECT_NEAR(now.element[0] - c.element[0], StepCost::yielding_point, 1e-18);
  EXPECT_EQ(now.element[8], c.element[8]);
  EXPECT_EQ(current_costs(c, ten, live_p, live_e).element[0], c.element[0]); // none yields
  EXPECT_THROW(current_costs(c, ten, live_p, live_e, std::vector<unsigned char>(1, 0)), Error);

  // Cut in two at these costs, the part holding the yielding end takes half the total cost in
  // elements of ≈ 1.6 × an elastic one's: ≈ 104 of the 256, not 128 — to within the x-plane of
  // 16 elements that RCB cuts whole. That cut is better balanced than the one of the start.
  const Decomposition d = decompose(m, now, 2);
  double total = 0, yielding_cost = 0;
  for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
    total += now.element[e];
    yielding_cost += yielding_e[e] ? now.element[e] / 128.0 : 0.0;
  }
  const auto in_yielding_part =
      static_cast<double>(std::count(d.part_e.begin(), d.part_e.end(), d.part_e[0]));
  EXPECT_NEAR(in_yielding_part, 0.5 * total / yielding_cost, 16.0);
  EXPECT_LT(in_yielding_part, 128.0 - 16.0);
  EXPECT_LT(phase_imbalance(d, now), phase_imbalance(decompose(m, c, 2), now));
}

TEST(Decomposition, ANewCutIsMadeWhenTheStepsItSavesPayForIt) {
  // Three parts costing 3, 2 and 1 ms per step in the particles' phase (mean 2: a step waits
  // 1 ms beyond an even share) and 5, 5 and 8 ms in the elements' (mean 6: 2 ms more). Evening
  // them out saves 3 ms a step; a cut of 10⁴ entities costs 10⁴ × StepCost::new_cut = 20 ms,
  // repaid after 20 / 3 = 6.7 steps of the current cut's service: 7 pay, 6 do not.
  const PhaseCosts c{{3e-3, 2e-3, 1e-3}, {5e-3, 5e-3, 8e-3}};
  EXPECT_NEAR(wait_beyond_even(c), 3e-3, 1e-15);
  const std::size_t entities = 10000;
  ASSERT_NEAR(StepCost::new_cut * entities, 20e-3, 1e-15);
  EXPECT_TRUE(new_cut_pays(c, 7, entities));
  EXPECT_FALSE(new_cut_pays(c, 6, entities));
  EXPECT_FALSE(new_cut_pays(c, 0, entities)); // a cut just made
  // Even parts never pay for a cut, however long the cut has served.
  const PhaseCosts even{{2e-3, 2e-3, 2e-3}, {6e-3, 6e-3, 6e-3}};
  EXPECT_NEAR(wait_beyond_even(even), 0.0, 1e-18);
  EXPECT_FALSE(new_cut_pays(even, 1000000, entities));
}

TEST(Subdomain, ARankComputesItsElementsAndReceivesTheForcesOfTheOthersOnItsNodes) {
  // A 4 × 2 × 2 block of equal elements cut in two at x = 2 mm: the 9 nodes on the cut belong
  // to the lower part. So it owns 27 nodes, computes its 8 elements and receives the forces of
  // the other part's 4 at the cut, reading no node; the upper part owns 18, computes its own 8,
  // receives nothing and reads the 9 on the cut.
  REQUIRE_PARTITIONER();
  Model m;
  add_block(m, 4, 2, 2);
  const Decomposition d = decompose(m, entity_costs(m), 2);
  const int lower = d.part_e[0]; // the element at the origin
  std::vector<int> owners(m.x_n.size(), 0), computed(m.hex_e.size(), 0);
  for (int part : {0, 1}) {
    const Subdomain s = make_subdomain(d, m, part, false);
    const bool is_lower = part == lower;
    EXPECT_EQ(s.nodes.size(), is_lower ? 27u : 18u);
    EXPECT_EQ(s.elements.size(), 8u);
    EXPECT_EQ(s.foreign_elements.size(), is_lower ? 4u : 0u);
    EXPECT_EQ(s.halo_nodes.size(), is_lower ? 0u : 9u);
    for (Index i : s.halo_nodes)
      EXPECT_NEAR(m.x_n[i].x(), 2 * mm, 1e-12);
    for (Index i : s.nodes)
      ++owners[i];
    for (Index k : s.elements)
      ++computed[k];
    // Every element holding an owned node is computed here or sends its forces here.
    for (Index k = 0; k < static_cast<Index>(m.hex_e.size()); ++k) {
      const bool holds = std::ranges::any_of(m.hex_e[k], [&](Index i) { return s.owns_n[i]; });
      EXPECT_EQ(std::ranges::binary_search(s.elements, k), d.part_e[k] == part) << k;
      EXPECT_EQ(std::ranges::binary_search(s.foreign_elements, k), holds && d.part_e[k] != part)
          << k;
    }
  }
  EXPECT_TRUE(std::ranges::all_of(owners, [](int n) { return n == 1; }));   // each node once
  EXPECT_TRUE(std::ranges::all_of(computed, [](int n) { return n == 1; })); // each element once
}

TEST(ParticleShare, ARankReadsItsParticlesNeighbours) {
  // An 8 × 4 × 4 lattice (1 mm, h = 1.2 mm: a list reaches 2.4 mm, two layers) owned by two
  // ranks split at x = 3.5 mm. The lower rank owns 4 layers (64 particles) and reads the 2
  // layers beyond the cut (32): its particles' neighbours.
  Model m;
  add_lattice(m, 8, 4, 4);
  Particles p;
  p.real = static_cast<Index>(m.x_p.size());
  p.x_p = m.x_p;
  p.id_p.resize(p.real);
  std::iota(p.id_p.begin(), p.id_p.end(), Index{0});
  NeighbourSearch search;
  search.build(m.x_p, m.h_p, 0.0);
  std::vector<int> owner(p.real);
  for (Index i = 0; i < p.real; ++i)
    owner[i] = m.x_p[i].x() < 3.5 * mm ? 0 : 1;
  const RowNumbering numbers{p.id_p, p.id_p, p.real}; // every row, in model order
  ParticleShare lower =
      make_particle_share(p, search.list(), MirrorParticles(), owner, numbers, 0, false);
  EXPECT_EQ(lower.own.size(), 64u);
  EXPECT_EQ(lower.halo_rows.size(), 32u);
  EXPECT_EQ(lower.visible.size(), 96u);
  for (Index i : lower.halo_rows)
    EXPECT_LT(m.x_p[i].x(), 5.5 * mm);
  // Every neighbour of an owned row is owned or read.
  for (Index i : lower.own)
    for (Index j : search.list().of(i))
      EXPECT_TRUE(lower.owns[j] || std::ranges::binary_search(lower.halo_rows, j));
  // A coupling's further reads join the halo (one process: no exchange to agree).
  std::vector<Index> further{lower.own[0]}; // owned: skipped
  for (Index i = 0; i < p.real && further.size() < 3; ++i)
    if (m.x_p[i].x() > 6 * mm) // the last layer: beyond the halo
      further.push_back(i);
  further.push_back(further[1]); // twice: once
  EXPECT_TRUE(read_also(lower, MirrorParticles(), further, owner, numbers));
  EXPECT_EQ(lower.halo_rows.size(), 34u);
  EXPECT_TRUE(std::ranges::binary_search(lower.halo_rows, further[2]));
  EXPECT_TRUE(std::ranges::is_sorted(lower.visible));
  EXPECT_EQ(lower.visible.size(), 98u);
}

TEST(Decomposition, ARanksVisibleRowsHoldTheImagesOfItsVisibleRowsAndNoOthers) {
  // The lattice above with a symmetry plane at z = −0.5 mm: the particles within 2.4 mm of it
  // (z = 0 and 1 mm) get images. Split at x = 3.5 mm, the lower rank keeps x = 0–3 mm and reads
  // x = 4, 5 mm: it refreshes the images of those rows only (48 of 64), and every image its own
  // rows list is among them.
  Model m;
  add_lattice(m, 8, 4, 4);
  Particles p;
  p.real = static_cast<Index>(m.x_p.size());
  p.for_each_field([&p](const char*, auto& field) { field.resize(p.real); });
  p.x_p = m.x_p;
  p.h_p = m.h_p;
  std::iota(p.id_p.begin(), p.id_p.end(), Index{0});
  const MirrorParticles::Plane plane{0, Vec3(0, 0, -0.5 * mm), Vec3(0, 0, -1)};
  MirrorParticles mirrors(std::vector{plane});
  mirrors.select(p, p.x_p, 2.4 * mm);
  ASSERT_EQ(mirrors.size(), 64);
  p.for_each_field([&](const char*, auto& field) { field.resize(p.real + mirrors.size()); });
  mirrors.refresh_motion(p, p.rows());
  NeighbourSearch search;
  search.build(p.x_p, p.h_p, 0.0);
  std::vector<int> owner(p.real);
  for (Index i = 0; i < p.real; ++i)
    owner[i] = m.x_p[i].x() < 3.5 * mm ? 0 : 1;
  for (const int rank : {0, 1}) {
    const RowNumbering numbers{p.id_p, std::span(p.id_p).first(p.real), p.real};
    const ParticleShare s =
        make_particle_share(p, search.list(), mirrors, owner, numbers, rank, false);
    EXPECT_TRUE(std::ranges::is_sorted(s.visible));
    const auto visible = [&](Index j) { return std::ranges::binary_search(s.visible, j); };
    Index images = 0;
    for (Index k = 0; k < mirrors.size(); ++k) {
      const Index source = mirrors.source(k);
      EXPECT_EQ(visible(p.rows() + k), visible(source)) << "image " << k;
      const double x = m.x_p[source].x();
      EXPECT_EQ(visible(p.rows() + k), rank == 0 ? x < 5.5 * mm : x > 1.5 * mm) << "image " << k;
      images += visible(p.rows() + k);
    }
    EXPECT_EQ(images, 48);
    for (Index i : s.own)
      for (Index j : search.list().of(i))
        EXPECT_TRUE(visible(j)) << "row " << i << " lists " << j;
  }
}

TEST(ParticleShare, ARanksRowsMapToTheNumbersEveryRankShares) {
  // A rank of a 10-particle model with 2 background rows holds particles 2, 5 and 7: its rows
  // 0–2, then the background rows 3–4, shared as 10 and 11.
  const std::vector<Index> id_of_row{2, 5, 7, -1, -1};
  std::vector<Index> row_of_id(10, -1);
  for (Index k = 0; k < 3; ++k)
    row_of_id[id_of_row[k]] = k;
  const RowNumbering numbers{id_of_row, row_of_id, 3};
  EXPECT_EQ(numbers.model(), 10);
  const std::vector<Index> shared{2, 5, 7, 10, 11};
  for (Index k = 0; k < 5; ++k) {
    EXPECT_EQ(numbers.number(k), shared[k]);
    EXPECT_EQ(numbers.row(shared[k]), k);
  }
  EXPECT_EQ(numbers.row(4), -1); // not held here
}

TEST(Decomposition, BadRequestsAreRefused) {
  Model m;
  add_lattice(m, 2, 2, 2);
  const EntityCosts c = entity_costs(m);
  EXPECT_THROW(decompose(m, c, 0), Error);
  EXPECT_THROW(decompose(m, EntityCosts{}, 1), Error);
  const Decomposition d = decompose(m, c, 1);
  EXPECT_THROW(halo_census(m, c, d, -1e-3), Error);
  Model other;
  add_lattice(other, 3, 2, 2);
  EXPECT_THROW(halo_census(other, entity_costs(other), d, 0.0), Error);
}

} // namespace
} // namespace sphfem
