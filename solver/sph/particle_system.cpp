#include "solver/sph/particle_system.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/parallel/ranks.hpp"
#include "solver/sph/sph_update.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string_view>

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
  p.real = p.model_real = n;
  p.background = p.model_background = attached;
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
// owner: the largest over the ranks), plus the skin: how near a plane a row gets mirror images.
double ParticleSystem::mirror_reach(std::span<const double> h) const {
  double largest_h = 0;
  const int rank = distributed_ ? ranks::rank() : 0;
  for (Index i = 0; i < particles_.size(); ++i)
    if (!distributed_ || row_owner(i) == rank)
      largest_h = std::max(largest_h, h[i]);
  return 2.0 * (distributed_ ? ranks::max(largest_h) : largest_h) + skin_;
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
    receive_neighbourhood(false);
  place_mirrors(p.x_p, mirror_.empty() ? 0.0 : mirror_reach(p.h_p));
  mark_listed();
  search_.build(p.x_p, p.h_p, skin_, listed());
  ++rebuilds_;
  ++list_builds_;
}

// The positions and smoothing lengths of the rows that a rebuild's lists of this rank's rows can
// hold, from their owners: the rows within a cutoff C = 2 max h + skin of its own rows' box, or
// with a mirror image there; the rows laid as its own and those, marked in binned_. With the
// surface contact, the lists of some background rows too (coupling/contact.hpp): a slave
// evaluated here lies within C of a corner of a face with an own corner, its other faces' corners
// within C of it, and a face spans less than 2C (at most 2.5 h of its corners: the contact's
// stretch allowance), so every corner it reads lies within 4C of an own row. near_if_listed_
// marks the background rows within 4C of the box, and the rows within 5C are binned: their
// lists are whole here. At a new cut or a checkpoint read (`at_build`) all this at the last
// build's positions and smoothing lengths, which travel too.
void ParticleSystem::receive_neighbourhood(bool at_build) {
  auto& p = particles_;
  const int rank = ranks::rank();
  const auto positions = [&] {
    return at_build ? search_.build_positions() : std::span<const Vec3>(p.x_p);
  };
  const auto own_rows = [&] {
    std::vector<Index> own; // now (particles may have migrated since the share)
    for (Index k = 0; k < p.rows(); ++k)
      if (row_owner(k) == rank)
        own.push_back(k);
    return own;
  };
  std::vector<Index> own = own_rows();
  const std::span<const double> h =
      at_build ? search_.build_smoothing_lengths() : std::span<const double>(p.h_p);
  double largest_h = 0;
  for (const Index i : own)
    largest_h = std::max(largest_h, h[i]);
  const double cutoff = 2 * ranks::max(largest_h) + skin_;
  const double margin = (attached_rows_listed_if_near_ ? 5 : 1) * cutoff;
  std::vector<std::vector<Index>> sends =
      rows_near_ranks(p, positions(), own, RowBox(positions(), own), mirror_, margin, cutoff);
  const RowNumbering numbers = numbering();
  std::vector<Index> held; // own, received and filled here
  for (const Index i : own)
    held.push_back(numbers.number(i));
  for (auto& list : sends)
    for (Index& k : list)
      k = numbers.number(k);
  HaloExchange near = HaloExchange::pushed(std::move(sends));
  for (const auto& from : near.receives())
    held.insert(held.end(), from.begin(), from.end());
  for (const Index k : filled_here_)
    held.push_back(numbers.model() + k);
  lay_rows(std::move(held));
  near.to_slots([numbers = numbering()](Index number) { return numbers.row(number); });
  near.refresh_each([&](auto visit) {
    p.for_each_listed_field(visit);
    if (at_build)
      search_.for_each_build_field(visit);
  });
  halo_bytes_ += near.bytes_sent();
  const Index n = p.size(), rows = p.rows();
  own = own_rows();
  binned_.assign(rows, 0);
  for (const Index i : own)
    binned_[i] = 1;
  for (const auto& from : near.receives())
    for (const Index i : from)
      binned_[i] = 1;
  near_if_listed_.clear();
  if (attached_rows_listed_if_near_) {
    const RowBox box(positions(), own);
    near_if_listed_.assign(rows, 0);
    for (Index k = n; k < rows; ++k)
      near_if_listed_[k] = binned_[k] && box.near(positions()[k], 4 * cutoff);
  }
}

