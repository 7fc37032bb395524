// Mesher internals for SPH bodies: the cubic lattice a body's particles sit on (cell centres;
// for a box optionally the cell corners, the nodes of the matching hex mesh).
// lattice.cpp fills boxes and cylinders analytically, appends the particles and names a box's
// particle faces;
// solid_file.cpp reads the volumes of a gmsh geometry file as closed triangulated surfaces;
// ray_parity.cpp decides which lattice points such a surface encloses. Verified by
// tests/mesher/lattice_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <array>
#include <filesystem>
#include <vector>

namespace sphfem::mesher {

// Cells of a lattice aligned with the global axes: cell (i, j, k), 0 ≤ i < n[0], …, is centred
// at first + (i·step.x, j·step.y, k·step.z). Cell (i, j, k) has flat index (i·n[1] + j)·n[2] + k,
// so a column (i, j) along z is contiguous.
struct Lattice {
  Vec3 first = Vec3::Zero();
  Vec3 step = Vec3::Ones();
  std::array<Index, 3> n{1, 1, 1};

  Vec3 centre(Index i, Index j, Index k) const {
    return first + Vec3(i * step.x(), j * step.y(), k * step.z());
  }
  std::size_t cell_count() const {
    return static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) *
           static_cast<std::size_t>(n[2]);
  }
};

// n_i = max(1, round(L_i / Δp)) cells of L_i / n_i per direction: tiles the box exactly.
Lattice box_lattice(const BoxGeometry& box, double spacing);

// n_i = ceil(L_i / Δp) cells of exactly Δp per direction, centred on the box [low, high], so
// they cover it (exactly when L_i is a multiple of Δp).
Lattice covering_lattice(const Vec3& low, const Vec3& high, double spacing);

// A closed triangulated surface: vertex positions, and triangles as vertex indices. Triangles
// sharing an edge share both its vertex indices (no duplicated vertices along an edge).
struct Triangulation {
  std::vector<Vec3> x;
  std::vector<std::array<Index, 3>> triangles;
};

// Sets enclosed[cell] = 1 for every lattice cell whose centre `surface` encloses, leaving the
// other entries alone (so several surfaces can be OR-ed); `enclosed` has cell_count() entries.
// Counts the surface crossings of each lattice column's vertical line below each centre: odd
// means inside. Lines through edges or vertices are decided by a consistent symbolic
// perturbation, so every closed surface is crossed an even number of times.
void mark_enclosed(const Triangulation& surface, const Lattice& lattice,
                   std::vector<char>& enclosed);

// Reads a gmsh geometry file (.geo, .step/.stp, .brep; coordinates in m) into gmsh's current
// session (best a fresh one: the file may set options), replacing its model, and triangulates the
// boundary of each volume with triangles of edge length about `size`. Throws sphfem::Error if the
// file defines no volume or a boundary is not closed; gmsh's own errors arrive as std::string.
std::vector<Triangulation> solid_boundaries(const std::filesystem::path& file, double size);

// Appends the particles of SPH body `body` (id `body_id`, material density ρ0 in kg/m³) to
// `model`, column by column of its lattice (x slowest, z fastest); for a box also its six
// particle faces "<body>/xmin" … "<body>/zmax" (Model::particle_faces; rules in lattice.cpp).
// File geometries need a gmsh session. Throws sphfem::Error if the spacing exceeds the body, no
// lattice point is inside, lattice nodes is asked for a geometry other than a box, or the
// geometry is a ring or a quarter cylinder (FE only).
void append_particles(Model& model, int body_id, const BodySpec& body, double density);

} // namespace sphfem::mesher
