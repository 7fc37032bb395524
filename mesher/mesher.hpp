// Model generation: meshes the case's FE bodies into structured 8-node hexahedra with gmsh and
// names their faces (node and face sets); fills its SPH bodies with particle lattices.
// Verified by tests/mesher/mesher_test.cpp, tests/mesher/ring_test.cpp and
// tests/mesher/lattice_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <string>

namespace sphfem {

// Discretises every body of the case, in case order.
// FE bodies become structured 8-node hexahedra (gmsh):
//   Box: n_i = max(1, round(L_i / element_size)) hexes per direction, faces xmin … zmax.
//   Cylinder: an O-grid (square core + 4 ring blocks) extruded along the axis, faces base
//   (at `base`), top, side; a quarter (axis along +z) an O-grid of its quadrant x, y ≥ base
//   (core square + 2 ring blocks), faces base, top, side, xmin, ymin; a half (axis in the x–z
//   plane) its two quadrants y ≥ base, face ymin (mesher/cylinder.cpp).
//   A cylinder with a pointed nose (hemispherical, conical, ogival; its tip at `base`) continues
//   the O-grid through the nose in four blocks a quadrant, face base the nose (mesher/nose.cpp).
//   Ring: 45° sectors around the square hole (8, a half 4, a quarter 2),
//   n_s = round(a / element_size) hexes along each sector's piece of the hole side and rim
//   arc, radially graded from element_size at the hole to about rim_element_size at the rim,
//   round(t / element_size) layers; the hole's nodes are those of a `lattice: nodes` SPH box of
//   spacing element_size filling it. Faces inner, rim, bottom, top (a half also ymin, a quarter
//   xmin, ymin) (mesher/ring.cpp). Hexes have positive volume in gmsh order; face-set quads have
//   outward right-hand normals.
// SPH bodies become particles on a cubic lattice of spacing Δp (rules in mesher/lattice.cpp):
// a box is tiled exactly, its particles at the cell centres (lattice centred) or on the nodes of
// the matching hex mesh (lattice nodes, lumped nodal masses); cylinders and geometry files keep
// the cell centres inside them; rings and quarter cylinders are FE only. Mass ρ0 · the
// particle's volume, density ρ0 (the material's), h = h_factor · Δp. An SPH box also gets
// particle faces xmin … zmax (Model::particle_faces: outermost particle layer, tributary areas,
// outward normal).
// Model::spacing_b gets Δp for SPH bodies and 0 for FE bodies.
// Then the interface tags of the case's attachments and contact pairs (background nodes with
// their h and Δp, interface_p; rules in mesher/interface_tags.cpp).
// Throws sphfem::Error naming the body on any failure.
Model mesh_case(const Case& c);

// A stable text signature of everything in the case that affects the model (per body in
// order: name, method, geometry kind and numbers — a ring's sector always, a cylinder's only
// when it is a quarter —, element_size or spacing, h_factor, lattice and material density; a
// geometry file by its path and an FNV-1a hash of its bytes — files it includes are not hashed;
// an FE body's h_factor only if it is in a contact pair), then one line per attachment, contact
// pair (its model, not the penalty, exponent or friction), FE body of a surface contact whose
// material erodes, and symmetry face of a body in contact, sorted. Doubles
// round-trip exactly. Throws if a geometry file is unreadable.
std::string mesh_signature(const Case& c);

} // namespace sphfem
