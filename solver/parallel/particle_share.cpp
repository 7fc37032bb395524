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

} // namespace

ParticleShare make_particle_share(const Particles& p, const NeighbourList& list,
                                  const MirrorParticles& mirrors, std::span<const int> owner_of_id,
                                  std::span<const int> owner_of_background, int rank,
                                  bool collective) {
  const Index n = p.size(), rows = p.rows(), total = p.total();
  SPHFEM_CHECK(owner_of_background.size() == static_cast<std::size_t>(p.background),
               "particle share: ", owner_of_background.size(), " owners for ", p.background,
               " background rows (internal error)");
  ParticleShare s;
  s.owner.resize(rows);
  for (Index k = 0; k < rows; ++k)
    s.owner[k] = k < n ? owner_of_id[p.id_p[k]] : owner_of_background[k - n];
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
  std::vector<Index> others;
  for (Index i = 0; i < rows; ++i) {
    if (s.owns[i]) {
      s.visible.push_back(i);
      continue;
    }
    others.push_back(i);
    if (read[i]) {
      s.halo_rows.push_back(i);
      s.visible.push_back(i);
    }
  }
  add_visible_images(s, mirrors, rows);
  if (!collective)
    return s;
  s.halo = HaloExchange(s.owner, s.halo_rows);
  // The gathers' slots include the images this rank does not keep current, each from its
  // source's owner, which does: a gathered state is the single process's in every slot. (A run
  // refreshes the images it reads before reading them, so a restart would not need them.)
  std::vector<int> slot_owner(total);
  for (Index k = 0; k < total; ++k) {
    slot_owner[k] = s.owner[row_of(k)];
    if (k >= rows && !s.owns[k])
      others.push_back(k);
  }
  s.all = HaloExchange(slot_owner, others);
  return s;
}

bool read_also(ParticleShare& s, const MirrorParticles& mirrors, std::span<const Index> rows) {
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
  s.halo = HaloExchange(s.owner, s.halo_rows);
  return true;
}

} // namespace sphfem