void ParticleSystem::lay_rows(std::vector<Index> numbers) {
  std::ranges::sort(numbers);
  numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());
  auto& p = particles_;
  const RowNumbering before = numbering();
  const Index model = before.model(), rows = static_cast<Index>(numbers.size());
  const Index real = static_cast<Index>(std::ranges::lower_bound(numbers, model) - numbers.begin());
  std::vector<Index> from(static_cast<std::size_t>(rows)); // the row now, −1 for none
  for (Index k = 0; k < rows; ++k)
    from[k] = before.row(numbers[k]);
  const auto lay = [&from](const char*, auto& field) {
    if (field.empty())
      return; // a search not built yet
    std::remove_reference_t<decltype(field)> laid(from.size());
    for (std::size_t k = 0; k < from.size(); ++k)
      if (from[k] >= 0)
        laid[k] = field[from[k]];
    field.swap(laid);
  };
  for (Index k = 0; k < p.real; ++k)
    index_of_id_[p.id_p[k]] = -1;
  p.for_each_field(lay);
  search_.for_each_build_field(lay);
  p.real = real;
  p.background = rows - real;
  p.mirrored_real = 0;
  p.background_of_row.resize(static_cast<std::size_t>(p.background));
  p.row_of_background.assign(static_cast<std::size_t>(p.model_background), -1);
  for (Index k = 0; k < rows; ++k) {
    if (k < real) {
      p.id_p[k] = numbers[k];
      index_of_id_[numbers[k]] = k;
    } else {
      p.id_p[k] = -1;
      p.background_of_row[k - real] = numbers[k] - model;
      p.row_of_background[numbers[k] - model] = k;
    }
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
    moves[to].push_back(id);
    moved.insert(moved.end(), {id, to});
  }
  const std::vector<Index> all = ranks::gather_all_varying(moved);
  if (all.empty())
    return;
  hand_over(std::move(moves));
  for (std::size_t k = 0; k < all.size(); k += 2)
    owner_[all[k]] = static_cast<int>(all[k + 1]);
  migrations_ += static_cast<long long>(all.size() / 2);
}

std::vector<Index> ParticleSystem::held_numbers() const {
  const RowNumbering numbers = numbering();
  std::vector<Index> held(static_cast<std::size_t>(particles_.rows()));
  for (Index k = 0; k < particles_.rows(); ++k)
    held[k] = numbers.number(k);
  return held;
}

void ParticleSystem::hand_over(std::vector<std::vector<Index>> numbers) {
  receive_whole(HaloExchange::pushed(std::move(numbers)));
}

void ParticleSystem::receive_whole(HaloExchange rows) {
  auto& p = particles_;
  std::vector<Index> held = held_numbers();
  for (const auto& from : rows.receives())
    held.insert(held.end(), from.begin(), from.end());
  lay_rows(std::move(held));
  rows.to_slots([numbers = numbering()](Index number) { return numbers.row(number); });
  rows.refresh_by_field([&](auto visit) {
    p.for_each_field(visit);
    search_.for_each_build_field(visit);
  });
  halo_bytes_ += rows.bytes_sent();
}

// The last build's lists for the rows this rank now lists (a new cut, a checkpoint read): from
// that build's positions and smoothing lengths (a distributed run's of the rows
// receive_neighbourhood(true) laid), with the mirror images the rows had at it.
void ParticleSystem::relist() {
  auto& p = particles_;
  const Index rows = p.rows();
  std::vector<Vec3> x(search_.build_positions().begin(), search_.build_positions().begin() + rows);
  std::vector<double> h(search_.build_smoothing_lengths().begin(),
                        search_.build_smoothing_lengths().begin() + rows);
  p.for_each_field([rows](const char*, auto& field) { field.resize(rows); });
  place_mirrors(x, mirror_.empty() ? 0.0 : mirror_reach(h));
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
  if (share_ && !a.reading()) {
    persist_whole(a);
    return;
  }
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
  if (!a.reading())
    return;
  p.model_real = static_cast<Index>(index_of_id_.size()); // every row was read
  p.model_background = p.background;
  p.background_of_row.clear();
  p.row_of_background.clear();
  if (!search_.built())
    return;
  if (!share_) {
    relist();
    return;
  }
  relist_shared(); // every rank read every row: it keeps its own and those near them
}

