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
// A distributed run's rank holds only the real particles it steps and those near them, in
// model-id order, then the background rows of those and of its nodes, in their nodes' order, then
// its images (parallel/particle_share.hpp): its rows are laid anew at each rebuild and new cut.
// Verified by tests/sph/sph_test.cpp, tests/sph/attached_rows_test.cpp and tests/coupling/.
#pragma once

#include "solver/io/case.hpp"
#include "solver/material/material.hpp"
#include "solver/parallel/particle_share.hpp"
#include "solver/parallel/ranks.hpp"
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

  // No particles and no attached rows in the model (a distributed rank may hold none of them).
  bool empty() const { return particles_.model_real + particles_.model_background == 0; }
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
  // (parallel/particle_share.hpp). filled_here: the attached rows this rank fills (their nodes'
  // rank), which it holds whatever their owner. Collective, as are update() and persist() after it.
  // owner_of_background: the rank of each attached row. The neighbour lists are then of the rows
  // this rank steps only, and, when `attached_rows_listed_if_near`, of the attached rows within two
  // list cutoffs of one of them (a coupling reads those: the surface contact finds its candidates
  // from its faces' corners). The first call of a system made `distributed` also makes its state at
  // t = 0 (lists, kinematics, forces); a later one (a new cut) moves each row that changes rank
  // whole from its old rank, and lists the rows from the last build's positions, which travel with
  // the rows near its own.
  void distribute(std::vector<int> owner_of_id, std::vector<int> owner_of_background,
                  std::vector<Index> filled_here, bool attached_rows_listed_if_near,
                  Migration migration = {});
  // Particles that changed rank since the start (over all ranks).
  long long migrations() const { return migrations_; }
  // Each real particle's value of `field` (a particle field, by row here) by model id, from its
  // owner, on the ranks `to` names (empty elsewhere); on one process the field in model order.
  // Collective.
  template <class T> std::vector<T> by_model_id(std::vector<T>& field, GatherTo to) const {
    return whole(field, to, static_cast<Index>(index_of_id_.size()));
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
  // Current row of the particle that model.h5 lists at `id`; −1 when a distributed run's rank
  // does not hold it.
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
  // decide the next rebuild; reading lists the rows from that build (with its mirror images). A
  // distributed run writes every rank's rows in the one-process layout (without mirror images),
  // gathered on rank 0, and each rank keeps its own and those near them of what it reads.
  // Collective then.
  void persist(StateArchive& a);

private:
  void rebuild();
  // The lists, kinematics and forces at t = 0: of every row on one process, of this rank's rows
  // in a distributed run (every row is current on every rank at t = 0; the halo then receives
  // what the kinematics wrote, as in update()).
  void start();
  void migrate();
  // Whole rows (and their last build's positions) from this rank to others: numbers[r] lists the
  // shared numbers (RowNumbering) of those rank r takes. Collective.
  void hand_over(std::vector<std::vector<Index>> numbers);
  // Whole rows from their owners, with their last build's positions: those `rows` (an exchange
  // on shared numbers) brings, held from now on. Collective.
  void receive_whole(HaloExchange rows);
  // Holds the rows of the shared numbers `numbers` lists (any order, repeats allowed), in their
  // order — real particles, then background rows — keeping the state of those held already; the
  // new rows are zero until received, the mirror images and lists gone until the next build.
  void lay_rows(std::vector<Index> numbers);
  std::vector<Index> held_numbers() const; // of the rows held now, ascending
  void hold_filled_rows();
  // The rows near this rank's own, at their current positions or (`at_build`) at the last
  // build's, from their owners; the rows laid as own and those.
  void receive_neighbourhood(bool at_build);
  void relist();
  void mark_listed(); // the rows this rank lists (all on one process: none marked)
  RowNumbering numbering() const {
    const Particles& p = particles_;
    return {p.id_p, index_of_id_, p.real, p.background_of_row, p.row_of_background};
  }
  // A distributed run's rank stepping row k (a real particle's or an attached row's).
  int row_owner(Index k) const { return owner_[numbering().number(k)]; }
  // A field's values of the first `count` shared numbers (RowNumbering), from their owners, on
  // the ranks `to` names. Collective.
  template <class T> std::vector<T> whole(std::vector<T>& field, GatherTo to, Index count) const;
  void persist_whole(StateArchive& a);
  NeighbourSearch::ListedRows listed() const { return {listed_, listed_if_near_, binned_}; }
  void share(); // the share of the current neighbour list
  // share(), then the new halo whole (field by field: the step's refreshes need a third of a
  // row's buffers), as its rows were current where they were owned only, and their images.
  void share_whole();
  // The last build's lists of the rows this rank now steps (a new cut, a checkpoint read) and
  // their share: receive_neighbourhood(true), relist(), share_whole().
  void relist_shared();
  bool rebuild_due() const;
  void forces(double dt);
  double mirror_reach(std::span<const double> h) const;
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
  bool distributed_ = false; // distribute() was called
  // A distributed run's owners by shared number (model particles, then attached rows).
  std::vector<int> owner_;
  std::vector<Index> filled_here_; // attached rows this rank fills: held whatever their owner
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

template <class T>
std::vector<T> ParticleSystem::whole(std::vector<T>& field, GatherTo to, Index count) const {
  const int me = ranks::rank();
  const bool receives = to == GatherTo::every_rank || me == 0;
  std::vector<T> out(receives ? static_cast<std::size_t>(count) : 0);
  if (!share_) {
    for (Index k = 0; k < particles_.rows(); ++k)
      if (const Index number = numbering().number(k); number < count)
        out[number] = field[k];
    return out;
  }
  const RowNumbering numbers = numbering();
  if (receives)
    for (Index k = 0; k < particles_.rows(); ++k)
      if (const Index number = numbers.number(k); number < count && owner_[number] == me)
        out[number] = field[k];
  // By shared number: an owner reads its row, a receiver writes the whole field's entry.
  struct ByNumber {
    std::vector<T>& field;
    std::vector<T>& out;
    const RowNumbering& numbers;
    const std::vector<int>& owner;
    int me;
    T& operator[](Index number) const {
      return owner[number] == me ? field[numbers.row(number)] : out[number];
    }
  };
  const ByNumber view{field, out, numbers, owner_, me};
  HaloExchange::gather(std::span(owner_).first(count), to).refresh_each([&view](auto visit) {
    visit("", view);
  });
  return out;
}

} // namespace sphfem
