// The stress update of one material point over one step (METHOD.md §5), the same for SPH
// particles, hexahedra and the `sphfem material` driver:
//   1. trial deviator: Jaumann rotation + 2G D′ Δt (elastic.hpp);
//   2. radial return onto the rate-dependent, damage-coupled yield surface: solve
//        g(Δp) = σ_trial − 3G Δp − (1 − D) σ_Y(r + (1 − D) Δp, (1 − D) Δp/Δt, T) = 0
//      by Newton's method kept inside the bracket [0, (σ_trial − σ_Y(r, 0, T)(1 − D))/3G]
//      by bisection, to |g| ≤ 1e-10 σ_trial; then S ← S (σ_trial − 3G Δp)/σ_trial;
//   3. adiabatic heating ΔT = χ σ_eq Δp/(ρ C_p);
//   4. damage ΔD = D_C Δp/(p_f − p_d) once p ≥ p_d, with σ* = −p/σ_eq and ṗ* = Δp/(Δt ṗ0),
//      p_f times the regularisation's L / width where the material states L
//      (ductile_damage.hpp);
//   5. failure at D ≥ D_C: S = 0 from then on and the point carries no tension (p ≥ 0).
// Temperature and damage enter the yield stress as they were at the start of the step.
#pragma once

#include "solver/core/types.hpp"

#include <array>

namespace sphfem {

struct Material;

// What a point carries from step to step besides its stress. A checkpoint stores its bytes, so
// the bytes after `failed` are a member, zeroed, not padding (whose bytes are left undefined):
// two runs then write the same bytes.
struct MaterialPoint {
  double plastic_strain = 0; // equivalent plastic strain p
  double damaged_strain = 0; // damage-accumulated plastic strain r, ṙ = (1 − D) ṗ
  double damage = 0;         // D
  double temperature = 0;    // T, K
  bool failed = false;       // D reached D_C
  std::array<unsigned char, 7> unused{};

  static MaterialPoint initial(const Material& m);
};
static_assert(sizeof(MaterialPoint) == 40, "MaterialPoint has padding: its bytes are undefined");

// Advances the deviatoric stress S (Pa) and the point's history over dt (s) with strain rate D
// and spin W (1/s) at the end-of-step density ρ (kg/m³). `pressure` (Pa, compression
// positive) comes in from the EOS at the new density and goes out as the point carries it
// (tension cut off once failed). `band_width` (m) is the width a shear band takes in the
// discretisation the point belongs to (2h for a particle, the size of a hexahedron; 0 for a
// point without a size). Returns the plastic strain increment Δp.
double update_point(const Material& m, const Mat3& D, const Mat3& W, double dt, double rho,
                    double& pressure, Mat3& S, MaterialPoint& point, double band_width);

// Whether the point's next update enters the radial return if its stress does not change: an
// intact point of a material with strength whose equivalent stress is at least its static
// flow stress (1 − D) σ_Y(r, 0, T), the test update_point makes on its trial stress. A yielding
// point's update costs ≈ 1.6 × an elastic one's (solver/time/cost_estimate.hpp).
bool yielding(const Material& m, const Mat3& S, const MaterialPoint& point);

// The von Mises equivalent stress √(3/2 S:S) of a deviator S, Pa.
double equivalent_stress(const Mat3& S);

} // namespace sphfem
