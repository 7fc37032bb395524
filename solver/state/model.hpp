// The discretised model the mesher produces and model.h5 stores: reference node positions,
// hexahedra, bodies and named node/face sets. The solver builds its state from this.
#pragma once

#include "solver/core/types.hpp"

#include <map>
#include <string>
#include <vector>

namespace sphfem {

struct Model {
  // Bodies in case order; node and element body ids index this list.
  std::vector<std::string> body_names;

  // Nodes (reference configuration).
  std::vector<Vec3> x_n;   // m
  std::vector<int> body_n; // body id per node

  // Hexahedra (gmsh node order, positive volume).
  std::vector<Hex> hex_e;
  std::vector<int> body_e; // body id per element

  // Named faces, keyed "<body>/<face>" (e.g. "bar/zmin"): the nodes on the face and its
  // quadrilaterals with outward normals.
  std::map<std::string, std::vector<Index>> node_sets;
  std::map<std::string, std::vector<Quad>> face_sets;

  // Signature of the mesh-relevant case keys this model was made from (staleness check).
  std::string signature;

  Index node_count() const { return static_cast<Index>(x_n.size()); }
  Index element_count() const { return static_cast<Index>(hex_e.size()); }
};

} // namespace sphfem
