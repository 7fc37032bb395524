// The material-point driver behind `sphfem material`: one material point taken along a
// homogeneous strain path, through exactly the update the solver runs (METHOD.md §5): per
// increment the density follows ρ ← ρ exp(−tr D Δt), the pressure comes from
// Material::pressure() at the new density, and update_point() advances deviator and history.
//   uniaxial-stress  D = diag(ε̇, d, d), the lateral rate d solved each increment so that
//                    σ_yy = σ_zz = 0 (to 1e-8 max(|σ_xx|, 1 Pa));
//   uniaxial-strain  D = diag(ε̇, 0, 0);
//   shear            simple shear, L = γ̇ e_x ⊗ e_y: D = sym L, W = skew L.
// Strain: the logarithmic strain ε = ε̇ t along x for the uniaxial paths, the shear γ = γ̇ t for
// shear. Internal energy per initial volume, for the EOS: E += ½(σ_n + σ_n+1):D Δt ρ0/ρ_n+1.
// Stress convention: σ = S − p I, tension positive. Verified by tests/material/.
#pragma once

#include "solver/core/types.hpp"
#include "solver/material/material.hpp"

#include <optional>
#include <vector>

namespace sphfem {

enum class StrainPath { UniaxialStress, UniaxialStrain, Shear };

struct DriverOptions {
  StrainPath path = StrainPath::UniaxialStress;
  double strain_rate = 1e-3; // ε̇ or γ̇, 1/s; negative: compression or reverse shear
  double final_strain = 0.1; // ε or γ at the end, of the sign of strain_rate
  int increments = 2000;     // equal increments of strain
  std::optional<double> initial_temperature; // K; default Material::initial_temperature()
  double band_width = 0; // m: the width the solver passes a point (2 h0 of a particle, ∛V0 of a
                         // hexahedron), scaling a regularised fracture strain by L / band_width;
                         // 0: the calibrated law
};

// The point's state after an increment (row 0: the initial state).
struct DriverRow {
  double time = 0;                // s
  double strain = 0;              // ε or γ
  double strain_rate = 0;         // imposed ε̇ or γ̇, 1/s
  Mat3 stress = Mat3::Zero();     // Cauchy stress σ = S − p I, Pa
  double von_mises = 0;           // Pa
  double pressure = 0;            // p, compression positive, Pa
  double plastic_strain = 0;      // p
  double plastic_strain_rate = 0; // Δp/Δt over the increment, 1/s
  double damage = 0;              // D
  double temperature = 0;         // K
  double density = 0;             // kg/m³
  bool failed = false;
};

// The path in `options.increments` equal increments; returns increments + 1 rows.
std::vector<DriverRow> drive_material(const Material& m, const DriverOptions& options);

} // namespace sphfem
