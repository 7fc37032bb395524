// The SPH half of a simulation: the particles, their neighbour search and the per-step
// sequence of METHOD.md §7 for particles — kick (v^{n+½} = v^{n−½} + Δt f/m), drift
// (x^{n+1} = xⁿ + Δt (v^{n+½} + XSPH)), then the particle phase of sph_update.hpp on the new
// positions. The particles keep model.h5's order (id_p and index_of() map between the two, for
// a checkpoint written before 2026-12-07, when rows were renumbered by cell at each rebuild):
// every neighbour row, so every sum over one, runs in that order, which is the same for any
// subset of the rows numbered alike — a distributed rank's, which bins at a rebuild only its own
// rows and those near them (their owners send their positions). Mirror images follow in the
// order of their sources, background rows in their nodes' order. With coupling (METHOD.md §4) the
// arrays continue with rows another phase attaches — the background particles of FE nodes,
// which the step (time/simulation.cpp) fills before each particle phase and whose forces it
// takes back after it, with the contact between bodies (coupling/). The particle phase itself
// knows nothing of elements. A case without particles or attached rows builds none of this.
// Verified by tests/sph/sph_test.cpp, tests/sph/attached_rows_test.cpp and tests/coupling/.
#pragma once

#include "solver/io/case.hpp"
#include "solver/material/material.hpp"
#include "solver/parallel/particle_share.hpp"
#include "solver/sph/mirror_particles.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/model.hpp"
#include "solver/state/particles.hpp"

#include <algorithm>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace sphfem {

class ParticleSystem {
public:
  // Fills the attached rows [p.real, p.rows()) of p: every field at the start, before the first
  // neighbour search.
  using AttachRows = std::function<void(Particles& p)>;

  ParticleSystem() = default;
  // attached: how many rows follow the real particles (the model's background nodes); attach
  // fills them. Both or neither. The neighbour lists, the kinematics and the forces at t = 0 are
  // made here on one process; a distributed run (`distributed`) makes them in distribute(), of
  // the rows each rank steps only.
  ParticleSystem(const Case& c, const Model& model, const std::vector<Material>& materials,
                 Index attached = 0, const AttachRows& attach = {}, bool distributed = false);

  bool empty() const { return particles_.total() == 0; }
  // How a distributed run's real particles change rank between cuts: at each neighbour-list
  // rebuild, one that left its rank's region by more than a list cutoff goes to the rank
  // `owner_at` names (the one whose region holds x; `current` while x lies within `slack` of
  // its own), unless `pinned` (by model id: tied to a node, which keeps its rank). Without
  // owner_at, particles keep their rank until the next cut.
  struct Migration {
    std::function<int(const Vec3& x, int current, double slack)> owner_at;
    std::vector<unsigned char> pinned;
  };
  // A distributed run (issue 28): from now on this rank steps the particles owner_of_id gives
  // it (by model id; they migrate as `migration` says) and computes what their forces read
  // (parallel/particle_share.hpp). Collective, as are update(), gather_state() and reading a
  // checkpoint after it. owner_of_background: the rank of each attached row. The neighbour
  // lists are then of the rows this rank steps only, and, when `attached_rows_listed_if_near`,
  // of the attached rows within two list cutoffs of one of them (a coupling reads those: the
  // surface contact finds its candidates from its faces' corners). The first call of a system
  // made `distributed` also makes its state at t = 0 (lists, kinematics, forces); a later one (a
  // new cut) moves each row that changes rank whole from its old rank, and lists the rows from
  // the last build's positions, which every rank receives.
  void distribute(std::vector<int> owner_of_id, std::vector<int> owner_of_background,
                  bool attached_rows_listed_if_near, Migration migration = {});
  // Particles that changed rank since the start (over all ranks).
  long long migrations() const { return migrations_; }
  // Every rank's particles (but the mirror images, which are each rank's own) and the last
  // neighbour build's positions into the arrays of the ranks `to` names (before a checkpoint or
  // a new cut); nothing on one process.
  void gather_state(GatherTo to);
  // The fields for_each visits (for_each(visit) calls visit(name, field) per field; indexed by
  // row, real and background), from each row's owner into the arrays of the ranks `to` names;
  // nothing on one process. Collective.
  template <class ForEach> void gather(ForEach for_each, GatherTo to) {
    if (share_)
      HaloExchange::gather(share_->owner, to).refresh_by_field(for_each);
  }
  // Per row: 1 for the rows this rank steps (all on one process: empty).
  std::span<const unsigned char> owned_rows() const;
  // The rows this rank steps, ascending; null on one process (all).
  const std::vector<Index>* own_rows() const { return share_ ? &share_->own : nullptr; }
  // The real particles' rows among them (own rows list background rows after the real ones);
  // empty on one process.
  std::span<const Index> own_real_rows() const {
    if (!share_)
      return {};
    const auto& own = share_->own;
    return {own.begin(), std::lower_bound(own.begin(), own.end(), particles().size())};
  }
  // The rows this rank reads and other ranks own (0 on one process).
  Index halo_row_count() const { return share_ ? Index(share_->halo_rows.size()) : 0; }
  // Adds `rows` to what this rank refreshes before each particle phase, until the next
  // neighbour list, and refreshes them now (a coupling's reads: the surface contact's faces and
  // slaves). Collective.
  void read_also(std::span<const Index> rows);
  // Changes whenever the rows this rank refreshes are chosen anew (each neighbour list, each
  // checkpoint read): a coupling's reads are then to be added again.
  long long shares() const { return shares_; }
  // Bytes this rank has sent to refresh other ranks' halos and, at each neighbour-list rebuild,
  // the rows that migrate and the positions of its rows near other ranks' (not counting the
  // gathers for checkpoints and new cuts).
  long long halo_bytes() const { return halo_bytes_ + (share_ ? share_->halo.bytes_sent() : 0); }
  // v += Δt_v f/m and the heating of the artificial terms over the same interval.
  void kick(double dt_v);
  void drift(double dt);
  // Neighbours (rebuilt when needed), kinematics, material update over dt, forces; the attached
  // rows must hold the current state of what they stand for (their owner refreshes them first).
  void update(double dt);
  // Force of the symmetry planes (mirror images) on the particles at the last evaluation, N:
  // an external reaction for the momentum balance. An exact sum over the ranks (collective).
  Vec3 mirror_force() const;
  // Stable step of the particles, s (∞ without particles).
  double stable_dt() const { return dt_stable_; }

