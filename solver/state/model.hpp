// The discretised model the mesher produces and model.h5 stores: reference node positions,
// hexahedra, bodies and named node/face sets. The solver builds its state from this.
#pragma once

#include "solver/core/types.hpp"

#include <map>
#include <string>
#include <vector>

namespace sphfem {

// The layer of an SPH body's particles that forms one of its named faces, each with the
// face area it carries (its tributary area), for loads and boundary conditions.
struct ParticleFace {
  std::vector<Index> particles; // indices into the particle arrays
  std::vector<double> area;     // tributary area of each, m²
  Vec3 normal = Vec3::Zero();   // outward unit normal of the (flat) face
};

struct Model {
  // Bodies in case order; node and element body ids index this list.
  std::vector<std::string> body_names;

  // Nodes (reference configuration).
  std::vector<Vec3> x_n;   // m
  std::vector<int> body_n; // body id per node

  // Hexahedra (gmsh node order, positive volume).
  std::vector<Hex> hex_e;
  std::vector<int> body_e; // body id per element

  // SPH particles (reference configuration), body by body in case order.
  std::vector<Vec3> x_p;     // m
  std::vector<double> m_p;   // mass, kg
  std::vector<double> rho_p; // initial density, kg/m³
  std::vector<double> h_p;   // smoothing length, m
  std::vector<int> body_p;   // body id per particle
  // Lattice spacing Δp per body (0 for FE bodies), m.
  std::vector<double> spacing_b;

  // Coupling (METHOD.md §4.1): the FE nodes that carry background particles (ascending), the
  // smoothing length of each (that of the SPH body it is attached to, else the FE body's
  // h_factor × element size) and its lattice spacing Δp (for the artificial stress and
  // contact), m; and per particle 1 if a background particle lies within its 2h (interface).
  std::vector<Index> background_nodes;
  std::vector<double> h_background;
  std::vector<double> spacing_background;
  std::vector<int> interface_p;

  // Named faces, keyed "<body>/<face>" (e.g. "bar/zmin"): the nodes on the face and its
  // quadrilaterals with outward normals.
  std::map<std::string, std::vector<Index>> node_sets;
  std::map<std::string, std::vector<Quad>> face_sets;

  // Named faces of SPH bodies, keyed "<body>/<face>" like the node sets.
  std::map<std::string, ParticleFace> particle_faces;

  // Signature of the mesh-relevant case keys this model was made from (staleness check).
  std::string signature;

  Index node_count() const { return static_cast<Index>(x_n.size()); }
  Index element_count() const { return static_cast<Index>(hex_e.size()); }
  Index particle_count() const { return static_cast<Index>(x_p.size()); }
};

} // namespace sphfem
