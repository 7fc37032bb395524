#include "solver/sph/particle_system.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/parallel/ranks.hpp"
#include "solver/sph/sph_update.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem {

ParticleSystem::ParticleSystem(const Case& c, const Model& model,
                               const std::vector<Material>& materials, Index attached,
                               const AttachRows& attach, bool distributed)
    : spec_(c.sph), materials_(materials), mirror_(c),
      dt_stable_(std::numeric_limits<double>::infinity()) {
  const Index n = model.particle_count(), total = n + attached;
  if (total == 0)
    return;
  SPHFEM_CHECK(attached == 0 || attach, "attached rows need their filler (internal error)");
  const std::vector<int> group = c.body_groups();
  auto& p = particles_;
  p.real = n;
  p.background = attached;
  p.for_each_field([total](const char*, auto& field) { field.resize(total); });
  for (Index i = 0; i < n; ++i) {
    const int body = model.body_p[i];
    SPHFEM_CHECK(body >= 0 && body < static_cast<int>(c.bodies.size()), "model.h5: particle ", i,
                 " has body id ", body);
    p.start_row(i, {model.x_p[i], c.bodies[body].velocity, model.m_p[i], model.rho_p[i],
                    model.h_p[i], model.spacing_b[body], body, group[body], i,
                    MaterialPoint::initial(materials[body])});
    p.inelastic = p.inelastic || materials[body].inelastic();
  }
  if (attached > 0)
    attach(p);
  double largest_h = 0;
  for (Index i = 0; i < total; ++i)
    largest_h = std::max(largest_h, p.h_p[i]);
  skin_ = spec_.skin * 2.0 * largest_h;
  index_of_id_.resize(n);
  for (Index k = 0; k < n; ++k)
    index_of_id_[p.id_p[k]] = k;
  if (!distributed)
    start();
}

void ParticleSystem::start() {
  auto& p = particles_;
  rebuild();
  if (distributed_)
    share();
  sph_kinematics(p, search_.list(), spec_, 0.0, own_rows(), visible_rows());
  if (share_)
    share_->halo.refresh_each([&p](auto visit) { p.for_each_updated_field(visit); });
  mirror_.refresh_stress(p, p.rows(), visible_rows());
  forces(0.0);
}

// Twice the largest real particle's h of `h` (a distributed run's rows are current on their
// owner: the largest over the ranks, unless `whole`), plus the skin: how near a plane a row gets
// mirror images.
double ParticleSystem::mirror_reach(std::span<const double> h, bool whole) const {
  double largest_h = 0;
  if (share_ && !whole) {
    for (const Index i : own_real_rows())
      largest_h = std::max(largest_h, h[i]);
    largest_h = ranks::max(largest_h);
  } else {
    for (Index i = 0; i < particles_.size(); ++i)
      largest_h = std::max(largest_h, h[i]);
  }
  return 2.0 * largest_h + skin_;
}

// The images of the rows at x (those binned_ marks, else all) within reach of a plane; the
// arrays resized for them, their state made from their sources' now.
void ParticleSystem::place_mirrors(std::span<const Vec3> x, double reach) {
  if (mirror_.empty())
    return;
  auto& p = particles_;
  mirror_.select(p, x, reach, binned_);
  const Index total = p.rows() + mirror_.size();
  // Room for a sixteenth more rows than now, not the vector's doubling: a row is ≈ 0.9 KB,
  // and the images are a fraction of the rows (the Børvik quarter: 2 301 of 13 392 rows).
  const auto room = static_cast<std::size_t>(total + total / 16);
  p.for_each_field([total, room](const char*, auto& field) {
    if (field.capacity() < static_cast<std::size_t>(total))
      field.reserve(room);
    field.resize(total);
  });
  if (!binned_.empty())
    binned_.resize(total, 1); // the images of binned rows
  mirror_.refresh_motion(p, p.rows());
  mirror_.refresh_stress(p, p.rows());
}

// The rows keep the model's order (see the header): the lists' rows are sorted by it. A
// distributed run's rank bins its own rows and those near them (receive_neighbourhood).
void ParticleSystem::rebuild() {
  auto& p = particles_;
  if (distributed_)
    receive_neighbourhood();
  place_mirrors(p.x_p, mirror_.empty() ? 0.0 : mirror_reach(p.h_p, false));
  mark_listed();
  search_.build(p.x_p, p.h_p, skin_, listed());
  ++rebuilds_;
  ++list_builds_;
}

