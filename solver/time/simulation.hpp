// One explicit simulation (METHOD.md §3, §7): the state of nodes and elements, and the
// central-difference step in LS-DYNA order — external forces at tⁿ, v^{n+½} = v^{n−½} + Δtⁿ aⁿ
// (Δtⁿ the mean of the neighbouring position steps),
// kinematic constraints, x^{n+1} = xⁿ + Δt v^{n+½}, then the element phase (stress to σ^{n+1},
// forces on x^{n+1}, next stable step). Energies and momentum are accounted every step so the
// balances of DESIGN.md can be reported. Verified by tests/fem/wave_test.cpp and
// tests/fem/conservation_test.cpp.
#pragma once

#include "solver/core/exact_sum.hpp"
#include "solver/coupling/background_particles.hpp"
#include "solver/coupling/contact.hpp"
#include "solver/coupling/interface_ties.hpp"
#include "solver/fem/node_gather.hpp"
#include "solver/io/case.hpp"
#include "solver/io/state_archive.hpp"
#include "solver/material/material.hpp"
#include "solver/parallel/subdomain.hpp"
#include "solver/sph/particle_system.hpp"
#include "solver/state/hex_elements.hpp"
#include "solver/state/model.hpp"
#include "solver/state/nodes.hpp"
#include "solver/time/constraints.hpp"
#include "solver/time/particle_boundaries.hpp"
#include "solver/time/pressure_loads.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace sphfem {

struct Energies {
  double kinetic = 0;       // J, from v^{n+½}
  double internal = 0;      // J
  double hourglass = 0;     // J
  double contact = 0;       // J
  double external_work = 0; // J, loads and reactions
  double eroded = 0;        // J, internal and hourglass energy of eroded elements
  double friction = 0;      // J, dissipated by contact friction
  double total() const { return kinetic + internal + hourglass + contact + eroded + friction; }
};

struct BodyTotals {
  std::string name;
  double mass = 0;                   // kg
  Vec3 com_velocity = Vec3::Zero();  // m/s
  Vec3 contact_force = Vec3::Zero(); // from its contact partners (METHOD.md §4.3), N
  Index killed_particles = 0;        // failed particles (METHOD.md §6)
  Index eroded_elements = 0;
  double kinetic = 0;  // J, ½ Σ m v² of its nodes and particles
  double internal = 0; // J, stress work and viscous heating in its particles and live elements
};

// What Simulation::rebalance found: the imbalance (largest rank's cost per step over the mean,
// the worse phase) at the entities' current costs, under the decomposition it had and the one it
// has now (the same when it was kept).
struct Rebalance {
  double before = 1, after = 1;
  bool done = false;
};

class Simulation {
public:
  // With a decomposition of several parts (a distributed run, issue 28) this rank steps its
  // share (parallel/subdomain.hpp) and holds the particles near it only: call gather_state()
  // before reading the whole state of the nodes.
  Simulation(const Case& c, const Model& model, const Decomposition* decomposition = nullptr);

