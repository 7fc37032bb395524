// Test helpers for tests/material: the Weldox 460 E library entries, and the closed forms of
// METHOD.md §5 written out again here, independently of solver/material, so that the tests
// compare the code with the formulas rather than with itself.
#pragma once

#include "solver/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace sphfem_test {

// cases/materials/weldox460e.yaml, optionally with --set style overrides.
inline std::vector<sphfem::MaterialSpec>
weldox_specs(const std::vector<std::string>& overrides = {}) {
  return sphfem::read_materials(std::string(SPHFEM_SOURCE_DIR) + "/cases/materials/weldox460e.yaml",
                                overrides);
}

// The entry `name` of `specs`.
inline const sphfem::MaterialSpec& entry(const std::vector<sphfem::MaterialSpec>& specs,
                                         const std::string& name) {
  const auto it = std::ranges::find(specs, name, &sphfem::MaterialSpec::name);
  EXPECT_NE(it, specs.end()) << name;
  return *it;
}

// Rate term of the flow stress (exponent C) or of the fracture strain (exponent D4) at the
// dimensionless rate x: Børvik's (1 + x)^C, or the paper's 1 + C ln x with x clamped at 1.
inline double rate_factor(bool log_form, double C, double x) {
  return log_form ? 1.0 + C * std::log(std::max(x, 1.0)) : std::pow(1.0 + x, C);
}

// Johnson–Cook flow stress of the intact material: [A + B rⁿ] [rate term] [1 − T*^m].
inline double jc_flow(const sphfem::MaterialSpec& s, double r, double rate, double T) {
  const sphfem::JohnsonCook& jc = *s.johnson_cook;
  const bool log_form = jc.rate_form == sphfem::RateForm::Log;
  const double t_star = std::clamp((T - jc.reference_temperature) /
                                       (jc.melting_temperature - jc.reference_temperature),
                                   0.0, 1.0);
  return (jc.A + jc.B * std::pow(r, jc.n)) *
         rate_factor(log_form, jc.C, rate / jc.reference_strain_rate) *
         (1.0 - std::pow(t_star, jc.m));
}

// Fracture strain p_f = [D1 + D2 exp(D3 σ*)] [rate term with D4] at T* = 0.
inline double fracture_strain(const sphfem::MaterialSpec& s, double triaxiality,
                              double plastic_rate) {
  const sphfem::DuctileDamage& d = *s.damage;
  const bool log_form = d.rate_form == sphfem::RateForm::Log;
  return (d.D1 + d.D2 * std::exp(d.D3 * triaxiality)) *
         rate_factor(log_form, d.D4, plastic_rate / s.johnson_cook->reference_strain_rate);
}

// Shear modulus G = E / 2(1 + ν) and bulk modulus K = E / 3(1 − 2ν).
inline double shear_modulus(const sphfem::MaterialSpec& s) {
  return s.youngs_modulus / (2.0 * (1.0 + s.poisson_ratio));
}
inline double bulk_modulus(const sphfem::MaterialSpec& s) {
  return s.youngs_modulus / (3.0 * (1.0 - 2.0 * s.poisson_ratio));
}

} // namespace sphfem_test