// The positions and smoothing lengths of the rows that a rebuild's lists of this rank's rows can
// hold, from their owners: the rows within a cutoff C = 2 max h + skin of its own rows' box, or
// with a mirror image there; marks them and its own rows in binned_. With the surface contact,
// the lists of some background rows too (coupling/contact.hpp): a slave evaluated here lies
// within C of a corner of a face with an own corner, its other faces' corners within C of it,
// and a face spans less than 2C (at most 2.5 h of its corners: the contact's stretch allowance),
// so every corner it reads lies within 4C of an own row. near_if_listed_ marks the background
// rows within 4C of the box, and the rows within 5C are binned: their lists are whole here.
void ParticleSystem::receive_neighbourhood() {
  auto& p = particles_;
  const Index n = p.size(), rows = p.rows();
  const int rank = ranks::rank();
  std::vector<Index> own; // now (particles may have migrated since the share)
  for (Index k = 0; k < rows; ++k)
    if (row_owner(k) == rank)
      own.push_back(k);
  double largest_h = 0;
  for (const Index i : own)
    largest_h = std::max(largest_h, p.h_p[i]);
  const double cutoff = 2 * ranks::max(largest_h) + skin_;
  const double margin = (attached_rows_listed_if_near_ ? 5 : 1) * cutoff;
  const RowBox box(p.x_p, own);
  HaloExchange near = HaloExchange::pushed(rows_near_ranks(p, own, box, mirror_, margin, cutoff));
  near.refresh_each([&p](auto visit) { p.for_each_listed_field(visit); });
  halo_bytes_ += near.bytes_sent();
  binned_.assign(rows, 0);
  for (const Index i : own)
    binned_[i] = 1;
  for (const auto& from : near.receives())
    for (const Index i : from)
      binned_[i] = 1;
  near_if_listed_.clear();
  if (attached_rows_listed_if_near_) {
    near_if_listed_.assign(rows, 0);
    for (Index k = n; k < rows; ++k)
      near_if_listed_[k] = binned_[k] && box.near(p.x_p[k], 4 * cutoff);
  }
}

// Real particles more than a list cutoff outside this rank's region go to the rank whose region
// holds them (pinned ones stay): their whole rows, then every rank learns their new owners. The
// slack keeps a particle that merely crossed a cut, which moves no work and would cross back and
// forth. Collective.
void ParticleSystem::migrate() {
  if (!migration_.owner_at)
    return;
  auto& p = particles_;
  const int rank = ranks::rank();
  const double slack = search_.cutoff();
  std::vector<std::vector<Index>> moves(static_cast<std::size_t>(ranks::size()));
  std::vector<Index> moved; // model id, new rank
  for (const Index i : own_real_rows()) {
    const Index id = p.id_p[i];
    if ((!migration_.pinned.empty() && migration_.pinned[id]) || !p.x_p[i].allFinite())
      continue; // a non-finite state stops the run at the rebuild, on its rank
    const int to = migration_.owner_at(p.x_p[i], rank, slack);
    if (to == rank)
      continue;
    moves[to].push_back(i);
    moved.insert(moved.end(), {id, to});
  }
  const std::vector<Index> all = ranks::gather_all_varying(moved);
  if (all.empty())
    return;
  HaloExchange rows = HaloExchange::pushed(std::move(moves));
  rows.refresh_by_field([&p](auto visit) { p.for_each_field(visit); });
  halo_bytes_ += rows.bytes_sent();
  for (std::size_t k = 0; k < all.size(); k += 2)
    owner_of_id_[all[k]] = static_cast<int>(all[k + 1]);
  migrations_ += static_cast<long long>(all.size() / 2);
}

// The last build's lists for the rows this rank now lists (a new cut, a checkpoint read): from
// that build's positions and smoothing lengths, whole on every rank then (gathered or read),
// with the mirror images every row had at it.
void ParticleSystem::relist() {
  auto& p = particles_;
  const Index rows = p.rows();
  std::vector<Vec3> x(search_.build_positions().begin(), search_.build_positions().begin() + rows);
  std::vector<double> h(search_.build_smoothing_lengths().begin(),
                        search_.build_smoothing_lengths().begin() + rows);
  binned_.clear();
  near_if_listed_.clear();
  p.for_each_field([rows](const char*, auto& field) { field.resize(rows); });
  place_mirrors(x, mirror_.empty() ? 0.0 : mirror_reach(h, true));
  for (Index k = 0; k < mirror_.size(); ++k) {
    x.push_back(mirror_.image_of(k, x[mirror_.source(k)]));
    h.push_back(h[mirror_.source(k)]);
  }
  mark_listed();
  search_.free_lists();
  search_.build(x, h, skin_, listed());
}

