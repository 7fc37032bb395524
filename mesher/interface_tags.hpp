// Interface tags for SPH–FEM coupling (METHOD.md §4.1): which FE nodes carry background
// particles, with the h and lattice spacing Δp each carries, and which SPH particles have a
// background particle within reach. Rules in interface_tags.cpp. Verified by
// tests/mesher/interface_tags_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <vector>

namespace sphfem::mesher {

// Fills Model::background_nodes, h_background, spacing_background and interface_p (one entry
// per particle, 0 or 1) from the case's attachments and contact pairs. The model must hold every
// body of `c`, meshed, with body ids in case order, in the initial configuration.
void tag_interfaces(Model& model, const Case& c);

// Whether a surface contact tags every node of FE body `body` (not only its surface): its
// material erodes, so any node may come to lie on its surface.
bool exposes_inner_nodes(const Case& c, const BodySpec& body);

// The nodes of body `body_id`'s hexahedra that lie on a face belonging to only one of them (the
// body's boundary), ascending. Faces among `cut` (a quarter model's symmetry faces: the whole
// body goes on there) do not count.
std::vector<Index> surface_nodes(const Model& model, int body_id,
                                 const std::vector<Quad>& cut = {});

} // namespace sphfem::mesher
