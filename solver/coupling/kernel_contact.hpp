// The paper's kernel contact between bodies (METHOD.md §4.3; `model: kernel`): particles and
// background particles of two bodies declared in contact repel each other once they come within
// 2h_ij, through the neighbour lists the SPH sums use. Each pair has the potential
//   Φ_ij = K V_ij (W(r_ij, h_ij) / W(Δp_ij, h_ij))ⁿ,   V_ij = 2 V_i V_j / (V_i + V_j),
// Δp_ij the mean lattice spacing, and i gets −∂Φ_ij/∂x_i = −K V_ij n (W/W₀)ⁿ⁻¹ ∇_i W_ij / W₀,
// j the opposite. METHOD.md's Q_i has V_i V_j in place of V_ij, which is a force times a
// volume; dividing by the pair's (harmonic) mean volume makes K the penalty pressure it is
// meant to be (at r = Δp, h = 1.2 Δp, n = 2, a pair of Δp³ particles pushes with ≈ 2 K Δp²).
// Φ is the contact energy the balance counts. Contact is opt-in: bodies not named in a pair
// pass through each other. Only the case's kernel pairs act here (coupling/contact.hpp).
// Verified by tests/coupling/contact_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/particles.hpp"

#include <vector>

namespace sphfem {

class KernelContact {
public:
  KernelContact() = default;
  explicit KernelContact(const Case& c);

  bool empty() const { return pairs_.empty(); }
  // Adds the contact forces to f_p and fc_p of every row, real or background, or of the rows
  // `only` lists (ascending; a distributed run's own rows), and adds to their phi_p half the
  // energy Φ_ij of each of their pairs, so that the contact energy is Σ phi_p.
  void apply(Particles& p, const NeighbourList& list,
             const std::vector<Index>* only = nullptr) const;

private:
  struct Pair {
    double penalty = 0;
    double exponent = 2;
  };
  int bodies_ = 0;
  std::vector<int> pair_of_; // bodies × bodies → index into pairs_, −1 if none
  std::vector<Pair> pairs_;
  std::vector<char> in_contact_; // per body: named in some pair
};

} // namespace sphfem
