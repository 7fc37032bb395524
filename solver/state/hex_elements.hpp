// Hexahedral elements as a struct of arrays (STYLE.md B): connectivity, the one-point
// integration state (deviatoric stress, pressure, bulk viscosity), energies and the nodal
// forces each element puts on its eight nodes (gathered per node, race-free). An eroded
// element (METHOD.md §6, FE erosion) is skipped by every loop: no stress, no force; its mass
// stays lumped at its nodes.
//
// The mesh fields (connectivity, material, body, mass, reference volume, erosion flag) are
// indexed by element. The state fields are indexed by slot: on one process the slot is the
// element; a rank of a distributed run (issue 28) holds the state of only the elements it
// computes and of the other ranks' elements at its nodes (parallel/subdomain.hpp), in slots
// [its own elements][those], each ascending: the state is 544 of an element's 601 bytes.
#pragma once

#include "solver/core/types.hpp"
#include "solver/material/material_point.hpp"

#include <array>
#include <vector>

namespace sphfem {

// A state field seen by element (a distributed run's exchanges list elements).
template <class T> struct BySlot {
  std::vector<T>& values;
  const std::vector<Index>& slot;
  T& operator[](Index e) const { return values[slot[e]]; }
};
template <class T> BySlot(std::vector<T>&, const std::vector<Index>&) -> BySlot<T>;

struct HexElements {
  // Mesh fields, by element.
  std::vector<Hex> nodes_e;    // connectivity, gmsh order
  std::vector<int> material_e; // index into the run's material table
  std::vector<int> body_e;     // body id
  std::vector<double> mass_e;  // kg, constant
  std::vector<double> V0_e;    // reference volume, m³
  std::vector<char> eroded_e;  // removed at failure (material erosion: true)
  // State fields, by slot.
  std::vector<double> V_e;                    // current volume, m³
  std::vector<Mat3> S_e;                      // deviatoric stress, Pa
  std::vector<double> p_e;                    // pressure (compression positive), Pa
  std::vector<double> q_e;                    // bulk viscosity pressure, Pa
  std::vector<double> e_int_e;                // internal energy (stress and bulk-viscosity work), J
  std::vector<double> de_int_e;               // its increment over the last step, J
  std::vector<double> e_hg_e;                 // hourglass energy, J
  std::vector<std::array<Vec3, 4>> hg_e;      // hourglass mode forces now acting, N
  std::vector<std::array<Vec3, 4>> hg_mode_e; // mode velocities they were computed from, m/s
  std::vector<std::array<Vec3, 8>> f_e;       // force of the element on each of its nodes, N
  std::vector<MaterialPoint> point_e;         // plastic strain, damage, temperature
  // A distributed run: per element its slot, −1 where this rank holds no state; empty on one
  // process (the slot is the element).
  std::vector<Index> slot_e;
  bool inelastic = false; // some element carries a plastic/damage history

  Index size() const { return static_cast<Index>(nodes_e.size()); }
  Index slot(Index e) const { return slot_e.empty() ? e : slot_e[e]; }
  // Visits every mesh array, then every state array, with its name (checkpoint).
  template <class Visit> void for_each_mesh_field(Visit visit) {
    visit("nodes_e", nodes_e), visit("material_e", material_e), visit("body_e", body_e);
    visit("mass_e", mass_e), visit("V0_e", V0_e), visit("eroded_e", eroded_e);
  }
  template <class Visit> void for_each_state_field(Visit visit) {
    visit("V_e", V_e), visit("S_e", S_e), visit("p_e", p_e), visit("q_e", q_e);
    visit("e_int_e", e_int_e), visit("de_int_e", de_int_e), visit("e_hg_e", e_hg_e);
    visit("hg_e", hg_e), visit("hg_mode_e", hg_mode_e), visit("f_e", f_e);
    visit("point_e", point_e);
  }
  // What the nodes read of an element after its update (a distributed run sends it to the
  // ranks owning its nodes, parallel/subdomain.hpp), by element: its forces on them, and the
  // stress, volume and erosion flag of the nodal stress (fem/nodal_stress.hpp) that background
  // particles take.
  template <class Visit> void for_each_nodal_field(Visit visit) {
    BySlot f{f_e, slot_e};
    BySlot S{S_e, slot_e};
    BySlot p{p_e, slot_e};
    BySlot V{V_e, slot_e};
    visit("f_e", f), visit("S_e", S), visit("p_e", p), visit("V_e", V);
    visit("eroded_e", eroded_e);
  }
  // Total stress σ = S − (p + q) I, tension positive, of the element in slot s.
  Mat3 sigma(Index s) const { return S_e[s] - (p_e[s] + q_e[s]) * Mat3::Identity(); }
};

} // namespace sphfem
