// Background particles (METHOD.md §4.1): the FE nodes the mesher tagged (Model::background_nodes)
// appear in the particle arrays after the real particles, as copies of nodal state — position,
// half-step velocity, lumped mass, density and stress of the adjacent elements — refreshed
// every step. Real particles include them in their sums (attachment, §4.2) and contact (§4.3);
// the pair forces they receive go back to their nodes with the sign the SPH pair gives them,
// so linear momentum of the coupled system is conserved to round-off. The step
// (time/simulation.cpp) owns them: the particle phase sees their rows, not the elements.
// Verified by tests/coupling/coupling_test.cpp.
#pragma once

#include "solver/core/exact_sum.hpp"
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
  // FE node of background particle k (array row p.background_row(k)).
  Index node(Index k) const { return nodes_[k]; }

  // Sets the fields of the slots that stay fixed (body, group, material, smoothing length,
  // spacing, the material point's initial state) and those fill() does not copy; p has its
  // real particles and room for these rows.
  void initialise(const Case& c, const Model& model, const std::vector<Material>& materials,
                  Particles& p) const;

  // Copies xⁿ⁺¹, v^{n+½} (also as drift velocity), mass, density Σm_e/ΣV_e and the
  // volume-weighted stress of the adjacent elements, and the node's element force (for the
  // heating predictor), into the slots. Call after the element phase, before the particles'.
  // `only`: the background particles to fill (a distributed run's: those of the nodes the rank
  // owns, whose elements it holds current), ascending; null: all.
  void fill(const Nodes& nodes, const HexElements& elements, const NodeGather& around, Particles& p,
            const std::vector<Index>* only = nullptr) const;

  // f_nodes[node] += the pair and contact forces on its background particle (of those `only`
  // lists).
  void return_forces(const Particles& p, std::vector<Vec3>& f_nodes,
                     const std::vector<Index>* only = nullptr) const;

  // The fields fill() writes and those return_forces() reads, as views indexed by background
  // particle (a distributed run's exchanges; the rank holds the rows it sends and receives):
  // visit(name, view) per field.
  template <class Visit> static void visit_filled(Particles& p, Visit visit);
  template <class Visit> static void visit_returned(Particles& p, Visit visit);

  // Energy stored by the coupling pairs on the background side (at the half step), J, over the
  // background `rows` (a distributed run: those this rank owns), exactly.
  ExactSum energy(const Particles& p, IndexRange rows) const;

private:
  template <class T> class Rows {
  public:
    Rows(const Particles& p, std::vector<T>& field) : p_(p), field_(field) {}
    T& operator[](Index k) const { return field_[p_.background_row(k)]; }

  private:
    const Particles& p_;
    std::vector<T>& field_;
  };
  template <class T> static Rows<T> rows(const Particles& p, std::vector<T>& field) {
    return Rows<T>(p, field);
  }

  std::vector<Index> nodes_;
};

template <class Visit> void BackgroundParticles::visit_filled(Particles& p, Visit visit) {
  auto x = rows(p, p.x_p), v = rows(p, p.v_p), u = rows(p, p.u_p), f = rows(p, p.f_p);
  auto m = rows(p, p.m_p), rho = rows(p, p.rho_p), pressure = rows(p, p.p_p);
  auto S = rows(p, p.S_p);
  visit("x", x);
  visit("v", v);
  visit("u", u);
  visit("m", m);
  visit("rho", rho);
  visit("p", pressure);
  visit("S", S);
  visit("f", f);
}

template <class Visit> void BackgroundParticles::visit_returned(Particles& p, Visit visit) {
  auto f = rows(p, p.f_p);
  visit("f", f);
}

} // namespace sphfem
