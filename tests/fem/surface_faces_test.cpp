// The surface of a hexahedral body (solver/fem/surface_faces): faces bounding one live element,
// outward, less the cut ones; an eroded element exposes the faces behind it.
#include "solver/fem/surface_faces.hpp"

#include <gtest/gtest.h>

#include <vector>

using namespace sphfem;

namespace {

// Two unit cubes side by side along x, gmsh order: nodes (i, j, k) at index i + 3 j + 6 k.
struct TwoCubes {
  std::vector<Vec3> x;
  std::vector<Hex> hex;
  std::vector<int> body{0, 0};
  TwoCubes() {
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i)
          x.emplace_back(i, j, k);
    const auto n = [](int i, int j, int k) { return i + 3 * j + 6 * k; };
    for (int i = 0; i < 2; ++i)
      hex.push_back({n(i, 0, 0), n(i + 1, 0, 0), n(i + 1, 1, 0), n(i, 1, 0), n(i, 0, 1),
                     n(i + 1, 0, 1), n(i + 1, 1, 1), n(i, 1, 1)});
  }
  Vec3 centre(const Hex& h) const {
    Vec3 c = Vec3::Zero();
    for (Index a : h)
      c += x[a] / 8.0;
    return c;
  }
  // Right-hand normal of a face (x2 − x0) × (x3 − x1).
  Vec3 normal(const Quad& q) const { return (x[q[2]] - x[q[0]]).cross(x[q[3]] - x[q[1]]); }
  Vec3 face_centre(const Quad& q) const { return 0.25 * (x[q[0]] + x[q[1]] + x[q[2]] + x[q[3]]); }
};

} // namespace

TEST(SurfaceFaces, OuterFacesPointOut) {
  const TwoCubes m;
  const auto faces = surface_faces(m.hex, m.body, 0, {}, {});
  ASSERT_EQ(faces.size(), 10u); // 12 faces, the shared one twice
  for (const SurfaceFace& f : faces) {
    const Vec3 out = m.face_centre(f.nodes) - m.centre(m.hex[f.element]);
    EXPECT_NEAR(m.normal(f.nodes).dot(out), 0.5 * 2, 1e-12); // |n| = 2 (unit face), |out| = ½
    EXPECT_NE(m.face_centre(f.nodes).x(), 1.0) << "the shared face is not surface";
  }
  EXPECT_TRUE(surface_faces(m.hex, m.body, 1, {}, {}).empty()); // no such body
}

TEST(SurfaceFaces, ErosionExposesTheFaceBehind) {
  const TwoCubes m;
  const std::vector<char> eroded{0, 1};
  const auto faces = surface_faces(m.hex, m.body, 0, eroded, {});
  ASSERT_EQ(faces.size(), 6u);
  bool exposed = false;
  for (const SurfaceFace& f : faces) {
    EXPECT_EQ(f.element, 0);
    if (m.face_centre(f.nodes).x() == 1.0) {
      exposed = true;
      EXPECT_GT(m.normal(f.nodes).x(), 0); // out of the remaining cube, towards the eroded one
    }
  }
  EXPECT_TRUE(exposed);
}

TEST(SurfaceFaces, CutFacesAreLeftOut) {
  const TwoCubes m;
  // The xmin face, in any node order.
  const std::vector<Quad> cut{{9, 0, 3, 6}};
  const auto faces = surface_faces(m.hex, m.body, 0, {}, cut);
  ASSERT_EQ(faces.size(), 9u);
  for (const SurfaceFace& f : faces)
    EXPECT_GT(m.face_centre(f.nodes).x(), 0.0);
}
