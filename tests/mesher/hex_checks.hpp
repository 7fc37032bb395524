// Independent geometry checks of hex meshes, shared by the mesher tests: hex volumes from
// tetrahedra, corner Jacobians, face normals, and a whole-mesh validity check (positive hexes,
// conformity, named faces complete, on the boundary and outward). Used by mesher_test.cpp and
// ring_test.cpp.
#pragma once

#include "solver/state/model.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <vector>

namespace sphfem::test {

inline double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

// Six tetrahedra around the 0–6 diagonal (exact for hexes with planar faces).
inline double hex_volume(const Model& m, const Hex& h) {
  static constexpr int tets[6][2] = {{1, 2}, {2, 3}, {3, 7}, {7, 4}, {4, 5}, {5, 1}};
  double v = 0;
  for (const auto& t : tets)
    v += tet_volume(m.x_n[h[0]], m.x_n[h[t[0]]], m.x_n[h[t[1]]], m.x_n[h[6]]);
  return v;
}

// 8 det J of the trilinear map at corner i of a hex in gmsh order (bottom 0–3 counter-clockwise
// about +ζ, top 4–7 above): the triple product of the corner's three edges, each taken along
// +ξ, +η, +ζ. Positive at all 8 corners for a valid hex.
inline double corner_jacobian(const Model& m, const Hex& h, int i) {
  static constexpr int xi_neighbour[8] = {1, 0, 3, 2, 5, 4, 7, 6};
  static constexpr int eta_neighbour[8] = {3, 2, 1, 0, 7, 6, 5, 4};
  static constexpr int xi_sign[8] = {1, -1, -1, 1, 1, -1, -1, 1}; // +1 at ξ = −1
  static constexpr int eta_sign[8] = {1, 1, -1, -1, 1, 1, -1, -1};
  const auto x = [&](int k) -> const Vec3& { return m.x_n[h[k]]; };
  const Vec3 d_xi = xi_sign[i] * (x(xi_neighbour[i]) - x(i));
  const Vec3 d_eta = eta_sign[i] * (x(eta_neighbour[i]) - x(i));
  const Vec3 d_zeta = (i < 4 ? 1 : -1) * (x(i ^ 4) - x(i));
  return d_xi.dot(d_eta.cross(d_zeta));
}

inline double min_corner_jacobian(const Model& m, const Hex& h) {
  double least = corner_jacobian(m, h, 0);
  for (int i = 1; i < 8; ++i)
    least = std::min(least, corner_jacobian(m, h, i));
  return least;
}

inline Vec3 quad_normal_area(const Model& m, const Quad& q) { // right-hand normal × area (planar)
  return 0.5 * (m.x_n[q[2]] - m.x_n[q[0]]).cross(m.x_n[q[3]] - m.x_n[q[1]]);
}

inline Vec3 quad_centroid(const Model& m, const Quad& q) {
  return 0.25 * (m.x_n[q[0]] + m.x_n[q[1]] + m.x_n[q[2]] + m.x_n[q[3]]);
}

inline Vec3 hex_centroid(const Model& m, const Hex& h) {
  Vec3 sum = Vec3::Zero();
  for (const Index i : h)
    sum += m.x_n[i];
  return sum / 8;
}

inline double total_volume(const Model& m, int body) {
  double v = 0;
  for (Index e = 0; e < m.element_count(); ++e)
    if (m.body_e[e] == body)
      v += hex_volume(m, m.hex_e[e]);
  return v;
}

// Every face of every hex, keyed by its sorted nodes, with its hex; sorted by key, so a face two
// hexes share appears twice in a row.
struct HexFace {
  std::array<Index, 4> key;
  std::size_t hex;
  bool operator<(const HexFace& other) const { return key < other.key; }
};

inline std::vector<HexFace> hex_faces(const Model& m) {
  static constexpr int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                      {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::vector<HexFace> all;
  all.reserve(6 * m.hex_e.size());
  for (std::size_t e = 0; e < m.hex_e.size(); ++e)
    for (const auto& f : faces) {
      const Hex& h = m.hex_e[e];
      HexFace face{{h[f[0]], h[f[1]], h[f[2]], h[f[3]]}, e};
      std::sort(face.key.begin(), face.key.end());
      all.push_back(face);
    }
  std::sort(all.begin(), all.end());
  return all;
}

// Checks every hex is valid (positive volume and corner Jacobians, nodes in range and all used,
// no face shared by more than two hexes) and every named face is complete (the named quads
// cover the boundary), on the boundary, in its body, and outward: its right-hand normal points
// away from the centroid of the hex it bounds.
inline void expect_valid_mesh(const Model& m) {
  ASSERT_EQ(m.body_n.size(), m.x_n.size());
  ASSERT_EQ(m.body_e.size(), m.hex_e.size());
  std::vector<bool> used(m.x_n.size(), false);
  for (const Hex& h : m.hex_e) {
    for (const Index i : h) {
      ASSERT_GE(i, 0);
      ASSERT_LT(i, m.node_count());
      used[i] = true;
    }
    EXPECT_GT(hex_volume(m, h), 0);
    EXPECT_GT(min_corner_jacobian(m, h), 0);
  }
  EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](bool u) { return u; }));

  const std::vector<HexFace> faces = hex_faces(m);
  std::size_t boundary = 0;
  for (std::size_t f = 0; f < faces.size();) {
    std::size_t g = f;
    while (g < faces.size() && faces[g].key == faces[f].key)
      ++g;
    EXPECT_LE(g - f, 2u);
    boundary += g - f == 1;
    f = g;
  }

  std::size_t named_quads = 0;
  std::set<std::array<Index, 4>> named; // no boundary face in two named faces
  for (const auto& [name, quads] : m.face_sets) {
    const std::string body = name.substr(0, name.find('/'));
    const auto b = static_cast<int>(std::find(m.body_names.begin(), m.body_names.end(), body) -
                                    m.body_names.begin());
    ASSERT_LT(b, static_cast<int>(m.body_names.size())) << name;
    std::set<Index> nodes;
    for (const Quad& q : quads) {
      HexFace key{q, 0};
      std::sort(key.key.begin(), key.key.end());
      const auto [first, last] = std::equal_range(faces.begin(), faces.end(), key);
      ASSERT_EQ(last - first, 1) << name << ": a named quad is not a boundary face of one hex";
      EXPECT_TRUE(named.insert(key.key).second) << name;
      const Vec3 inside = hex_centroid(m, m.hex_e[first->hex]);
      EXPECT_GT(quad_normal_area(m, q).dot(quad_centroid(m, q) - inside), 0) << name;
      for (const Index i : q) {
        EXPECT_EQ(m.body_n[i], b) << name;
        nodes.insert(i);
      }
    }
    ASSERT_TRUE(m.node_sets.contains(name));
    EXPECT_EQ(m.node_sets.at(name), std::vector<Index>(nodes.begin(), nodes.end())) << name;
    named_quads += quads.size();
  }
  EXPECT_EQ(m.node_sets.size(), m.face_sets.size());
  EXPECT_EQ(boundary, named_quads); // named faces cover the whole boundary
}

} // namespace sphfem::test
