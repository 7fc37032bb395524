// Background particles (METHOD.md §4.1): the FE nodes the mesher tagged (Model::background_nodes)
// appear in the particle arrays after the real particles, as copies of nodal state — position,
// half-step velocity, lumped mass, density and stress of the adjacent elements — refreshed
// every step. Real particles include them in their sums (attachment, §4.2) and contact (§4.3);
// the pair forces they receive go back to their nodes with the sign the SPH pair gives them,
// so linear momentum of the coupled system is conserved to round-off. The step
// (time/simulation.cpp) owns them: the particle phase sees their rows, not the elements.
// Verified by tests/coupling/coupling_test.cpp.
#pragma once

#include "solver/fem/node_gather.hpp"
#include "solver/io/case.hpp"
#include "solver/material/material.hpp"
#include "solver/state/hex_elements.hpp"
#include "solver/state/model.hpp"
#include "solver/state/nodes.hpp"
#include "solver/state/particles.hpp"

#include <vector>

namespace sphfem {

class BackgroundParticles {
public:
  BackgroundParticles() = default;
  explicit BackgroundParticles(std::vector<Index> nodes) : nodes_(std::move(nodes)) {}

  Index size() const { return static_cast<Index>(nodes_.size()); }
  bool empty() const { return nodes_.empty(); }
  // FE node of background particle k (array slot p.real + k).
  Index node(Index k) const { return nodes_[k]; }

  // Sets the fields of the slots that stay fixed (body, group, material, smoothing length,
  // spacing, the material point's initial state) and those fill() does not copy; p has its
  // real particles and room for these rows.
  void initialise(const Case& c, const Model& model, const std::vector<Material>& materials,
                  Particles& p) const;

  // Copies xⁿ⁺¹, v^{n+½} (also as drift velocity), mass, density Σm_e/ΣV_e and the
  // volume-weighted stress of the adjacent elements, and the node's element force (for the
  // heating predictor), into the slots. Call after the element phase, before the particles'.
  void fill(const Nodes& nodes, const HexElements& elements, const NodeGather& around,
            Particles& p) const;

  // f_nodes[node] += the pair and contact forces on its background particle.
  void return_forces(const Particles& p, std::vector<Vec3>& f_nodes) const;

  // Energy stored by the coupling pairs on the background side (at the half step), J.
  double energy(const Particles& p) const;

private:
  std::vector<Index> nodes_;
};

} // namespace sphfem