void ParticleSystem::mark_listed() {
  listed_.clear();
  listed_if_near_.clear();
  if (!distributed_)
    return;
  const auto& p = particles_;
  const Index n = p.size(), rows = p.rows();
  const int rank = ranks::rank();
  listed_.assign(p.total(), 0); // mirror images gather nothing
  for (Index k = 0; k < rows; ++k)
    listed_[k] = row_owner(k) == rank;
  if (attached_rows_listed_if_near_) {
    listed_if_near_.assign(p.total(), 0);
    if (near_if_listed_.empty())
      std::fill(listed_if_near_.begin() + n, listed_if_near_.begin() + rows, 1);
    else
      std::copy(near_if_listed_.begin(), near_if_listed_.end(), listed_if_near_.begin());
  }
}

long long ParticleSystem::pair_loop_entries() const {
  if (empty())
    return 0;
  const NeighbourList& list = search_.list();
  const Index rows = std::min(particles_.rows(), list.particle_count());
  if (!share_)
    return list.offsets[rows];
  double mine = 0;
  for (const Index i : share_->own)
    if (i < rows)
      mine += static_cast<double>(list.offsets[i + 1] - list.offsets[i]);
  return std::llround(ranks::sum_in_rank_order(std::array{mine})[0]);
}

void ParticleSystem::persist(StateArchive& a) {
  auto& p = particles_;
  a.value("particles/real", p.real);
  a.value("particles/background", p.background);
  a.value("particles/mirrored_real", p.mirrored_real);
  a.value("particles/inelastic", p.inelastic);
  a.value("particles/excluded", p.excluded);
  p.for_each_field(
      [&a](const char* name, auto& field) { a.array(std::string("particles/") + name, field); });
  search_.persist(a);
  list_builds_ += a.reading();
  a.array("particles/index_of_id", index_of_id_);
  a.value("particles/skin", skin_);
  a.value("particles/dt_stable", dt_stable_);
  a.value("particles/rebuilds", rebuilds_);
  if (a.reading() && search_.built())
    relist();
  if (a.reading() && share_)
    share(); // the checkpoint's list (collective: every rank reads the checkpoint)
}

void ParticleSystem::distribute(std::vector<int> owner_of_id, std::vector<int> owner_of_background,
                                bool attached_rows_listed_if_near, Migration migration) {
  const bool cut_anew = share_ != nullptr;
  if (cut_anew) { // the rows that change rank, whole from their old owner
    auto& p = particles_;
    const Index n = p.size();
    const int me = ranks::rank();
    std::vector<std::vector<Index>> moves(static_cast<std::size_t>(ranks::size()));
    for (const Index k : share_->own) {
      const int to = k < n ? owner_of_id[p.id_p[k]] : owner_of_background[k - n];
      if (to != me)
        moves[to].push_back(k);
    }
    HaloExchange::pushed(std::move(moves)).refresh_by_field([&p](auto visit) {
      p.for_each_field(visit);
    });
    gather([this](auto visit) { search_.for_each_build_field(visit); }, GatherTo::every_rank);
  }
  distributed_ = true;
  owner_of_id_ = std::move(owner_of_id);
  migration_ = std::move(migration);
  owner_of_background_ = std::move(owner_of_background);
  attached_rows_listed_if_near_ = attached_rows_listed_if_near;
  if (empty())
    return;
  if (!search_.built()) {
    start();
    return;
  }
  relist(); // the last build's lists of the rows this rank now steps
  ++list_builds_;
  share();
  if (cut_anew) { // the new halo whole: its rows were current where they were owned only
    auto& p = particles_;
    share_->halo.refresh_by_field([&p](auto visit) { p.for_each_field(visit); });
    mirror_.refresh_motion(p, p.rows(), visible_rows());
    mirror_.refresh_stress(p, p.rows(), visible_rows());
  }
}

void ParticleSystem::share() {
  if (share_)
    halo_bytes_ += share_->halo.bytes_sent();
  share_ = std::make_unique<ParticleShare>(make_particle_share(
      particles_, search_.list(), mirror_, owner_of_id_, owner_of_background_, ranks::rank()));
  ++shares_;
}

void ParticleSystem::read_also(std::span<const Index> rows) {
  if (!share_)
    return;
  const long long sent = share_->halo.bytes_sent();
  if (!sphfem::read_also(*share_, mirror_, rows))
    return;
  halo_bytes_ += sent;
  auto& p = particles_;
  share_->halo.refresh_each([&p](auto visit) { p.for_each_field(visit); });
  mirror_.refresh_motion(p, p.rows(), visible_rows());
  mirror_.refresh_stress(p, p.rows(), visible_rows());
}

