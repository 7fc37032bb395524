// The particle phase of an explicit step (METHOD.md §2, §5, §7), in three parts run after
// the positions have moved to x^{n+1} with velocities v^{n+½}:
//   1. kinematics (pair loop, on the mid-step geometry): velocity gradient L = G C/ρ_i with
//      G = Σ_j m_j v_ji ⊗ ∇W and the gradient correction C (identity when off; m_j/ρ_i in
//      place of METHOD's m_j/ρ_j, the same on a uniform density, so that L is exactly the
//      gradient whose transpose the momentum equation uses), continuity rate dρ/dt, XSPH;
//   2. material (per particle): ρ^{n+1}, h^{n+1} = h0 (ρ0/ρ)^{1/3}, pressure from the EOS,
//      Jaumann + elastic or elastic–plastic deviator with damage and kill,
//      stress work into internal energy, artificial stress R from the principal stresses;
//   3. forces (pair loop): momentum m_i m_j (σ_i C_iᵀ/ρ_i² + σ_j C_jᵀ/ρ_j²) ∇W — METHOD's
//      symmetric form when C = I, Bonet & Lok's corrected form otherwise: stress power and
//      force work agree, a uniform stress loads only the surface, and angular momentum is
//      conserved — artificial viscosity Π_ij and artificial stress (R_i + R_j) f_ijⁿ; the
//      heating of the artificial terms; the stable step.
// Both pair loops gather per particle over full neighbour lists and write only particle i,
// so they are race-free; each pair term is evaluated with commutative operations only, so
// the force i gets from j is exactly minus the force j gets from i (momentum to round-off).
// Verified by tests/sph/sph_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/material/material.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/particles.hpp"

#include <vector>

namespace sphfem {

// dt: the step just taken (0 at the start), to recover the mid-step positions.
// `only` (each function): the rows to compute, ascending — a distributed run's share
// (parallel/particle_share.hpp); null: all. `visible`: the rows and mirror images whose
// per-particle terms those read (the share, its halo and their images, ascending), null: all.
void sph_kinematics(Particles& p, const NeighbourList& list, const SphSpec& spec, double dt,
                    const std::vector<Index>* only = nullptr,
                    const std::vector<Index>* visible = nullptr);

// Advances density, smoothing length and stress over dt (> 0).
// Johnson–Cook materials take the stress update of material_point.hpp; a particle that fails
// is killed (Particles::kill_p, METHOD.md §6).
void sph_material_update(Particles& p, const std::vector<Material>& materials, const SphSpec& spec,
                         double dt, const std::vector<Index>* only = nullptr);

// Fills f_p and heat_p; returns the stable step cfl · min h/(c + |v|) (s). The heating power
// is taken at the velocities of the kick that will apply it, v + ½ dt f/m, predicted with the
// previous forces and dt the step just taken: with the kick's start velocities instead, the
// artificial stress's heat lags its work by ½ dt f²/m per pair and step, a steady energy drift
// (2% over bar_pressed_sph).
// Pairs with a particle killed in tension are skipped.
double sph_forces(Particles& p, const NeighbourList& list, const std::vector<Material>& materials,
                  const SphSpec& spec, double dt, const std::vector<Index>* only = nullptr,
                  const std::vector<Index>* visible = nullptr);

} // namespace sphfem
