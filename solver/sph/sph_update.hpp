// The particle phase of an explicit step (METHOD.md §2, §5, §7), in three parts run after
// the positions have moved to x^{n+1} with velocities v^{n+½}:
//   1. kinematics (pair loop, on the mid-step geometry): velocity gradient L (with the
//      gradient correction when asked), continuity rate dρ/dt, XSPH correction;
//   2. material (per particle): ρ^{n+1}, h^{n+1} = h0 (ρ0/ρ)^{1/3}, Jaumann + elastic stress,
//      stress work into internal energy, artificial stress R from the principal stresses;
//   3. forces (pair loop): momentum with stress, artificial viscosity Π_ij and artificial
//      stress (R_i + R_j) f_ijⁿ; the heating of the artificial terms; the stable step.
// Both pair loops gather per particle over full neighbour lists and write only particle i,
// so they are race-free; each pair term is evaluated with commutative operations only, so
// the force i gets from j is exactly minus the force j gets from i (momentum to round-off).
// Verified by tests/sph/sph_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/material/elastic.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/particles.hpp"

#include <vector>

namespace sphfem {

// dt: the step just taken (0 at the start), to recover the mid-step positions.
void sph_kinematics(Particles& p, const NeighbourList& list, const SphSpec& spec, double dt);

// Advances density, smoothing length and stress over dt (> 0).
void sph_material_update(Particles& p, const std::vector<ElasticConstants>& materials,
                         const SphSpec& spec, double dt);

// Fills f_p and heat_p; returns the stable step cfl · min h/(c + |v|) (s).
double sph_forces(Particles& p, const NeighbourList& list,
                  const std::vector<ElasticConstants>& materials, const SphSpec& spec);

} // namespace sphfem