// With the last build's positions: a new cut or a restart lists its rows from them.
void ParticleSystem::gather_state(GatherTo to) {
  gather(
      [this](auto visit) {
        particles_.for_each_field(visit);
        search_.for_each_build_field(visit);
      },
      to);
}

std::span<const unsigned char> ParticleSystem::owned_rows() const {
  return share_ ? std::span<const unsigned char>(share_->owns) : std::span<const unsigned char>();
}

// Whether the list may miss a pair; in a distributed run each rank knows the excursions of its
// own rows (and of their mirror images), and the ranks' largest two are merged.
bool ParticleSystem::rebuild_due() const {
  const auto& p = particles_;
  if (!share_)
    return search_.needs_update(p.x_p, p.h_p);
  if (!search_.built_for(p.x_p, p.h_p))
    return true;
  const std::array<double, 2> mine = search_.largest_excursions(p.x_p, p.h_p, share_->owns);
  return search_.exceeds_skin(NeighbourSearch::merge_excursions(ranks::gather_all(mine)));
}

void ParticleSystem::forces(double dt) {
  if (!share_) {
    dt_stable_ = sph_forces(particles_, search_.list(), materials_, spec_, dt);
    return;
  }
  dt_stable_ = ranks::min(sph_forces(particles_, search_.list(), materials_, spec_, dt,
                                     &share_->own, &share_->visible));
}

Vec3 ParticleSystem::mirror_force() const {
  if (mirror_.empty())
    return Vec3::Zero();
  const auto& p = particles_;
  ExactSums<3> sum = exact_sums<3>(IndexRange::of(own_rows(), p.rows()), [&](Index i) {
    return std::array{p.fm_p[i].x(), p.fm_p[i].y(), p.fm_p[i].z()};
  });
  if (share_)
    ranks::sum_exactly(sum);
  return {sum[0].value(), sum[1].value(), sum[2].value()};
}

void ParticleSystem::kick(double dt_v) {
  auto& p = particles_;
  const Index n = p.size();
  const IndexRange rows = IndexRange::of(own_rows(), p.rows());
#pragma omp parallel for schedule(static) if (rows.count > parallel_min_items)
  for (Index k = 0; k < rows.count; ++k) {
    const Index i = rows[k];
    if (i < n)
      p.v_p[i] += (dt_v / p.m_p[i]) * p.f_p[i];
    p.e_p[i] += dt_v * p.heat_p[i]; // background particles too: their half of the heating
  }
}

void ParticleSystem::drift(double dt) {
  auto& p = particles_;
  // Real particles only: a background row moves with its node.
  const IndexRange real = IndexRange::of(own_rows(), p.size());
#pragma omp parallel for schedule(static) if (real.count > parallel_min_items)
  for (Index k = 0; k < real.count; ++k) {
    const Index i = real[k];
    p.u_p[i] = p.v_p[i] + p.xsph_p[i];
    p.x_p[i] += dt * p.u_p[i];
  }
}

void ParticleSystem::update(double dt) {
  if (empty())
    return;
  auto& p = particles_;
  const auto every_field = [&p](auto visit) { p.for_each_field(visit); };
  if (share_) {
    share_->halo.refresh_each([&p](auto visit) { p.for_each_moved_field(visit); });
    // The images of rows just received: on one process their stress and kill state were
    // copied at the end of the last step, after their sources' material update.
    mirror_.refresh_stress(p, p.rows(), visible_rows());
  }
  mirror_.refresh_motion(p, p.rows(), visible_rows());
  if (rebuild_due()) {
    if (share_)
      migrate();
    rebuild();
    if (share_) {
      share();
      // The new halo whole (field by field: the step's refreshes need a third of a row's
      // buffers): the rows it gained were current here in position only.
      share_->halo.refresh_by_field(every_field);
      mirror_.refresh_motion(p, p.rows(), visible_rows());
      mirror_.refresh_stress(p, p.rows(), visible_rows());
    }
  }
  sph_kinematics(p, search_.list(), spec_, dt, own_rows(), visible_rows());
  sph_material_update(p, materials_, spec_, dt, own_rows());
  if (share_) {
    // Particles killed in tension, over all ranks: each counts its own.
    double mine = 0;
    for (Index i : share_->own)
      mine += i < p.size() && p.kill_p[i] == Kill::Tension;
    p.excluded = static_cast<Index>(ranks::sum_in_rank_order(std::array{mine})[0]);
    share_->halo.refresh_each([&p](auto visit) { p.for_each_updated_field(visit); });
  }
  mirror_.refresh_stress(p, p.rows(), visible_rows());
  forces(dt);
}

} // namespace sphfem