  const Particles& particles() const { return particles_; }
  Particles& particles() { return particles_; }
  // Current index of the particle that model.h5 lists at `id`.
  Index index_of(Index id) const { return index_of_id_[id]; }
  long long rebuilds() const { return rebuilds_; }
  // Changes whenever the neighbour lists are made anew: at each rebuild and when the rows a
  // distributed run's rank lists change (a new cut, a checkpoint read). What is found from the
  // lists (contact candidates) is to be found again.
  long long list_builds() const { return list_builds_; }
  // The neighbour lists: in a distributed run, those of the rows this rank steps (and of the
  // attached rows near them if distribute() asked); the other rows' are empty.
  const NeighbourList& neighbours() const { return search_.list(); }
  // Entries in the lists that the pair loops visit (of the particles and background particles;
  // mirror images gather nothing), over all ranks (collective when distributed).
  long long pair_loop_entries() const;
  // Checkpoint: every particle field, the neighbour search's last build and the counters that
  // decide the next rebuild; reading lists the rows from that build (with its mirror images).
  void persist(StateArchive& a);

private:
  void rebuild();
  // The lists, kinematics and forces at t = 0: of every row on one process, of this rank's rows
  // in a distributed run (every row is current on every rank at t = 0; the halo then receives
  // what the kinematics wrote, as in update()).
  void start();
  void migrate();
  void receive_neighbourhood();
  void relist();
  void mark_listed(); // the rows this rank lists (all on one process: none marked)
  // A distributed run's rank stepping row k (a real particle's or an attached row's).
  int row_owner(Index k) const {
    const Index n = particles_.size();
    return k < n ? owner_of_id_[particles_.id_p[k]] : owner_of_background_[k - n];
  }
  NeighbourSearch::ListedRows listed() const { return {listed_, listed_if_near_, binned_}; }
  void share(); // the share of the current neighbour list
  bool rebuild_due() const;
  void forces(double dt);
  double mirror_reach(std::span<const double> h, bool whole) const;
  void place_mirrors(std::span<const Vec3> x, double reach);
  // A distributed run's rows and images that its own rows read (null on one process: all). The
  // other images are refreshed at each rebuild only.
  const std::vector<Index>* visible_rows() const { return share_ ? &share_->visible : nullptr; }

  SphSpec spec_;
  std::vector<Material> materials_;
  Particles particles_;
  NeighbourSearch search_;
  MirrorParticles mirror_;
  std::vector<Index> index_of_id_;
  double skin_ = 0;
  double dt_stable_ = 0;
  long long rebuilds_ = 0;
  long long list_builds_ = 0;
  bool distributed_ = false;             // distribute() was called
  std::vector<int> owner_of_id_;         // a distributed run's owners by model id; else empty
  std::vector<int> owner_of_background_; // and of the attached rows
  Migration migration_;
  long long migrations_ = 0;
  bool attached_rows_listed_if_near_ = false;
  std::vector<unsigned char> listed_;         // per row: 1 when this rank lists it; empty: all
  std::vector<unsigned char> listed_if_near_; // per row: 1 when listed near a listed row
  std::vector<unsigned char> binned_;         // per row: 1 when this rank bins it; empty: all
  std::vector<unsigned char> near_if_listed_; // rows that may be listed_if_near_; empty: all
  std::unique_ptr<ParticleShare> share_;      // this rank's share of the current list
  long long halo_bytes_ = 0;                  // sent through the shares of earlier lists
  long long shares_ = 0;                      // shares made so far
};

} // namespace sphfem
