#include "solver/time/simulation.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/fem/hex8.hpp"
#include "solver/fem/hex_update.hpp"
#include "solver/material/material_point.hpp"
#include "solver/parallel/ranks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <type_traits>
#include <utility>

namespace sphfem {

Simulation::Simulation(const Case& c, const Model& model, const Decomposition* decomposition)
    : cfl_(c.time.cfl), fem_(c.fem), body_names_(model.body_names) {
  SPHFEM_CHECK(model.body_names.size() == c.bodies.size(),
               "model.h5 does not match the case (bodies differ): re-mesh");
  std::vector<int> body_material;
  for (const auto& body : c.bodies) {
    body_material.push_back(static_cast<int>(materials_.size()));
    materials_.push_back(Material::from(c.material(body.material)));
  }

  const Index n = model.node_count();
  nodes_.x0_n = model.x_n;
  nodes_.x_n = model.x_n;
  nodes_.body_n = model.body_n;
  nodes_.v_n.resize(n);
  nodes_.m_n.assign(n, 0.0);
  nodes_.f_int_n.assign(n, Vec3::Zero());
  nodes_.f_ext_n.assign(n, Vec3::Zero());
  for (Index i = 0; i < n; ++i)
    nodes_.v_n[i] = c.bodies[model.body_n[i]].velocity;

  // Elements: reference volume and mass; lumped (row-sum) mass, ρV/8 to each node.
  const Index ne = model.element_count();
  auto& e = elements_;
  e.nodes_e = model.hex_e;
  e.body_e = model.body_e;
  e.material_e.resize(ne);
  e.mass_e.resize(ne);
  e.V0_e.resize(ne);
  e.eroded_e.assign(ne, 0);
  for (Index k = 0; k < ne; ++k) {
    HexPoints x;
    for (int I = 0; I < 8; ++I)
      x[I] = model.x_n[model.hex_e[k][I]];
    const double V = hex8_gradient(x).volume;
    SPHFEM_CHECK(V > 0, "model.h5: element ", k, " has non-positive volume");
    e.material_e[k] = body_material[model.body_e[k]];
    e.V0_e[k] = V;
    const Material& material = materials_[e.material_e[k]];
    e.mass_e[k] = material.elastic.density * V;
    e.inelastic = e.inelastic || material.inelastic();
    for (Index node : model.hex_e[k])
      nodes_.m_n[node] += e.mass_e[k] / 8.0;
  }
  for (Index i = 0; i < n; ++i)
    SPHFEM_CHECK(nodes_.m_n[i] > 0, "model.h5: node ", i, " belongs to no element");
  // The background particles' first fill reads the volume and stress of every element around
  // their nodes: these three state fields are whole until then.
  e.V_e = e.V0_e;
  e.S_e.assign(ne, Mat3::Zero());
  e.p_e.assign(ne, 0.0);

  gather_ = NodeGather(e.nodes_e, n);
  constraints_ = Constraints(c, model);
  loads_ = PressureLoads(c, model);
  constraints_.apply_initial(nodes_.v_n);
  ties_ = InterfaceTies(c, model);
  if (decomposition != nullptr && decomposition->parts > 1) {
    // A distributed run: this rank's share of the nodes and elements, so that it holds the
    // state of only the elements it computes or reads from the start.
    decomposition_ = tied(*decomposition);
    subdomain_ = std::make_unique<Subdomain>(make_subdomain(decomposition_, model, ranks::rank()));
  }
  background_ = BackgroundParticles(model.background_nodes);
  // A distributed run's particle phase starts in distribute(): each rank lists, moves and
  // pushes only the rows it steps from the first step on.
  particles_ = ParticleSystem(
      c, model, materials_, background_.size(),
      [&](Particles& p) {
        background_.initialise(c, model, materials_, p);
        background_.fill(nodes_, elements_, gather_, p);
      },
      subdomain_ != nullptr);
  particle_boundaries_ = ParticleBoundaries(c, model);
  contact_ = Contact(c, model, particles_.particles(), background_, elements_);
  reference_state();
  const auto& p = particles_.particles(); // every row until distributed
  momentum_scale_ =
      deterministic_sum(n, 0.0, [&](Index i) { return nodes_.m_n[i] * nodes_.v_n[i].norm(); }) +
      deterministic_sum(p.size(), 0.0, [&](Index i) { return p.m_p[i] * p.v_p[i].norm(); });
  if (subdomain_)
    particles_.distribute(decomposition_.part_p, decomposition_.part_b, subdomain_->background,
                          contact_.reads_lists_of_nearby_background_rows(),
                          migration(decomposition_));
  apply_contact(0.0);

  const std::vector<Index>* computed = subdomain_ ? &subdomain_->elements : nullptr;
  dt_elements_ =
      update_hex_elements({nodes_.x_n, nodes_.v_n, 0.0, computed}, materials_, fem_, elements_);
  if (subdomain_)
    dt_elements_ = ranks::min(dt_elements_);
  return_background_forces();
  initial_energy_ = energies().total(); // kinetic, and contact energy if bodies start close
  initial_momentum_ = momentum();
}

void Simulation::reference_state() {
  auto& e = elements_;
  if (subdomain_) // V_e, S_e and p_e are whole; the other fields are made for the share
    cut_element_state([](auto& field) { return std::exchange(field, {}); });
  const auto count = subdomain_ ? e.V_e.size() : static_cast<std::size_t>(e.size());
  e.q_e.assign(count, 0.0);
  e.e_int_e.assign(count, 0.0);
  e.de_int_e.assign(count, 0.0);
  e.e_hg_e.assign(count, 0.0);
  e.hg_e.assign(count, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  e.hg_mode_e.assign(count, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  std::array<Vec3, 8> no_force;
  no_force.fill(Vec3::Zero());
  e.f_e.assign(count, no_force);
  e.point_e.resize(count);
  for (Index k = 0; k < e.size(); ++k)
    if (const Index s = e.slot(k); s >= 0)
      e.point_e[s] = MaterialPoint::initial(materials_[e.material_e[k]]);
}

// Particles follow the particles' regions of the cut between cuts; tied ones stay with their
// nodes' rank.
ParticleSystem::Migration Simulation::migration(const Decomposition& d) const {
  Decomposition regions; // the regions alone
  regions.parts = d.parts;
  regions.particle_regions = d.particle_regions;
  std::vector<unsigned char> pinned(d.part_p.size(), 0);
  for (Index k = 0; k < ties_.size(); ++k)
    pinned[ties_.particle_id(k)] = 1;
  return {[regions](const Vec3& x, int current, double slack) {
            return regions.particle_part_at(x, current, slack);
          },
          std::move(pinned)};
}

Decomposition Simulation::tied(Decomposition d) const {
  for (Index k = 0; k < ties_.size(); ++k)
    d.tie(ties_.particle_id(k), ties_.node(k));
  return d;
}

void Simulation::take_share(Decomposition d, const Model& model) {
  d = tied(std::move(d));
  if (subdomain_)
    halo_bytes_ += subdomain_->bytes_sent();
  const std::unique_ptr<Subdomain> before = std::move(subdomain_);
  subdomain_ = std::make_unique<Subdomain>(make_subdomain(d, model, ranks::rank()));
  hold_element_state(*before, d);
  // The nodes that change rank, each whole from its old owner.
  const int me = ranks::rank();
  std::vector<std::vector<Index>> moves(static_cast<std::size_t>(ranks::size()));
  for (const Index i : before->nodes)
    if (d.part_n[i] != me)
      moves[d.part_n[i]].push_back(i);
  HaloExchange::pushed(std::move(moves)).refresh_by_field([this](auto visit) {
    nodes_.for_each_field(visit);
  });
  particles_.distribute(d.part_p, d.part_b, subdomain_->background,
                        contact_.reads_lists_of_nearby_background_rows(), migration(d));
  decomposition_ = std::move(d);
}

namespace {

// An element state field during a new cut, by element: read from the old slots of the elements
// this rank computed (the first `old_own` slots), written into the new slots of the others.
template <class T> struct CutSlots {
  std::vector<T>& old_values;
  const std::vector<Index>& old_slot;
  Index old_own;
  std::vector<T>& new_values;
  const std::vector<Index>& new_slot;
  T& operator[](Index k) const {
    const Index s = old_slot[k];
    return s >= 0 && s < old_own ? old_values[s] : new_values[new_slot[k]];
  }
};
template <class T>
CutSlots(std::vector<T>&, const std::vector<Index>&, Index, std::vector<T>&,
         const std::vector<Index>&) -> CutSlots<T>;

} // namespace

template <class WholeOf> void Simulation::cut_element_state(WholeOf whole_of) {
  auto& e = elements_;
  std::vector<Index> held = subdomain_->elements;
  held.insert(held.end(), subdomain_->foreign_elements.begin(), subdomain_->foreign_elements.end());
  e.for_each_state_field([&](const char*, auto& field) {
    const auto whole = whole_of(field);
    if (whole.empty())
      return;
    std::remove_cvref_t<decltype(whole)> mine(held.size());
    for (std::size_t s = 0; s < held.size(); ++s)
      mine[s] = whole[held[s]];
    field.swap(mine);
  });
  e.slot_e.assign(static_cast<std::size_t>(e.size()), -1);
  for (std::size_t s = 0; s < held.size(); ++s)
    e.slot_e[held[s]] = static_cast<Index>(s);
}

void Simulation::hold_element_state(const Subdomain& before, const Decomposition& d) {
  auto& e = elements_;
  const int me = ranks::rank();
  std::vector<Index> held = subdomain_->elements;
  held.insert(held.end(), subdomain_->foreign_elements.begin(), subdomain_->foreign_elements.end());
  std::vector<Index> slot(static_cast<std::size_t>(e.size()), -1);
  for (std::size_t s = 0; s < held.size(); ++s)
    slot[held[s]] = static_cast<Index>(s);
  // Each element this rank computed goes to the ranks holding it now: the one computing it and
  // those owning one of its nodes.
  std::vector<std::vector<Index>> sends(static_cast<std::size_t>(ranks::size()));
  for (const Index k : before.elements) {
    std::array<int, 9> holders;
    holders[0] = d.part_e[k];
    for (int I = 0; I < 8; ++I)
      holders[I + 1] = d.part_n[e.nodes_e[k][I]];
    std::ranges::sort(holders);
    for (int I = 0; I < 9; ++I)
      if (holders[I] != me && (I == 0 || holders[I] != holders[I - 1]))
        sends[holders[I]].push_back(k);
  }
  HaloExchange moves = HaloExchange::pushed(std::move(sends));
  const auto old_own = static_cast<Index>(before.elements.size());
  e.for_each_state_field([&](const char*, auto& field) {
    std::remove_reference_t<decltype(field)> mine(held.size());
    for (std::size_t s = 0; s < held.size(); ++s)
      if (const Index was = e.slot_e[held[s]]; was >= 0 && was < old_own)
        mine[s] = field[was];
    CutSlots view{field, e.slot_e, old_own, mine, slot};
    moves.refresh(view);
    field.swap(mine);
  });
  e.slot_e = std::move(slot);
}

Simulation::HaloShare Simulation::halo_share() const {
  if (!subdomain_)
    return {};
  const auto own_particles = Index(particles_.own_real_rows().size());
  // As the census counts them: a background particle stepped here but filled on its node's
  // rank is a ghost point here, and a foreign node there (its force returns).
  const Subdomain& s = *subdomain_;
  return {double(particles_.halo_row_count() + Index(s.halo_nodes.size()) +
                 Index(s.background_filled.received() + s.background_returned.received())),
          double(own_particles + Index(s.nodes.size()))};
}

long long Simulation::halo_bytes() const {
  if (!subdomain_)
    return 0;
  return halo_bytes_ + subdomain_->bytes_sent() + particles_.halo_bytes();
}

Rebalance Simulation::rebalance(const Model& model, const EntityCosts& reference,
                                double threshold) {
  Rebalance r;
  if (!subdomain_)
    return r;
  // This rank's cost per step in each phase now, over what it steps, and every rank's.
  const Particles& p = particles_.particles();
  double particle_cost = 0, element_cost = 0;
  const IndexRange real = own_rows(0, p.size()), attached = own_rows(p.size(), p.rows());
  const auto yields_p = [&](Index i) -> unsigned char {
    return yielding(materials_[p.material_p[i]], p.S_p[i], p.point_p[i]);
  };
  const HexElements& e = elements_;
  const auto yields_e = [&](Index k) -> unsigned char {
    return yielding(materials_[e.material_e[k]], e.S_e[e.slot(k)], e.point_e[e.slot(k)]);
  };
  for (Index k = 0; k < real.count; ++k)
    if (p.kill_p[real[k]] != Kill::Tension)
      particle_cost += live_particle_cost(p.neighbours_p[real[k]], yields_p(real[k]));
  for (Index k = 0; k < attached.count; ++k)
    particle_cost += reference.background[p.background_particle(attached[k])];
  for (const Index k : subdomain_->elements)
    element_cost += e.eroded_e[k] == 0 ? live_element_cost(reference.element[k], yields_e(k)) : 0;
  const std::vector<double> each = ranks::gather_all(std::array{particle_cost, element_cost});
  PhaseCosts phases;
  for (std::size_t q = 0; q < each.size(); q += 2) {
    phases.particle.push_back(each[q]);
    phases.element.push_back(each[q + 1]);
  }
  r.before = r.after = phase_imbalance(phases);
  if (!(r.before > threshold))
    return r;
  if (!new_cut_pays(phases, steps_ - last_cut_step_, model.x_p.size() + model.hex_e.size()))
    return r;
  // What the bisection reads of every entity, from its owner: a particle's position, neighbour
  // count, kill state and whether it yields; a node's position; an element's erosion and
  // whether it yields. By model entity (through id_p: a row's own id but in an old checkpoint).
  // The rest of the state moves only with a new cut (take_share).
  Particles& rows = particles_.particles();
  std::vector<unsigned char> yielding_row(static_cast<std::size_t>(p.rows()), 0);
  for (Index k = 0; k < real.count; ++k)
    yielding_row[real[k]] = yields_p(real[k]);
  constexpr GatherTo every_rank = GatherTo::every_rank;
  std::vector<Vec3> x_p = particles_.by_model_id(rows.x_p, every_rank);
  const std::vector<int> neighbours = particles_.by_model_id(rows.neighbours_p, every_rank);
  const std::vector<Kill> kill_p = particles_.by_model_id(rows.kill_p, every_rank);
  const std::vector<unsigned char> yielding_p = particles_.by_model_id(yielding_row, every_rank);
  HaloExchange::gather(decomposition_.part_n, every_rank).refresh(nodes_.x_n);
  const Index np = model.particle_count(), ne = e.size();
  std::vector<unsigned char> live_p(static_cast<std::size_t>(np)), live_e(ne), yielding_e(ne);
  for (Index i = 0; i < np; ++i)
    live_p[i] = kill_p[i] != Kill::Tension;
  for (const Index k : subdomain_->elements)
    yielding_e[k] = yields_e(k);
  subdomain_->all_elements.refresh(elements_.eroded_e, yielding_e);
  subdomain_->all_elements.release();
  for (Index k = 0; k < ne; ++k)
    live_e[k] = e.eroded_e[k] == 0;
  const EntityCosts now =
      current_costs(reference, neighbours, live_p, live_e, yielding_p, yielding_e);
  Model here = model; // the entities where they are now
  here.x_n = nodes_.x_n;
  here.x_p = std::move(x_p);
  Decomposition d = decompose(here, now, decomposition_.parts);
  const double after = phase_imbalance(d, now);
  if (!(after < r.before))
    return r;
  take_share(std::move(d), model);
  last_cut_step_ = steps_;
  r.after = after;
  r.done = true;
  return r;
}

template <class F> void Simulation::for_own_nodes(F f) {
  const IndexRange own = own_nodes();
#pragma omp parallel for schedule(static) if (own.count > parallel_min_items)
  for (Index j = 0; j < own.count; ++j)
    f(own[j]);
}

void Simulation::share_erosion() {
  double mine = 0;
  for (const Index k : subdomain_->elements)
    mine += elements_.eroded_e[k] != 0;
  const double eroded = ranks::sum_in_rank_order(std::array{mine})[0];
  if (eroded == eroded_shared_)
    return;
  subdomain_->all_elements.refresh(elements_.eroded_e);
  eroded_shared_ = eroded;
}

void Simulation::gather_state(GatherTo to) {
  if (!subdomain_)
    return;
  HaloExchange::gather(decomposition_.part_n, to).refresh_by_field([this](auto visit) {
    nodes_.for_each_field(visit);
  });
  subdomain_->all_elements.refresh(elements_.eroded_e);
  // Its buffers are not needed until the next checkpoint or new cut.
  subdomain_->all_elements.release();
}

void Simulation::step(double dt) {
  SPHFEM_CHECK(dt > 0 && std::isfinite(dt), "time step ", dt, " s at t = ", time_,
               " s is not positive: the run is unstable");
  auto& x = nodes_.x_n;
  auto& v = nodes_.v_n;
  auto& f = nodes_.f_int_n;
  const auto& m = nodes_.m_n;

  // Velocities live at half steps, so with a varying step they advance over the mean of the
  // two neighbouring position steps (½Δt on the first step, which starts from v⁰ at t = 0).
  // When the step shrinks (a shock arrives) the mean would exceed the new stability limit,
  // so it is capped at the new step.
  const double dt_v = steps_ == 0 ? 0.5 * dt : std::min(0.5 * (dt_previous_ + dt), dt);

  // Total nodal force at tⁿ: element forces plus loads (kept in f_int_n for this phase).
  if (!loads_.empty()) {
    loads_.apply(time_, x, nodes_.f_ext_n);
    for_own_nodes([&](Index i) { f[i] += nodes_.f_ext_n[i]; });
  }
  for_own_nodes([&](Index i) { v[i] += (dt_v / m[i]) * f[i]; });
  particles_.kick(dt_v);
  friction_work_ += dt_v * contact_.friction_power(); // friction's forces act over this kick
  // The symmetry planes' push on the particles is an external reaction (the mirrored half).
  const Vec3 mirror_impulse = dt_v * particles_.mirror_force();
  external_impulse_ += mirror_impulse;
  impulse_scale_ += mirror_impulse.norm();
  const auto index_of = [this](Index id) { return particles_.index_of(id); };
  ties_.merge(particles_.particles(), nodes_, index_of);
  ReactionTotals on_particles;
  if (!particle_boundaries_.empty())
    on_particles = particle_boundaries_.apply(time_, time_ + 0.5 * dt, dt_v, particles_);

  // The loads' and the constraints' work and impulse: exact sums over the nodes and particles
  // this rank owns, then over the ranks (the single process's bits).
  const std::span<const unsigned char> own =
      subdomain_ ? std::span<const unsigned char>(subdomain_->owns_n)
                 : std::span<const unsigned char>();
  ReactionTotals loaded;
  if (!loads_.empty())
    loaded.sums = exact_sums<4>(own_nodes(), [&](Index i) {
      const Vec3& fe = nodes_.f_ext_n[i];
      const Vec3 v_old = v[i] - (dt_v / m[i]) * f[i];
      const Vec3 impulse = dt_v * fe;
      return std::array{dt_v * fe.dot(0.5 * (v_old + v[i])), impulse.x(), impulse.y(), impulse.z()};
    });
  ReactionTotals reactions = constraints_.apply(time_ + 0.5 * dt, dt_v, m, f, v, own);
  if (subdomain_) {
    ExactSums<12> all;
    for (int k = 0; k < 4; ++k)
      all[k] = on_particles.sums[k], all[4 + k] = loaded.sums[k], all[8 + k] = reactions.sums[k];
    ranks::sum_exactly(all);
    for (int k = 0; k < 4; ++k)
      on_particles.sums[k] = all[k], loaded.sums[k] = all[4 + k], reactions.sums[k] = all[8 + k];
  }
  const auto account = [this](const ReactionTotals& t) {
    const Vec3 impulse = t.impulse();
    external_work_ += t.work();
    external_impulse_ += impulse;
    impulse_scale_ += impulse.norm();
  };
  if (!particle_boundaries_.empty())
    account(on_particles);
  if (!loads_.empty())
    account(loaded);
  account(reactions);
  ties_.follow(particles_.particles(), nodes_, index_of);

  for_own_nodes([&](Index i) { x[i] += dt * v[i]; });
  if (subdomain_)
    subdomain_->halo.refresh(x, v);

  particles_.drift(dt);

  if (subdomain_) {
    dt_elements_ = ranks::min(
        update_hex_elements({x, v, dt, &subdomain_->elements}, materials_, fem_, elements_));
    subdomain_->element_forces.refresh_each(
        [this](auto visit) { elements_.for_each_nodal_field(visit); });
    gather_.gather_forces(elements_, f, &subdomain_->nodes);
    if (contact_.follows_erosion())
      share_erosion();
  } else {
    dt_elements_ = update_hex_elements({x, v, dt}, materials_, fem_, elements_);
    gather_.gather_forces(elements_, f);
  }
  const std::vector<Index>* filled_here = subdomain_ ? &subdomain_->background : nullptr;
  background_.fill(nodes_, elements_, gather_, particles_.particles(), filled_here);
  if (subdomain_)
    subdomain_->background_filled.refresh_each(
        [this](auto visit) { BackgroundParticles::visit_filled(particles_.particles(), visit); });
  particles_.update(dt);
  apply_contact(dt);
  return_background_forces();
  time_ += dt;
  dt_previous_ = dt;
  ++steps_;
}

void Simulation::apply_contact(double dt) {
  if (const std::vector<Index>* own = particles_.own_rows(); own != nullptr) {
    const ContactRanks ranks{own, particles_.owned_rows(), particles_.shares(),
                             [this](std::span<const Index> rows) { particles_.read_also(rows); }};
    contact_.apply(particles_.particles(), particles_.neighbours(), particles_.list_builds(),
                   elements_, dt, &ranks);
  } else {
    contact_.apply(particles_.particles(), particles_.neighbours(), particles_.list_builds(),
                   elements_, dt);
  }
}

void Simulation::return_background_forces() {
  if (subdomain_)
    subdomain_->background_returned.refresh_each(
        [this](auto visit) { BackgroundParticles::visit_returned(particles_.particles(), visit); });
  background_.return_forces(particles_.particles(), nodes_.f_int_n,
                            subdomain_ ? &subdomain_->background : nullptr);
}

void Simulation::persist(StateArchive& a) {
  a.value("simulation/time", time_);
  a.value("simulation/steps", steps_);
  a.value("simulation/dt_elements", dt_elements_);
  a.value("simulation/dt_previous", dt_previous_);
  a.value("simulation/external_work", external_work_);
  a.value("simulation/friction_work", friction_work_);
  a.value("simulation/initial_energy", initial_energy_);
  a.value("simulation/initial_momentum", initial_momentum_);
  a.value("simulation/momentum_scale", momentum_scale_);
  a.value("simulation/external_impulse", external_impulse_);
  a.value("simulation/impulse_scale", impulse_scale_);
  nodes_.for_each_field(
      [&a](const char* name, auto& field) { a.array(std::string("nodes/") + name, field); });
  elements_.for_each_mesh_field(
      [&a](const char* name, auto& field) { a.array(std::string("elements/") + name, field); });
  persist_element_state(a);
  a.value("elements/inelastic", elements_.inelastic);
  particles_.persist(a);
  contact_.persist(a);
}

void Simulation::persist_element_state(StateArchive& a) {
  auto& e = elements_;
  const auto name_of = [](const char* name) { return std::string("elements/") + name; };
  if (!subdomain_) {
    e.for_each_state_field([&](const char* name, auto& field) { a.array(name_of(name), field); });
    return;
  }
  const Index ne = e.size();
  if (a.reading()) { // the whole field, of which this rank keeps its slots
    e.for_each_state_field([&](const char* name, auto& field) {
      std::remove_reference_t<decltype(field)> whole, mine(field.size());
      a.array(name_of(name), whole);
      for (Index k = 0; k < ne; ++k)
        if (e.slot_e[k] >= 0)
          mine[e.slot_e[k]] = whole[k];
      field.swap(mine);
    });
    return;
  }
  // Rank 0 receives every other rank's elements, one field at a time, and writes the field.
  const bool writer = ranks::rank() == 0;
  std::vector<Index> every;
  if (writer) {
    every.resize(static_cast<std::size_t>(ne));
    std::iota(every.begin(), every.end(), Index{0});
  }
  HaloExchange to_writer(decomposition_.part_e, every);
  e.for_each_state_field([&](const char* name, auto& field) {
    std::remove_reference_t<decltype(field)> whole;
    if (writer) {
      whole.resize(static_cast<std::size_t>(ne));
      for (const Index k : subdomain_->elements)
        whole[k] = field[e.slot(k)];
      to_writer.refresh(whole);
    } else {
      BySlot mine{field, e.slot_e};
      to_writer.refresh(mine);
    }
    a.array(name_of(name), whole);
  });
}

IndexRange Simulation::own_nodes() const {
  return IndexRange::of(subdomain_ ? &subdomain_->nodes : nullptr, nodes_.size());
}

IndexRange Simulation::own_element_range() const {
  return IndexRange::of(subdomain_ ? &subdomain_->elements : nullptr, elements_.size());
}

IndexRange Simulation::own_rows(Index begin, Index end) const {
  return IndexRange::of(particles_.own_rows(), begin, end);
}

Energies Simulation::energies() const {
  const auto& p = particles_.particles();
  const auto& n = nodes_;
  const auto& e = elements_;
  // Kinetic energy is that of v^{n+½}; the internal energy is taken at the same half step,
  // half-way through the last stress update (else a vibrating body shows an energy
  // oscillation of relative size ω Δt / 2).
  // An eroded element's energy moves from internal and hourglass to eroded.
  ExactSums<5> sum; // kinetic, internal, hourglass, eroded, contact
  add_to(sum, exact_sums<5>(own_nodes(), [&](Index i) {
           return std::array{0.5 * n.m_n[i] * n.v_n[i].squaredNorm(), 0.0, 0.0, 0.0, 0.0};
         }));
  add_to(sum, exact_sums<5>(own_rows(0, p.size()), [&](Index i) {
           return std::array{0.5 * p.m_p[i] * p.v_p[i].squaredNorm(), p.e_p[i] - 0.5 * p.de_p[i],
                             0.0, 0.0, 0.0};
         }));
  add_to(sum, exact_sums<5>(own_element_range(), [&](Index k) {
           const Index s = e.slot(k);
           const double internal = e.e_int_e[s] - 0.5 * e.de_int_e[s];
           return e.eroded_e[k] ? std::array{0.0, 0.0, 0.0, internal + e.e_hg_e[s], 0.0}
                                : std::array{0.0, internal, e.e_hg_e[s], 0.0, 0.0};
         }));
  sum[1] += background_.energy(p, own_rows(p.size(), p.rows()));
  sum[4] += contact_.energy(p, own_rows(0, p.rows()));
  if (subdomain_)
    ranks::sum_exactly(sum);
  Energies out;
  out.kinetic = sum[0].value();
  out.internal = sum[1].value();
  out.hourglass = sum[2].value();
  out.eroded = sum[3].value();
  out.contact = sum[4].value();
  out.friction = friction_work_;
  out.external_work = external_work_;
  return out;
}

double Simulation::balance_error(const Energies& e) const {
  const double scale =
      std::max({e.kinetic + e.internal, std::abs(e.external_work), initial_energy_});
  if (scale == 0)
    return 0;
  return std::abs(e.total() - e.external_work - initial_energy_) / scale;
}

Vec3 Simulation::momentum() const {
  const auto& p = particles_.particles();
  const auto& n = nodes_;
  ExactSums<3> sum = exact_sums<3>(own_nodes(), [&](Index i) {
    const Vec3 q = n.m_n[i] * n.v_n[i];
    return std::array{q.x(), q.y(), q.z()};
  });
  add_to(sum, exact_sums<3>(own_rows(0, p.size()), [&](Index i) {
           const Vec3 q = p.m_p[i] * p.v_p[i];
           return std::array{q.x(), q.y(), q.z()};
         }));
  if (subdomain_)
    ranks::sum_exactly(sum);
  return {sum[0].value(), sum[1].value(), sum[2].value()};
}

double Simulation::momentum_drift() const {
  const double scale = std::max({initial_momentum_.norm(), momentum_scale_, impulse_scale_,
                                 std::numeric_limits<double>::min()});
  return (momentum() - initial_momentum_ - external_impulse_).norm() / scale;
}

std::vector<BodyTotals> Simulation::bodies() const {
  // Per body: Σ m, ½ Σ m v², Σ m v over its nodes and particles, the internal energy of its
  // particles and live elements, the contact force on it, its killed particles and eroded
  // elements — exact sums over what each rank keeps current. The energy stored by the attachment
  // coupling (background particles) belongs to no body: the bodies' internal energies add up to
  // energy.internal less that.
  constexpr std::size_t K = 11; // m, kinetic, internal, m v (3), contact force (3), killed, eroded
  const auto& part = particles_.particles();
  const auto& n = nodes_;
  const auto& e = elements_;
  const auto body_count = body_names_.size();
  std::vector<ExactSum> sum(K * body_count);
  for (std::size_t b = 0; b < body_count; ++b) {
    const int body = static_cast<int>(b);
    ExactSums<K> s = exact_sums<K>(own_nodes(), [&](Index i) {
      const double m = n.m_n[i];
      const Vec3& v = n.v_n[i];
      if (n.body_n[i] != body)
        return std::array<double, K>{};
      return std::array<double, K>{
          m, 0.5 * m * v.squaredNorm(), 0, m * v.x(), m * v.y(), m * v.z(), 0, 0, 0, 0, 0};
    });
    add_to(s, exact_sums<K>(own_rows(0, part.size()), [&](Index i) {
             const double m = part.m_p[i];
             const Vec3& v = part.v_p[i];
             if (part.body_p[i] != body)
               return std::array<double, K>{};
             return std::array<double, K>{m,
                                          0.5 * m * v.squaredNorm(),
                                          part.e_p[i] - 0.5 * part.de_p[i],
                                          m * v.x(),
                                          m * v.y(),
                                          m * v.z(),
                                          0,
                                          0,
                                          0,
                                          part.kill_p[i] != Kill::None ? 1.0 : 0.0,
                                          0};
           }));
    add_to(s, exact_sums<K>(own_element_range(), [&](Index k) {
             if (e.body_e[k] != body)
               return std::array<double, K>{};
             if (e.eroded_e[k])
               return std::array<double, K>{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1.0};
             const Index slot = e.slot(k);
             return std::array<double, K>{0, 0, e.e_int_e[slot] - 0.5 * e.de_int_e[slot]};
           }));
    const ExactSums<3> contact = contact_.force_on(part, body, own_rows(0, part.rows()));
    for (std::size_t j = 0; j < 3; ++j)
      s[6 + j] += contact[j];
    std::copy(s.begin(), s.end(), sum.begin() + static_cast<std::ptrdiff_t>(K * b));
  }
  if (subdomain_)
    ranks::sum_exactly(sum);
  std::vector<BodyTotals> out;
  for (std::size_t b = 0; b < body_count; ++b) {
    const auto value = [&](std::size_t j) { return sum[K * b + j].value(); };
    const double mass = value(0);
    const Vec3 momentum(value(3), value(4), value(5));
    BodyTotals totals{body_names_[b], mass, mass > 0 ? Vec3(momentum / mass) : Vec3(Vec3::Zero()),
                      Vec3(value(6), value(7), value(8))};
    totals.kinetic = value(1);
    totals.internal = value(2);
    totals.killed_particles = static_cast<Index>(value(9));
    totals.eroded_elements = static_cast<Index>(value(10));
    out.push_back(totals);
  }
  return out;
}

} // namespace sphfem
