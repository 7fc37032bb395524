// Domain decomposition of a model among ranks (issue 28, point 2): recursive coordinate
// bisection (Zoltan's RCB) of the particles, and another of the hexahedra (at their centroids),
// each entity weighted by its measured cost per step (solver/time/cost_estimate.hpp's StepCost:
// a particle costs StepCost::particle plus StepCost::entry per neighbour-list entry; an element
// StepCost::element plus its share of the nodes; a yielding one, StepCost::yielding_point more).
// Two cuts, because the step has two phases separated by exchanges (the elements', then the
// particles'): one cut of both kinds together balanced their sum, and each rank idled through the
// phase it had little of (docs/scaling.md). Elements and their nodes go together: a node belongs to
// the lowest part among the elements that hold it, and is "shared" when elements of several parts
// hold it (its forces and masses are then summed across those parts, METHOD.md §3). Background
// particles (§4.1) are filled from their node by the node's part but cost in the particle phase
// (their pair loops): they are cut with the particles, at their node's position.
//
// The partition is computed by Zoltan on one process for all parts (MPI_COMM_SELF), so it is
// the same on every rank and for every rank count that asks for the same number of parts, and
// repeats bit for bit. Verified by tests/parallel/decomposition_test.cpp.
#pragma once

#include "solver/sph/mirror_particles.hpp"
#include "solver/state/model.hpp"

#include <span>
#include <vector>

namespace sphfem {

// Seconds of one thread per step, per entity.
struct EntityCosts {
  std::vector<double> particle;   // per particle of the model
  std::vector<double> background; // per background particle: its pair-list entries
  std::vector<double> element;    // per hexahedron, with its share of the nodes' cost
};

// Costs from the model's reference configuration: each particle's neighbour-list entries are
// counted among the particles, background particles and their mirror images across the case's
// symmetry planes (solver/sph/mirror_particles.hpp; a plane acts on the bodies of its group,
// `body_group` giving each body's) within h_i + h_j, the kernel's reach.
EntityCosts entity_costs(const Model& m, const std::vector<int>& body_group = {},
                         const MirrorParticles& mirrors = MirrorParticles());

struct Decomposition {
  // Each part's region: the box RCB's cuts bound it by (infinite on the model's outer sides).
  // The regions tile space; a moving entity's owner is the region it is in (part_at). The
  // elements' cut makes `regions`, the particles' `particle_regions` (the same when the model
  // has only one kind).
  struct Region {
    Vec3 lo, hi;
    bool holds(const Vec3& x) const { // faces included
      return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
    }
  };

  int parts = 1;
  std::vector<Region> regions;          // per part: of its elements and nodes
  std::vector<Region> particle_regions; // per part: of its particles
  std::vector<int> part_p;              // per particle
  std::vector<int> part_b;              // per background particle: the particles' cut
  std::vector<int> part_e;              // per element
  std::vector<int> part_n;              // per node: the lowest part among the elements holding it
  std::vector<unsigned char> shared_n;  // 1 when elements of more than one part hold the node

  // The owner of an entity at x: `current` while its region still holds x (RCB splits the
  // entities lying on a cut between the two sides), else the lowest part whose region does.
  int part_at(const Vec3& x, int current = -1) const;
  // The same for a particle, by particle_regions; `current` also while x lies within `slack`
  // of its region (a particle just across a cut stays).
  int particle_part_at(const Vec3& x, int current = -1, double slack = 0) const;

  // A tied particle (model id) and its node (interface ties, METHOD.md §4.2) move as one: the
  // node joins the particle's part, which then also computes the elements around it, so that
  // the particles' cut keeps its balance (with the particle given to the node's part instead,
  // the Børvik core's tied layer put 140 of its 2 601 particles on one of two ranks).
  void tie(Index particle, Index node) { part_n[node] = part_p[particle]; }
};

// True when this build can decompose (MPI and Zoltan found at configuration).
bool decomposition_available();

// RCB into `parts` parts (≥ 1) balancing the particles' costs and the elements' costs. Throws
// sphfem::Error when parts < 1, when the costs do not match the model, or when the build has no
// Zoltan.
Decomposition decompose(const Model& m, const EntityCosts& costs, int parts);

// A live particle's cost per step with `neighbours` entries in its list (killed: nothing), and
// StepCost::yielding_point more when its material point yields.
double live_particle_cost(int neighbours, bool yielding = false);
// A live element's cost per step: `reference` (its cost in the reference configuration), and
// StepCost::yielding_point more when its material point yields.
double live_element_cost(double reference, bool yielding);

// Each entity's cost per step at a later state of the run: a live particle costs
// StepCost::particle + StepCost::entry × its current neighbour count, a live element its cost in
// `costs`, each plus StepCost::yielding_point when `yielding_p` / `yielding_e` marks it (its
// material point yields: the return costs ≈ 60% of an elastic element's step; empty: none
// yields); a background particle costs its cost in `costs`; killed particles and eroded elements
// cost nothing. Spans indexed as the model's particles and elements; throws sphfem::Error when a
// size differs.
EntityCosts current_costs(const EntityCosts& costs, std::span<const int> neighbours_p,
                          std::span<const unsigned char> live_p,
                          std::span<const unsigned char> live_e,
                          std::span<const unsigned char> yielding_p = {},
                          std::span<const unsigned char> yielding_e = {});

// Each part's cost per step at a later state of the run (current_costs), the decomposition kept.
// Shows how the work moves as a plug and debris leave.
std::vector<double> part_costs(const Decomposition& d, const EntityCosts& costs,
                               std::span<const int> neighbours_p,
                               std::span<const unsigned char> live_p,
                               std::span<const unsigned char> live_e,
                               std::span<const unsigned char> yielding_p = {},
                               std::span<const unsigned char> yielding_e = {});

// Each part's cost per step in each phase of the step: the particles' (with the background
// particles) and the elements'. Throws sphfem::Error when the costs are not of the
// decomposition's model.
struct PhaseCosts {
  std::vector<double> particle, element; // per part, s
};
PhaseCosts phase_costs(const Decomposition& d, const EntityCosts& costs);

// The largest part's cost over the mean, the worse of the two phases' (the particles' with the
// background particles, the elements'): what a step waits for. Throws sphfem::Error when the
// costs are not of the decomposition's model.
double phase_imbalance(const Decomposition& d, const EntityCosts& costs);
// The same of each part's phase costs.
double phase_imbalance(const PhaseCosts& c);
// What a step waits for beyond an even share, s: the largest part's cost over the mean in each
// phase, summed over the phases (what the best cut of the same entities would save per step).
double wait_beyond_even(const PhaseCosts& c);
// Whether a new cut of a model of `entities` particles and elements, its parts costing `c` per
// step now, pays: whether evening them out would save, over as many steps as the current cut
// has served (`steps_served`, the guess of how long the new one will), more than the cut costs
// (StepCost::new_cut per entity).
bool new_cut_pays(const PhaseCosts& c, long long steps_served, std::size_t entities);

} // namespace sphfem
