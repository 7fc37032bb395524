#include "solver/fem/surface_faces.hpp"

#include <algorithm>
#include <utility>

namespace sphfem {
namespace {

// A gmsh hexahedron's faces by local node, each ordered for an outward right-hand normal of a
// positive-volume element: ζ = −1, ζ = +1, η = −1, ξ = +1, η = +1, ξ = −1.
constexpr int local_faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                   {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

Quad sorted(Quad q) {
  std::ranges::sort(q);
  return q;
}

} // namespace

std::vector<SurfaceFace> surface_faces(std::span<const Hex> hex, std::span<const int> body_e,
                                       int body, std::span<const char> eroded,
                                       std::span<const Quad> cut) {
  // Every face of the body's live elements, keyed by its sorted nodes: a key met once is on
  // the surface.
  std::vector<std::pair<Quad, Index>> faces; // (key, element · 6 + local face)
  for (std::size_t e = 0; e < hex.size(); ++e) {
    if (body_e[e] != body || (!eroded.empty() && eroded[e]))
      continue;
    for (int f = 0; f < 6; ++f) {
      Quad q;
      for (int k = 0; k < 4; ++k)
        q[k] = hex[e][local_faces[f][k]];
      faces.emplace_back(sorted(q), static_cast<Index>(e) * 6 + f);
    }
  }
  std::ranges::sort(faces);
  std::vector<Quad> cut_keys;
  for (const Quad& q : cut)
    cut_keys.push_back(sorted(q));
  std::ranges::sort(cut_keys);

  std::vector<Index> once;
  for (std::size_t f = 0; f < faces.size();) {
    std::size_t same = f + 1;
    while (same < faces.size() && faces[same].first == faces[f].first)
      ++same;
    if (same == f + 1 && !std::ranges::binary_search(cut_keys, faces[f].first))
      once.push_back(faces[f].second);
    f = same;
  }
  std::ranges::sort(once);
  std::vector<SurfaceFace> out;
  out.reserve(once.size());
  for (const Index code : once) {
    const Index e = code / 6;
    SurfaceFace face{{}, e};
    for (int k = 0; k < 4; ++k)
      face.nodes[k] = hex[e][local_faces[code % 6][k]];
    out.push_back(face);
  }
  return out;
}

} // namespace sphfem