  // Largest step the stability limits allow now: min(time.cfl × Δt_FE ⊕ Δt_c, 0.3 Δt_c,
  // sph.cfl × min over particles of h/(c + |v|)), Δt_FE = min over elements of L_e/c and Δt_c =
  // 2/ω the stiffest surface contact spring's critical step. a ⊕ b = (a⁻² + b⁻²)^−½: a node's
  // element and contact springs add their ω². The contact's own bound, ωΔt ≤ 0.6, is accuracy:
  // a penalty spring that closes and opens between steps gains or loses energy the more the
  // larger ωΔt (two bars struck end on end: balance error 4.1%, 1.6%, 0.12% at ωΔt ≈ 1.6, 1.1,
  // 0.54). Without surface contact Δt_c = ∞ and the limit is time.cfl × Δt_FE as before.
  double stable_dt() const {
    const double contact = contact_.stable_dt();
    if (std::isinf(contact))
      return std::min(cfl_ * dt_elements_, particles_.stable_dt());
    const double combined =
        1 / std::sqrt(1 / (dt_elements_ * dt_elements_) + 1 / (contact * contact));
    return std::min({cfl_ * combined, contact_step_factor * contact, particles_.stable_dt()});
  }
  // The contact springs' step as a fraction of their critical step 2/ω.
  static constexpr double contact_step_factor = 0.3;
  void step(double dt);
  // A distributed run: every rank's nodes and elements' erosion flags into the arrays of the
  // ranks `to` names — rank 0 for a checkpoint, which it writes; every rank for the energy
  // guard's message — as on one process. The elements' state fields stay in each rank's slots
  // (HexElements) and the particles' rows on their ranks: persist() gathers them into the
  // checkpoint one field at a time. The other ranks' arrays keep what they held. Collective;
  // nothing to do on one process.
  void gather_state(GatherTo to = GatherTo::every_rank);
  // A distributed run: when the decomposition's imbalance at the entities' current costs
  // (parallel/decomposition.hpp: current_costs of `reference`, the run's costs at t = 0; killed
  // particles and eroded elements cost nothing, a particle's neighbours are counted now, an
  // entity whose material point yields costs its return; each rank sums its own) exceeds
  // `threshold`, every rank learns where each entity is and what it costs, and the entities are
  // decomposed where they are now; each particle row, node and element state that changes rank
  // then goes whole from its old rank to its new ones (the state is not gathered). The per-entity
  // arithmetic is the same under any decomposition and the sums are exact, so the run stays the
  // single process's bit for bit. No cut is made when evening the ranks out would not pay for it
  // over as many steps as the current cut has served (parallel/decomposition.hpp: new_cut_pays),
  // checked before anything is gathered; kept when the new one would not be better. Collective;
  // nothing to do on one process.
  Rebalance rebalance(const Model& model, const EntityCosts& reference, double threshold);
  // Bytes this rank has sent to refresh other ranks' halos (0 on one process).
  long long halo_bytes() const;
  // A distributed run: what this rank receives of other ranks each step now — the particles'
  // halo rows (particles and background particles), the nodes of its elements that others own,
  // the background particles filled or returned across ranks — and what it owns — its
  // particles and nodes: the census's halo fraction (parallel/halo.hpp) counted on the run's own
  // share. Zero on one process.
  struct HaloShare {
    double halo = 0, own = 0;
  };
  HaloShare halo_share() const;
  // A distributed run: the elements this rank computes, ascending (empty on one process).
  std::span<const Index> own_elements() const {
    return subdomain_ ? std::span<const Index>(subdomain_->elements) : std::span<const Index>();
  }
  // Whether this rank keeps the state of a node, or of a particle row, current (always on one
  // process): its owner, which the history's probes read.
  bool owns_node(Index i) const { return !subdomain_ || subdomain_->owns_n[i]; }
  bool owns_row(Index row) const {
    const std::span<const unsigned char> owned = particles_.owned_rows();
    return owned.empty() || owned[row];
  }

  double time() const { return time_; }
  long long steps() const { return steps_; }

  const Nodes& nodes() const { return nodes_; }
  const HexElements& elements() const { return elements_; }
  const std::vector<Material>& materials() const { return materials_; } // by material index
  const NodeGather& node_gather() const { return gather_; }
  const ParticleSystem& particle_system() const { return particles_; }
  const Contact& contact() const { return contact_; }
  const std::vector<std::string>& body_names() const { return body_names_; }
  double initial_energy() const { return initial_energy_; } // J, E0 of the balance

  // The balances and the bodies' sums are exact sums (core/exact_sum.hpp) over the entities each
  // rank keeps current, summed over the ranks: the single process's bits at any rank count,
  // without gathering the state. Collective in a distributed run.
  Energies energies() const;
  // |E_kin + E_int + E_hg + E_contact + E_eroded + E_friction − W_ext − E_0| /
  // max(E_kin + E_int, |W_ext|, E_0).
  double balance_error(const Energies& e) const;
  // |Σ m v − P_0 − ∫F_ext dt| / max(|P_0|, Σ m |v_0|, Σ_steps |F_ext Δt|, tiny): the impulse
  // term gives a meaningful scale to bodies set in motion by loads alone.
  double momentum_drift() const;
  Vec3 momentum() const;
  std::vector<BodyTotals> bodies() const;

