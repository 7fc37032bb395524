#include "solver/parallel/particle_share.hpp"

#include "solver/core/error.hpp"
#include "solver/parallel/ranks.hpp"

#include <algorithm>

namespace sphfem {

namespace {

// The images whose source is visible, appended to the visible rows (image slots from `rows`).
void add_visible_images(ParticleShare& s, const MirrorParticles& mirrors, Index rows) {
  std::vector<unsigned char> visible(rows, 0);
  for (const Index i : s.visible)
    visible[i] = 1;
  for (Index k = 0; k < mirrors.size(); ++k)
    if (visible[mirrors.source(k)])
      s.visible.push_back(rows + k);
}

// The exchange refreshing `halo_rows`, agreed on the shared numbers, in this rank's rows.
HaloExchange halo_exchange(std::span<const Index> halo_rows, std::span<const int> owner,
                           const RowNumbering& numbering) {
  std::vector<Index> numbers(halo_rows.size());
  std::ranges::transform(halo_rows, numbers.begin(), [&](Index k) { return numbering.number(k); });
  HaloExchange h(owner, numbers);
  h.to_slots([&](Index number) { return numbering.row(number); });
  return h;
}

} // namespace

ParticleShare make_particle_share(const Particles& p, const NeighbourList& list,
                                  const MirrorParticles& mirrors, std::span<const int> owner,
                                  const RowNumbering& numbering, int rank, bool collective) {
  const Index rows = p.rows(), total = p.total();
  SPHFEM_CHECK(owner.size() == static_cast<std::size_t>(numbering.model() + p.model_background),
               "particle share: ", owner.size(), " owners for ", numbering.model(),
               " particles and ", p.model_background, " background particles (internal error)");
  ParticleShare s;
  s.owner.resize(rows);
  for (Index k = 0; k < rows; ++k)
    s.owner[k] = owner[numbering.number(k)];
  // A mirror image is made here from its source row.
  const auto row_of = [&](Index j) { return j < rows ? j : mirrors.source(j - rows); };
  s.owns.assign(total, 0);
  for (Index k = 0; k < total; ++k)
    s.owns[k] = s.owner[row_of(k)] == rank;
  std::vector<unsigned char> read(rows, 0);
  for (Index i = 0; i < rows; ++i) {
    if (!s.owns[i])
      continue;
    s.own.push_back(i);
    for (Index j : list.of(i))
      read[row_of(j)] = 1;
  }
  for (Index i = 0; i < rows; ++i) {
    if (s.owns[i]) {
      s.visible.push_back(i);
      continue;
    }
    if (read[i]) {
      s.halo_rows.push_back(i);
      s.visible.push_back(i);
    }
  }
  add_visible_images(s, mirrors, rows);
  if (!collective)
    return s;
  s.halo = halo_exchange(s.halo_rows, owner, numbering);
  return s;
}

bool read_also(ParticleShare& s, const MirrorParticles& mirrors, std::span<const Index> rows,
               std::span<const int> owner, const RowNumbering& numbering) {
  std::vector<Index> added;
  for (const Index i : rows)
    if (!s.owns[i] && !std::ranges::binary_search(s.halo_rows, i))
      added.push_back(i);
  std::ranges::sort(added);
  added.erase(std::unique(added.begin(), added.end()), added.end());
  if (ranks::max(static_cast<int>(added.size())) == 0)
    return false;
  std::vector<Index> merged(s.halo_rows.size() + added.size());
  std::ranges::merge(s.halo_rows, added, merged.begin());
  s.halo_rows = std::move(merged);
  merged.assign(s.own.size() + s.halo_rows.size(), 0);
  std::ranges::merge(s.own, s.halo_rows, merged.begin());
  s.visible = std::move(merged);
  add_visible_images(s, mirrors, static_cast<Index>(s.owner.size()));
  s.halo = halo_exchange(s.halo_rows, owner, numbering);
  return true;
}

RowBox::RowBox(std::span<const Vec3> x, std::span<const Index> own) {
  for (const Index i : own) {
    lo = lo.cwiseMin(x[i]);
    hi = hi.cwiseMax(x[i]);
  }
}

std::vector<std::vector<Index>> rows_near_ranks(const Particles& p, std::span<const Vec3> x,
                                                std::span<const Index> own, const RowBox& box,
                                                const MirrorParticles& mirrors, double margin,
                                                double image_reach) {
  const std::array<double, 6> corners{box.lo.x(), box.lo.y(), box.lo.z(),
                                      box.hi.x(), box.hi.y(), box.hi.z()};
  const std::vector<double> all = ranks::gather_all(corners);
  const int n = ranks::size(), me = ranks::rank();
  std::vector<RowBox> boxes(n, RowBox({}, {}));
  for (int r = 0; r < n; ++r) {
    boxes[r].lo = {all[6 * r], all[6 * r + 1], all[6 * r + 2]};
    boxes[r].hi = {all[6 * r + 3], all[6 * r + 4], all[6 * r + 5]};
  }
  std::vector<std::vector<Index>> sends(n);
  for (const Index i : own) {
    if (i >= p.rows())
      break;
    const std::vector<Vec3> images =
        mirrors.empty() ? std::vector<Vec3>{} : mirrors.images_of(x[i], p.group_p[i], image_reach);
    for (int r = 0; r < n; ++r) {
      if (r == me)
        continue;
      bool near = boxes[r].near(x[i], margin);
      for (const Vec3& image : images)
        near = near || boxes[r].near(image, margin);
      if (near)
        sends[r].push_back(i);
    }
  }
  return sends;
}

} // namespace sphfem
