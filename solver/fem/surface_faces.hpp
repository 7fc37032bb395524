// The surface of a hexahedral body: the quadrilaterals that bound exactly one of its live
// (uneroded) hexahedra, ordered so that their right-hand normal points out of the body
// (types.hpp's Quad), less the faces a caller cuts away (its symmetry planes: the body goes on
// beyond them). The mesher gives a contact body's surface nodes background particles from it;
// surface contact (coupling/surface_contact.hpp) takes its segments from it, and takes them
// again when elements erode, so that the faces behind an eroded element become surface.
// Verified by tests/fem/surface_faces_test.cpp.
#pragma once

#include "solver/core/types.hpp"

#include <span>
#include <vector>

namespace sphfem {

struct SurfaceFace {
  Quad nodes;    // outward normal by the right-hand rule
  Index element; // the hexahedron it bounds
};

// The surface faces of body `body`, ordered by element, then by the element's local face.
// eroded: one flag per element, or empty when nothing erodes; cut: faces to leave out (any
// node order).
std::vector<SurfaceFace> surface_faces(std::span<const Hex> hex, std::span<const int> body_e,
                                       int body, std::span<const char> eroded,
                                       std::span<const Quad> cut);

} // namespace sphfem