  // Checkpoint: time, step, the balances' accumulators and every node, element and particle
  // field; reading it into a simulation built from the same case and model continues that run
  // bit for bit, on any number of ranks. A distributed run writes after gather_state(), on
  // every rank together: rank 0 into the file, the others into a DiscardingArchive, each
  // element state field and particle field gathered on rank 0 as it is written. Collective then.
  void persist(StateArchive& a);

private:
  // f(i) for each node this rank steps (all on one process), in parallel.
  template <class F> void for_own_nodes(F f);
  // The nodes, elements and particle rows in [begin, end) whose state this rank keeps current
  // (all on one process).
  IndexRange own_nodes() const;
  IndexRange own_element_range() const;
  IndexRange own_rows(Index begin, Index end) const;
  // A distributed run whose contact surfaces follow erosion: when the elements eroded over all
  // ranks change in number, every rank learns each element's state (the elements a rank does
  // not compute keep old flags otherwise). Collective.
  void share_erosion();
  // The contact after the particle phase (dt: the step just taken, 0 at the start), on this
  // rank's rows in a distributed run. Collective then.
  void apply_contact(double dt);
  // The background particles' pair and contact forces into their nodes' f_int_n, from the rank
  // that stepped them (a distributed run: the nodes' ranks receive them first; collective).
  void return_background_forces();
  // `d` with the interface ties applied: a tied node goes with its particle, so that the tie's
  // merge is one rank's. (A background particle is stepped by the particles' cut — its pair
  // loops are particle-phase work — and filled by its node's rank.)
  Decomposition tied(Decomposition d) const;
  // This rank's share of a new cut `d`, tied, and the state that changes rank with it.
  // Collective.
  void take_share(Decomposition d, const Model& model);
  ParticleSystem::Migration migration(const Decomposition& d) const;
  // The elements' reference state (t = 0) in the slots of this rank's share (all on one
  // process). The background particles' first fill has read V_e, S_e and p_e whole; they are
  // cut to the share here.
  void reference_state();
  // The elements' state fields into the slots of the current share of `d` (HexElements) from
  // those of the share it replaces, `before` (a new cut): each element's from the rank that
  // computed it, one field at a time. Collective.
  void hold_element_state(const Subdomain& before, const Decomposition& d);
  // Each state field, given whole by element by whole_of(field) (skipped when that is empty),
  // cut to the slots of this rank's share: its elements, then the others' at its nodes.
  template <class WholeOf> void cut_element_state(WholeOf whole_of);
  // persist() of the elements' state fields: each gathered on rank 0 when writing, each rank's
  // slots taken from the whole field when reading.
  void persist_element_state(StateArchive& a);

  double cfl_;
  FemSpec fem_;
  std::vector<Material> materials_;
  std::vector<std::string> body_names_;
  Nodes nodes_;
  HexElements elements_;
  BackgroundParticles background_; // the FE nodes in the particle arrays (METHOD.md §4.1)
  ParticleSystem particles_;
  NodeGather gather_;
  Constraints constraints_;
  PressureLoads loads_;
  ParticleBoundaries particle_boundaries_;
  InterfaceTies ties_;
  Contact contact_;

  double time_ = 0;
  long long steps_ = 0;
  long long last_cut_step_ = 0; // the step of the last new cut (Simulation::rebalance)
  double dt_elements_ = 0;
  double dt_previous_ = 0;
  double external_work_ = 0;
  double friction_work_ = 0; // J, dissipated by contact friction
  double initial_energy_ = 0;
  Vec3 initial_momentum_ = Vec3::Zero();
  double momentum_scale_ = 0;
  Vec3 external_impulse_ = Vec3::Zero();
  double impulse_scale_ = 0;
  std::unique_ptr<Subdomain> subdomain_; // a distributed run's share; null on one process
  Decomposition decomposition_;          // of a distributed run, with the ties applied
  long long halo_bytes_ = 0;             // sent by the subdomains replaced by rebalancing
  double eroded_shared_ = -1;            // elements eroded over all ranks when last shared
};

} // namespace sphfem
