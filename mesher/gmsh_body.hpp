// Mesher internals: one body at a time in gmsh's current model. box.cpp, cylinder.cpp and
// ring.cpp build the geometry with structured-mesh constraints and named faces; extract.cpp
// copies the mesh into the Model. Verified by tests/mesher/mesher_test.cpp and
// tests/mesher/ring_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <functional>
#include <string>
#include <vector>

namespace sphfem::mesher {

// Where the body's meshing frame sits in space: x = rotation · x_local + origin.
// `finish`, if set, adjusts the generated mesh in place before it is read (a nose's surface
// nodes moved onto the nose, mesher/nose.cpp).
struct Placement {
  Mat3 rotation = Mat3::Identity();
  Vec3 origin = Vec3::Zero();
  std::function<void()> finish{};
};

// Build the body in gmsh's current (empty) model, ready for generate(3): transfinite and
// recombination constraints set, faces added as physical surfaces "<body>/<face>".
Placement build_box(const BodySpec& body);
Placement build_cylinder(const BodySpec& body);
Placement build_nosed_cylinder(const BodySpec& body); // a cylinder whose nose is not flat
Placement build_ring(const BodySpec& body);

// A right-handed frame whose third axis is `axis`; the identity for +z.
Mat3 frame_along(const Vec3& axis);

// A round body's sectors: 4 quadrants (full), 2 (half, y ≥ 0), 1 (quarter, x, y ≥ 0); the
// rotation that places its local frame (axis +z) on `axis` keeping the cut planes where they
// are (a quarter: the identity; a half: a turn about y); a clear error for an axis a sector
// cannot take (a quarter's along +z, a half's in the x–z plane).
int quadrant_count(Sector sector);
// The rays of a sector that lie on its cut planes: on x = 0 (a quarter's one) and on y = 0 (a
// quarter's one, a half's two); each carries the same faces, so a body's cut faces number
// these times its faces per ray.
struct CutRays {
  std::size_t x = 0, y = 0;
};
CutRays cut_rays(Sector sector);
Mat3 sector_rotation(Sector sector, const Vec3& axis);
void check_sector_axis(Sector sector, const Vec3& axis);

// Number of element layers for `length` at `element_size`: max(1, round(length / size)).
int divisions(double length, double element_size);

// Positions of the model points bounding entity (dim, tag), e.g. a surface's corners
// (synchronised model).
std::vector<Vec3> corner_points(int dim, int tag);

// The surfaces of gmsh's current (synchronised) model that bound exactly one volume — the body's
// boundary — each with its corner points, for naming faces by where their corners lie.
struct BoundarySurface {
  int tag;
  std::vector<Vec3> corners;
};
std::vector<BoundarySurface> boundary_surfaces();

// Adds the surfaces as the physical surface group named `name`.
void add_named_face(const std::string& name, const std::vector<int>& surfaces);

// `hex` (gmsh order, indices into x) with positive volume: mirrored, bottom and top faces
// reversed, if inverted. Throws for a degenerate hex.
Hex with_positive_volume(const std::vector<Vec3>& x, Hex hex);

// Appends the meshed current gmsh model to `model` as body `body_id`: the nodes the hexes use
// (in gmsh tag order, placed), the hexes reordered to positive volume, and every physical
// surface as a node set and a face set of outward quads.
void append_mesh(Model& model, int body_id, const Placement& placement);

} // namespace sphfem::mesher
