// Symmetry planes for SPH bodies (a `symmetry` condition on a box face of a particle body, or on
// a flat face — a box face, a quarter cylinder's or ring's cut face xmin/ymin — of an FE body in a
// kernel contact pair, whose background particles the other body meets):
// the real (and background) particles within reach of a plane get mirror images across it — and
// across both planes of a corner — appended to the particle arrays, refreshed every step with the
// mirrored position, velocity (R v), stress (R σ Rᵀ) and gradient correction (R C Rᵀ), R = I − 2 n
// nᵀ (a product of two for a corner). Real particles include them in their sums, so the kernel
// support is whole at the plane and the body behaves as the symmetric whole would; the images
// gather nothing themselves. Verified by tests/sph/mirror_particles_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/particles.hpp"

#include <span>
#include <utility>
#include <vector>

namespace sphfem {

class MirrorParticles {
public:
  MirrorParticles() = default;
  // The planes of the case's symmetry conditions on SPH bodies and FE bodies in kernel contact.
  explicit MirrorParticles(const Case& c);

  struct Plane {
    int group; // of the body it bounds: an attached FE body's background particles share it
    Vec3 point, normal;
  };
  explicit MirrorParticles(std::vector<Plane> planes) : planes_(std::move(planes)) {}

  // The images of a point of `group` at x: one across every non-empty subset of the group's
  // planes within `reach` of x (three at the corner of a quarter model) — the rule select uses.
  std::vector<Vec3> images_of(const Vec3& x, int group, double reach) const;

  bool empty() const { return planes_.empty(); }
  Index size() const { return static_cast<Index>(source_.size()); }
  // The row image k is made from (current index).
  Index source(Index k) const { return source_[k]; }

  // Chooses the images of the real and background particles at positions x (one per row of
  // p.rows(): the current ones, or a neighbour build's) lying within `reach` of their group's
  // planes, among the rows `among` marks (all when empty: a distributed run's rank makes the
  // images of the rows it bins); images of real particles first; sets p.mirrored_real.
  void select(Particles& p, std::span<const Vec3> x, double reach,
              std::span<const unsigned char> among = {});
  // Image k of a source at x.
  Vec3 image_of(Index k, const Vec3& x) const { return image_[k].R * x + image_[k].t; }
  // Position, velocity, mass, density, h and identity of each image (slots from `first`), or of
  // the image slots `only` lists (a distributed run's visible rows: images of sources the rank
  // keeps current; its rows read no other).
  void refresh_motion(Particles& p, Index first, const std::vector<Index>* only = nullptr) const;
  // Density, h, stress, gradient correction, artificial stress and last force of each image (or
  // of those `only` lists).
  void refresh_stress(Particles& p, Index first, const std::vector<Index>* only = nullptr) const;

private:
  struct Image {
    Mat3 R; // x' = R x + t
    Vec3 t;
  };
  // The image maps of a point of `group` at x (images_of).
  std::vector<Image> maps_of(const Vec3& x, int group, double reach) const;

  std::vector<Plane> planes_;
  std::vector<Index> source_; // real particle of each image (current index)
  std::vector<Image> image_;
};

} // namespace sphfem
