// Model generation: meshes the case's bodies into structured 8-node hexahedra with gmsh and
// names their faces (node and face sets). Verified by tests/mesher/mesher_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <string>

namespace sphfem {

// Meshes every body of the case into structured 8-node hexahedra with gmsh, in case order.
// Box: n_i = max(1, round(L_i / element_size)) hexes per direction, faces xmin … zmax.
// Cylinder: an O-grid (square core + 4 ring blocks) extruded along the axis, faces base
// (at `base`), top, side. Hexes have positive volume in gmsh order; face-set quads have
// outward right-hand normals. Throws sphfem::Error naming the body on any failure.
Model mesh_case(const Case& c);

// A stable text signature of everything in the case that affects the mesh (per body in
// order: name, method, geometry kind and numbers, element_size; doubles round-trip exactly).
std::string mesh_signature(const Case& c);

} // namespace sphfem
