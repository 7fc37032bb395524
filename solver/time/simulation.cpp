#include "solver/time/simulation.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/fem/hex8.hpp"
#include "solver/fem/hex_update.hpp"
#include "solver/parallel/ranks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>

namespace sphfem {

namespace {

struct WorkAndImpulse {
  double work = 0;
  Vec3 impulse = Vec3::Zero();
  WorkAndImpulse& operator+=(const WorkAndImpulse& o) {
    work += o.work;
    impulse += o.impulse;
    return *this;
  }
};

} // namespace

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
  e.V_e.resize(ne);
  e.S_e.assign(ne, Mat3::Zero());
  e.p_e.assign(ne, 0.0);
  e.q_e.assign(ne, 0.0);
  e.e_int_e.assign(ne, 0.0);
  e.de_int_e.assign(ne, 0.0);
  e.e_hg_e.assign(ne, 0.0);
  e.f_e.resize(ne);
  e.point_e.resize(ne);
  e.eroded_e.assign(ne, 0);
  e.hg_e.assign(ne, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  e.hg_mode_e.assign(ne, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  for (Index k = 0; k < ne; ++k) {
    HexPoints x;
    for (int I = 0; I < 8; ++I)
      x[I] = model.x_n[model.hex_e[k][I]];
    const double V = hex8_gradient(x).volume;
    SPHFEM_CHECK(V > 0, "model.h5: element ", k, " has non-positive volume");
    e.material_e[k] = body_material[model.body_e[k]];
    e.V0_e[k] = e.V_e[k] = V;
    const Material& material = materials_[e.material_e[k]];
    e.mass_e[k] = material.elastic.density * V;
    e.point_e[k] = MaterialPoint::initial(material);
    e.inelastic = e.inelastic || material.inelastic();
    for (Index node : model.hex_e[k])
      nodes_.m_n[node] += e.mass_e[k] / 8.0;
  }
  for (Index i = 0; i < n; ++i)
    SPHFEM_CHECK(nodes_.m_n[i] > 0, "model.h5: node ", i, " belongs to no element");

  gather_ = NodeGather(e.nodes_e, n);
  constraints_ = Constraints(c, model);
  loads_ = PressureLoads(c, model);
  constraints_.apply_initial(nodes_.v_n);
  background_ = BackgroundParticles(model.background_nodes);
  particles_ = ParticleSystem(c, model, materials_, background_.size(), [&](Particles& p) {
    background_.initialise(c, model, materials_, p);
    background_.fill(nodes_, elements_, gather_, p);
  });
  particle_boundaries_ = ParticleBoundaries(c, model);
  ties_ = InterfaceTies(c, model);
  contact_ = Contact(c, model, particles_.particles(), background_, elements_);
  contact_.apply(particles_.particles(), particles_.neighbours(), particles_.rebuilds(), elements_,
                 0.0);

  dt_elements_ = update_hex_elements({nodes_.x_n, nodes_.v_n, 0.0}, materials_, fem_, elements_);
  background_.return_forces(particles_.particles(), nodes_.f_int_n);
  initial_energy_ = energies().total(); // kinetic, and contact energy if bodies start close
  initial_momentum_ = momentum();
  const auto& p = particles_.particles();
  momentum_scale_ =
      deterministic_sum(n, 0.0, [&](Index i) { return nodes_.m_n[i] * nodes_.v_n[i].norm(); }) +
      deterministic_sum(p.size(), 0.0, [&](Index i) { return p.m_p[i] * p.v_p[i].norm(); });
  if (decomposition != nullptr && decomposition->parts > 1)
    take_share(*decomposition, model);
}

void Simulation::take_share(Decomposition d, const Model& model) {
  // A tied node goes with its particle: the tie's merge is then one rank's. A background
  // particle is stepped by the particles' cut (its pair loops are particle-phase work) and
  // filled by its node's rank.
  for (Index k = 0; k < ties_.size(); ++k)
    d.tie(ties_.particle_id(k), ties_.node(k));
  if (subdomain_)
    halo_bytes_ += subdomain_->bytes_sent();
  subdomain_ = std::make_unique<Subdomain>(make_subdomain(d, model, ranks::rank()));
  particles_.distribute(d.part_p, d.part_b);
  decomposition_ = std::move(d);
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
  // The costs now, by model entity (particles are stored in cell order).
  const Particles& p = particles_.particles();
  const Index np = p.size(), ne = elements_.size();
  std::vector<int> neighbours(static_cast<std::size_t>(np));
  std::vector<unsigned char> live_p(static_cast<std::size_t>(np)), live_e(ne);
  for (Index i = 0; i < np; ++i) {
    neighbours[p.id_p[i]] = p.neighbours_p[i];
    live_p[p.id_p[i]] = p.kill_p[i] != Kill::Tension;
  }
  for (Index k = 0; k < ne; ++k)
    live_e[k] = elements_.eroded_e[k] == 0;
  const EntityCosts now = current_costs(reference, neighbours, live_p, live_e);
  r.before = r.after = phase_imbalance(decomposition_, now);
  if (!(r.before > threshold))
    return r;
  Model here = model; // the entities where they are now
  here.x_n = nodes_.x_n;
  for (Index i = 0; i < np; ++i)
    here.x_p[p.id_p[i]] = p.x_p[i];
  Decomposition d = decompose(here, now, decomposition_.parts);
  const double after = phase_imbalance(d, now);
  if (!(after < r.before))
    return r;
  take_share(std::move(d), model);
  r.after = after;
  r.done = true;
  return r;
}

template <class F> void Simulation::for_own_nodes(F f) {
  const IndexRange own = IndexRange::of(subdomain_ ? &subdomain_->nodes : nullptr, nodes_.size());
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

void Simulation::gather_state() {
  if (!subdomain_)
    return;
  subdomain_->all_nodes.refresh_each([this](auto visit) { nodes_.for_each_field(visit); });
  subdomain_->all_elements.refresh_each([this](auto visit) { elements_.for_each_field(visit); });
  particles_.gather_state();
}

void Simulation::step(double dt) {
  SPHFEM_CHECK(dt > 0 && std::isfinite(dt), "time step ", dt, " s at t = ", time_,
               " s is not positive: the run is unstable");
  auto& x = nodes_.x_n;
  auto& v = nodes_.v_n;
  auto& f = nodes_.f_int_n;
  const auto& m = nodes_.m_n;
  const Index n = nodes_.size();

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

  // The loads' and the constraints' work and impulse: over the nodes this rank owns, then
  // summed over the ranks in rank order.
  const std::span<const unsigned char> own =
      subdomain_ ? std::span<const unsigned char>(subdomain_->owns_n)
                 : std::span<const unsigned char>();
  WorkAndImpulse loaded;
  if (!loads_.empty())
    loaded = deterministic_sum(n, WorkAndImpulse{}, [&](Index i) {
      if (!own.empty() && !own[i])
        return WorkAndImpulse{};
      const Vec3& fe = nodes_.f_ext_n[i];
      const Vec3 v_old = v[i] - (dt_v / m[i]) * f[i];
      return WorkAndImpulse{dt_v * fe.dot(0.5 * (v_old + v[i])), dt_v * fe};
    });
  ReactionTotals reactions = constraints_.apply(time_ + 0.5 * dt, dt_v, m, f, v, own);
  if (subdomain_) {
    const std::array<double, 12> local{on_particles.work,
                                       on_particles.impulse.x(),
                                       on_particles.impulse.y(),
                                       on_particles.impulse.z(),
                                       loaded.work,
                                       loaded.impulse.x(),
                                       loaded.impulse.y(),
                                       loaded.impulse.z(),
                                       reactions.work,
                                       reactions.impulse.x(),
                                       reactions.impulse.y(),
                                       reactions.impulse.z()};
    const std::vector<double> total = ranks::sum_in_rank_order(local);
    on_particles = {total[0], Vec3(total[1], total[2], total[3])};
    loaded = {total[4], Vec3(total[5], total[6], total[7])};
    reactions = {total[8], Vec3(total[9], total[10], total[11])};
  }
  if (!particle_boundaries_.empty()) {
    external_work_ += on_particles.work;
    external_impulse_ += on_particles.impulse;
    impulse_scale_ += on_particles.impulse.norm();
  }
  if (!loads_.empty()) {
    external_work_ += loaded.work;
    external_impulse_ += loaded.impulse;
    impulse_scale_ += loaded.impulse.norm();
  }
  external_work_ += reactions.work;
  external_impulse_ += reactions.impulse;
  impulse_scale_ += reactions.impulse.norm();
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
  background_.fill(nodes_, elements_, gather_, particles_.particles());
  if (subdomain_)
    subdomain_->background_filled.refresh_each(
        [this](auto visit) { BackgroundParticles::visit_filled(particles_.particles(), visit); });
  particles_.update(dt);
  if (const std::vector<Index>* own = particles_.own_rows(); own != nullptr) {
    const ContactRanks ranks{own, particles_.owned_rows(), particles_.shares(),
                             [this](std::span<const Index> rows) { particles_.read_also(rows); }};
    contact_.apply(particles_.particles(), particles_.neighbours(), particles_.rebuilds(),
                   elements_, dt, &ranks);
  } else {
    contact_.apply(particles_.particles(), particles_.neighbours(), particles_.rebuilds(),
                   elements_, dt);
  }
  if (subdomain_)
    subdomain_->background_returned.refresh_each(
        [this](auto visit) { BackgroundParticles::visit_returned(particles_.particles(), visit); });
  background_.return_forces(particles_.particles(), f);
  time_ += dt;
  dt_previous_ = dt;
  ++steps_;
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
  elements_.for_each_field(
      [&a](const char* name, auto& field) { a.array(std::string("elements/") + name, field); });
  a.value("elements/inelastic", elements_.inelastic);
  particles_.persist(a);
  contact_.persist(a);
}

Energies Simulation::energies() const {
  Energies out;
  const auto& p = particles_.particles();
  out.kinetic = deterministic_sum(
                    nodes_.size(), 0.0,
                    [&](Index i) { return 0.5 * nodes_.m_n[i] * nodes_.v_n[i].squaredNorm(); }) +
                deterministic_sum(p.size(), 0.0,
                                  [&](Index i) { return 0.5 * p.m_p[i] * p.v_p[i].squaredNorm(); });
  // Kinetic energy is that of v^{n+½}; the internal energy is taken at the same half step,
  // half-way through the last stress update (else a vibrating body shows an energy
  // oscillation of relative size ω Δt / 2).
  // An eroded element's energy moves from internal and hourglass to eroded.
  const auto& e = elements_;
  const auto internal = [&](Index k) { return e.e_int_e[k] - 0.5 * e.de_int_e[k]; };
  out.internal =
      deterministic_sum(e.size(), 0.0, [&](Index k) { return e.eroded_e[k] ? 0.0 : internal(k); }) +
      deterministic_sum(p.size(), 0.0, [&](Index i) { return p.e_p[i] - 0.5 * p.de_p[i]; }) +
      background_.energy(particles_.particles());
  out.hourglass =
      deterministic_sum(e.size(), 0.0, [&](Index k) { return e.eroded_e[k] ? 0.0 : e.e_hg_e[k]; });
  out.eroded = deterministic_sum(
      e.size(), 0.0, [&](Index k) { return e.eroded_e[k] ? internal(k) + e.e_hg_e[k] : 0.0; });
  out.contact = contact_.energy(particles_.particles());
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
  return deterministic_sum(nodes_.size(), Vec3(Vec3::Zero()),
                           [&](Index i) -> Vec3 { return nodes_.m_n[i] * nodes_.v_n[i]; }) +
         deterministic_sum(p.size(), Vec3(Vec3::Zero()),
                           [&](Index i) -> Vec3 { return p.m_p[i] * p.v_p[i]; });
}

double Simulation::momentum_drift() const {
  const double scale = std::max({initial_momentum_.norm(), momentum_scale_, impulse_scale_,
                                 std::numeric_limits<double>::min()});
  return (momentum() - initial_momentum_ - external_impulse_).norm() / scale;
}

std::vector<BodyTotals> Simulation::bodies() const {
  // Per body: Σ m, Σ m v and ½ Σ m v² over its nodes and particles, and the internal energy of
  // its particles and elements (a masked deterministic sum each). The energy stored by the
  // attachment coupling (background particles) belongs to no body: the bodies' internal
  // energies add up to energy.internal less that.
  struct BodySums {
    double m = 0, kinetic = 0, internal = 0;
    Vec3 p = Vec3::Zero();
    BodySums& operator+=(const BodySums& o) {
      m += o.m;
      kinetic += o.kinetic;
      internal += o.internal;
      p += o.p;
      return *this;
    }
  };
  const auto& part = particles_.particles();
  const auto& e = elements_;
  std::vector<BodyTotals> out;
  for (int b = 0; b < static_cast<int>(body_names_.size()); ++b) {
    BodySums sum = deterministic_sum(nodes_.size(), BodySums{}, [&](Index i) {
      const double m = nodes_.m_n[i];
      const Vec3& v = nodes_.v_n[i];
      return nodes_.body_n[i] == b ? BodySums{m, 0.5 * m * v.squaredNorm(), 0, m * v} : BodySums{};
    });
    sum += deterministic_sum(part.size(), BodySums{}, [&](Index i) {
      const double m = part.m_p[i];
      const Vec3& v = part.v_p[i];
      return part.body_p[i] == b
                 ? BodySums{m, 0.5 * m * v.squaredNorm(), part.e_p[i] - 0.5 * part.de_p[i], m * v}
                 : BodySums{};
    });
    sum += deterministic_sum(e.size(), BodySums{}, [&](Index k) {
      return e.body_e[k] == b && !e.eroded_e[k]
                 ? BodySums{0, 0, e.e_int_e[k] - 0.5 * e.de_int_e[k], Vec3::Zero()}
                 : BodySums{};
    });
    const Vec3 contact = contact_.force_on(part, b);
    BodyTotals totals{body_names_[b], sum.m, sum.m > 0 ? Vec3(sum.p / sum.m) : Vec3(Vec3::Zero()),
                      contact};
    totals.kinetic = sum.kinetic;
    totals.internal = sum.internal;
    for (Index i = 0; i < part.size(); ++i)
      totals.killed_particles += part.body_p[i] == b && part.kill_p[i] != Kill::None;
    for (Index k = 0; k < elements_.size(); ++k)
      totals.eroded_elements += elements_.body_e[k] == b && elements_.eroded_e[k];
    out.push_back(totals);
  }
  return out;
}

} // namespace sphfem