// Every row in the one-process layout, model-id order then background rows, from its owner to
// rank 0, which writes (the others' archive discards); no mirror images: reading makes them.
void ParticleSystem::persist_whole(StateArchive& a) {
  auto& p = particles_;
  const Index model = static_cast<Index>(index_of_id_.size());
  const Index count = model + p.model_background;
  Index real = model, background = p.model_background, mirrored = 0;
  a.value("particles/real", real);
  a.value("particles/background", background);
  a.value("particles/mirrored_real", mirrored);
  a.value("particles/inelastic", p.inelastic);
  a.value("particles/excluded", p.excluded);
  const auto write = [&](const std::string& name, auto& field) {
    auto rows = whole(field, GatherTo::writer, count);
    a.array(name, rows);
  };
  p.for_each_field([&](const char* name, auto& field) {
    if (std::string_view(name) == "id_p") {
      std::vector<Index> ids(static_cast<std::size_t>(count), -1);
      std::iota(ids.begin(), ids.begin() + model, Index(0));
      a.array("particles/id_p", ids);
    } else {
      write(std::string("particles/") + name, field);
    }
  });
  search_.persist_through(a, write);
  std::vector<Index> index_of_id(static_cast<std::size_t>(model));
  std::iota(index_of_id.begin(), index_of_id.end(), Index(0));
  a.array("particles/index_of_id", index_of_id);
  a.value("particles/skin", skin_);
  a.value("particles/dt_stable", dt_stable_);
  a.value("particles/rebuilds", rebuilds_);
}

void ParticleSystem::distribute(std::vector<int> owner_of_id, std::vector<int> owner_of_background,
                                std::vector<Index> filled_here, bool attached_rows_listed_if_near,
                                Migration migration) {
  std::vector<int> owner = std::move(owner_of_id);
  owner.insert(owner.end(), owner_of_background.begin(), owner_of_background.end());
  const bool cut_anew = share_ != nullptr;
  if (cut_anew) { // the rows that change rank, whole from their old owner
    const RowNumbering numbers = numbering();
    const int me = ranks::rank();
    std::vector<std::vector<Index>> moves(static_cast<std::size_t>(ranks::size()));
    for (const Index k : share_->own)
      if (const Index number = numbers.number(k); owner[number] != me)
        moves[owner[number]].push_back(number);
    hand_over(std::move(moves));
  }
  distributed_ = true;
  owner_ = std::move(owner);
  filled_here_ = std::move(filled_here);
  migration_ = std::move(migration);
  attached_rows_listed_if_near_ = attached_rows_listed_if_near;
  if (empty())
    return;
  if (cut_anew)
    hold_filled_rows();
  if (!search_.built()) {
    start();
    return;
  }
  relist_shared();
  ++list_builds_;
}

// The background rows this rank fills from now on and does not hold, whole from their owners: a
// fill writes some fields only (and keeps the density where every element around is eroded).
void ParticleSystem::hold_filled_rows() {
  const RowNumbering numbers = numbering();
  std::vector<Index> missing;
  for (const Index k : filled_here_)
    if (numbers.row(numbers.model() + k) < 0)
      missing.push_back(numbers.model() + k);
  receive_whole(HaloExchange(owner_, missing));
}

void ParticleSystem::relist_shared() {
  receive_neighbourhood(true);
  relist();
  share_whole();
}

void ParticleSystem::share_whole() {
  share();
  auto& p = particles_;
  share_->halo.refresh_by_field([&p](auto visit) { p.for_each_field(visit); });
  mirror_.refresh_motion(p, p.rows(), visible_rows());
  mirror_.refresh_stress(p, p.rows(), visible_rows());
}

void ParticleSystem::share() {
  if (share_)
    halo_bytes_ += share_->halo.bytes_sent();
  share_ = std::make_unique<ParticleShare>(
      make_particle_share(particles_, search_.list(), mirror_, owner_, numbering(), ranks::rank()));
  ++shares_;
}

void ParticleSystem::read_also(std::span<const Index> rows) {
  if (!share_)
    return;
  const long long sent = share_->halo.bytes_sent();
  if (!sphfem::read_also(*share_, mirror_, rows, owner_, numbering()))
    return;
  halo_bytes_ += sent;
  auto& p = particles_;
  share_->halo.refresh_each([&p](auto visit) { p.for_each_field(visit); });
  mirror_.refresh_motion(p, p.rows(), visible_rows());
  mirror_.refresh_stress(p, p.rows(), visible_rows());
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
    if (share_)
      share_whole();
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
