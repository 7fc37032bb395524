// A material as the solver uses it (STYLE.md C): linear elasticity plus, where the case asks
// for them, a Johnson–Cook strength, ductile damage, adiabatic heating and a Mie–Grüneisen
// equation of state (METHOD.md §5). What a material does not name costs nothing: an elastic
// material takes the same path as before any of these existed. Material::from() is the one
// registry from the case file's model name to a material.
#pragma once

#include "solver/material/adiabatic_heating.hpp"
#include "solver/material/ductile_damage.hpp"
#include "solver/material/elastic.hpp"
#include "solver/material/johnson_cook.hpp"
#include "solver/material/mie_gruneisen.hpp"

#include <cmath>
#include <optional>
#include <string_view>
#include <vector>

namespace sphfem {

// The model names a case file may give (materials.<name>.model).
inline const std::vector<std::string_view> material_models{"elastic", "johnson_cook"};

struct Material {
  ElasticConstants elastic{};
  std::optional<JohnsonCook> strength{};     // none: linear elastic deviator
  std::optional<DuctileDamage> damage{};     // only with a strength
  std::optional<AdiabaticHeating> heating{}; // only with a strength
  std::optional<MieGruneisen> eos{};         // none: p = K (ρ/ρ0 − 1)
  bool erosion = false;                      // hexahedra of this material are removed at failure

  static Material from(const MaterialSpec& spec);

  // Whether points of this material carry a plastic/damage/temperature history.
  bool inelastic() const { return strength.has_value(); }
  // Whether its fracture strain depends on a point's band width (ductile_damage.hpp).
  bool regularised() const { return damage && damage->regularisation_length > 0; }
  // The temperature points start at, K.
  double initial_temperature() const { return strength ? strength->reference_temperature : 293.0; }
  // Pressure (Pa, compression positive) at density ρ; `energy` is the internal energy per
  // initial volume (J/m³), used by the EOS only.
  double pressure(double rho, double energy) const {
    if (!eos)
      return elastic_pressure(elastic, rho);
    return eos->pressure(elastic.density, rho / elastic.density - 1.0, energy);
  }
  // Longitudinal wave speed for the time step and artificial viscosity, m/s.
  double sound_speed(double rho, double energy) const {
    if (!eos)
      return std::sqrt(elastic.p_wave_modulus() / rho);
    const double bulk =
        eos->bulk_sound_speed_squared(elastic.density, rho / elastic.density - 1.0, energy);
    return std::sqrt(std::max(bulk, 0.0) + 4.0 * elastic.shear / (3.0 * rho));
  }
};

} // namespace sphfem
