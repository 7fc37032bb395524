// Verification of the material-point driver (solver/material/material_driver.hpp) against the
// closed forms of METHOD.md §5 for Weldox 460 E (cases/materials/weldox460e.yaml): the flow
// curve in uniaxial stress at three rates and both rate forms, adiabatic heating and thermal
// softening, the failure strain of the damage law in uniaxial stress and in shear (with and
// without a threshold strain), and the elastic paths against their exact solutions.
#include "reference.hpp"
#include "solver/core/error.hpp"
#include "solver/material/material_driver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

namespace sphfem {
namespace {

using sphfem_test::entry;
using sphfem_test::fracture_strain;
using sphfem_test::jc_flow;
using sphfem_test::weldox_specs;

const double T0 = 293.0; // reference temperature of the weldox entries, K

Material without(Material m, bool heating, bool damage) {
  if (!heating)
    m.heating.reset();
  if (!damage)
    m.damage.reset();
  return m;
}

std::vector<DriverRow> uniaxial_stress(const Material& m, double rate, double to, int n) {
  DriverOptions o;
  o.strain_rate = rate;
  o.final_strain = to;
  o.increments = n;
  return drive_material(m, o);
}

// The first failed row, or the end.
auto first_failure(const std::vector<DriverRow>& rows) {
  return std::ranges::find(rows, true, &DriverRow::failed);
}

class DriverFlowCurve : public testing::TestWithParam<std::tuple<std::string, double>> {};

// Damage and heating off: every plastic row lies on [A + B pⁿ] [rate term]. With the row's own
// plastic rate this is the return's consistency (1e-8); with the imposed rate ε̇ it is the 0.5%
// of the acceptance: beyond p = 0.01 the hardening slope is below 2.1 GPa ≈ 1% of E, so
// ṗ ≥ 0.99 ε̇ and the rate terms differ by less than C · 1% ≈ 1e-4. The lateral stresses vanish
// to the driver's tolerance and the pressure is −σ_xx/3 (triaxiality 1/3).
TEST_P(DriverFlowCurve, UniaxialStressFollowsJohnsonCook) {
  const auto [name, rate] = GetParam();
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, name);
  const auto rows = uniaxial_stress(without(Material::from(spec), false, false), rate, 0.5, 1000);
  ASSERT_EQ(rows.size(), 1001u);
  int checked = 0;
  for (const DriverRow& r : rows) {
    const double sxx = std::abs(r.stress(0, 0));
    EXPECT_LE(std::abs(r.stress(1, 1)), 1e-8 * std::max(sxx, 1.0));
    EXPECT_LE(std::abs(r.stress(2, 2)), 1e-8 * std::max(sxx, 1.0));
    EXPECT_NEAR(r.pressure, -r.stress(0, 0) / 3, 1e-8 * std::max(sxx, 1.0));
    if (r.plastic_strain < 0.01)
      continue;
    ++checked;
    const double own = jc_flow(spec, r.plastic_strain, r.plastic_strain_rate, T0);
    EXPECT_NEAR(r.von_mises, own, 1e-8 * own) << "p = " << r.plastic_strain;
    const double imposed = jc_flow(spec, r.plastic_strain, rate, T0);
    EXPECT_NEAR(r.von_mises, imposed, 5e-3 * imposed) << "p = " << r.plastic_strain;
    EXPECT_NEAR(r.temperature, T0, 0.0); // heating off: exactly the initial temperature
  }
  EXPECT_GT(checked, 900);
}

INSTANTIATE_TEST_SUITE_P(
    RatesAndForms, DriverFlowCurve,
    testing::Combine(testing::Values("weldox460e", "weldox460e_paper"),
                     testing::Values(1e-3, 1.0, 1e3)),
    [](const auto& info) {
      const double rate = std::get<1>(info.param);
      return std::get<0>(info.param) + "_rate" + (rate < 1 ? "1em3" : rate > 1 ? "1e3" : "1");
    });

// Heating on, damage off, at 1000/s: the temperature is the integral of χ σ_eq dp/(ρ C_p)
// (trapezoid over the rows, within 1% from p = 0.05 on: the code takes the end-of-step stress,
// and over the increment that crosses yield the two differ by ~10%), the flow stress is softened by
// 1 − T*^m at the temperature of the step start, and so lies below the isothermal curve.
TEST(DriverHeating, TemperatureIsThePlasticWorkAndSoftens) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, "weldox460e");
  const Material m = Material::from(spec);
  const auto hot = uniaxial_stress(without(m, true, false), 1e3, 1.0, 1000);
  const auto cold = uniaxial_stress(without(m, false, false), 1e3, 1.0, 1000);
  const double chi = 0.9, Cp = 452; // taylor_quinney, specific_heat of the yaml
  double rise = 0;
  for (std::size_t i = 1; i < hot.size(); ++i) {
    const DriverRow &a = hot[i - 1], &b = hot[i];
    rise += 0.5 * chi * (a.von_mises / (a.density * Cp) + b.von_mises / (b.density * Cp)) *
            (b.plastic_strain - a.plastic_strain);
    if (b.plastic_strain >= 0.05) {
      EXPECT_NEAR(b.temperature - T0, rise, 0.01 * rise) << "row " << i;
    }
    if (b.plastic_strain >= 0.01) {
      const double expected = jc_flow(spec, b.plastic_strain, b.plastic_strain_rate, a.temperature);
      EXPECT_NEAR(b.von_mises, expected, 1e-8 * expected) << "row " << i;
      EXPECT_LT(b.von_mises, cold[i].von_mises) << "row " << i;
    }
  }
  // The softening matters: about 19% at the end (ΔT ≈ 256 K, T* ≈ 0.17, 1 − T*^0.94 ≈ 0.81).
  EXPECT_GT(hot.back().temperature - T0, 200.0);
  EXPECT_LT(hot.back().von_mises, 0.85 * cold.back().von_mises);
}

class DriverFailure : public testing::TestWithParam<std::string> {};

// Damage on, heating off, uniaxial stress at 1e-3/s (σ* = 1/3, ṗ* ≈ 2): D grows as the sum of
// D_C Δp/p_f(1/3, ṗ) over the rows, the stress is (1 − D) σ_Y(r, (1 − D)ṗ) with r the
// damage-accumulated strain, the point fails at p = p_f(1/3, 2) within 1%, and from then on
// every stress component is zero.
TEST_P(DriverFailure, UniaxialStressFailsAtTheFractureStrain) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, GetParam());
  const auto rows = uniaxial_stress(without(Material::from(spec), false, true), 1e-3, 2.0, 2000);
  const auto failed = first_failure(rows);
  ASSERT_NE(failed, rows.end());
  const double p_f = fracture_strain(spec, 1.0 / 3.0, 1e-3);
  EXPECT_NEAR(failed->plastic_strain, p_f, 0.01 * p_f);

  double D = 0, r = 0;
  for (auto row = rows.begin() + 1; row != failed; ++row) {
    const DriverRow& before = *(row - 1);
    const double dp = row->plastic_strain - before.plastic_strain;
    const double intact = 1.0 - before.damage;
    r += intact * dp;
    if (dp > 0) {
      const double flow = intact * jc_flow(spec, r, intact * row->plastic_strain_rate, T0);
      EXPECT_NEAR(row->von_mises, flow, 1e-8 * flow);
      const double triaxiality = -row->pressure / row->von_mises;
      EXPECT_NEAR(triaxiality, 1.0 / 3.0, 1e-7);
      D += 0.3 * dp / fracture_strain(spec, 1.0 / 3.0, row->plastic_strain_rate);
    }
    EXPECT_NEAR(row->damage, D, 1e-8);
  }
  EXPECT_NEAR(failed->damage, 0.3, 1e-12);
  for (auto row = failed; row != rows.end(); ++row) {
    EXPECT_NEAR(row->stress.norm(), 0.0, 0.0) << "strain " << row->strain; // exactly zero
    EXPECT_NEAR(row->von_mises, 0.0, 0.0);
    EXPECT_TRUE(row->failed);
    EXPECT_NEAR(row->damage, 0.3, 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(BothRateForms, DriverFailure,
                         testing::Values("weldox460e", "weldox460e_paper"),
                         [](const auto& info) { return info.param; });

// A threshold p_d = 0.5: no damage below it, D = D_C (p − p_d)/(p_f − p_d) above, failure still
// at p_f.
TEST(DriverDamage, ThresholdStrainDelaysDamageNotFailure) {
  const auto specs = weldox_specs({"materials.weldox460e.damage.threshold_strain=0.5"});
  const MaterialSpec& spec = entry(specs, "weldox460e");
  ASSERT_NEAR(spec.damage->threshold_strain, 0.5, 0.0);
  const auto rows = uniaxial_stress(without(Material::from(spec), false, true), 1e-3, 2.0, 2000);
  const auto failed = first_failure(rows);
  ASSERT_NE(failed, rows.end());
  const double p_f = fracture_strain(spec, 1.0 / 3.0, 1e-3);
  EXPECT_NEAR(failed->plastic_strain, p_f, 0.01 * p_f);
  for (auto row = rows.begin(); row != failed; ++row) {
    const double p = row->plastic_strain;
    const double expected = p < 0.5 ? 0.0 : 0.3 * (p - 0.5) / (p_f - 0.5);
    EXPECT_NEAR(row->damage, expected, 0.01 * 0.3) << "p = " << p;
  }
}

// Damage on, heating and EOS off (p = K(ρ/ρ0 − 1) = 0 in shear, which keeps the volume).
Material without_eos(Material m) {
  m = without(m, false, true);
  m.eos.reset();
  return m;
}

// Simple shear at γ̇ = √3 · 1e-3/s (ṗ ≈ 1e-3/s) to ṗ t = p_end, 1000 increments per unit of p.
DriverOptions shear_to(double p_end) {
  DriverOptions o;
  o.path = StrainPath::Shear;
  o.strain_rate = std::sqrt(3.0) * 1e-3;
  o.final_strain = std::sqrt(3.0) * p_end;
  o.increments = int(1000 * p_end);
  return o;
}

// Simple shear of a material without EOS (p = K(ρ/ρ0 − 1) = 0: shear keeps the volume), so
// σ* = 0 and p_f = (D1 + D2) (1 + ṗ*)^D4. γ̇ = √3 · 1e-3/s gives ṗ ≈ 1e-3/s.
TEST(DriverDamage, ShearFailsAtZeroTriaxiality) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, "weldox460e");
  const auto rows = drive_material(without_eos(Material::from(spec)), shear_to(2.5));
  const auto failed = first_failure(rows);
  ASSERT_NE(failed, rows.end());
  const double p_f = (0.0705 + 1.732) * std::pow(1.0 + 2.0, -0.015); // D1, D2, D4 of the yaml
  EXPECT_NEAR(failed->plastic_strain, p_f, 0.01 * p_f);
  for (auto row = rows.begin(); row != failed; ++row) {
    EXPECT_NEAR(row->pressure, 0.0, 0.0); // exactly: tr D = 0 keeps ρ = ρ0
    EXPECT_NEAR(row->density, 7850.0, 0.0);
  }
  for (auto row = failed; row != rows.end(); ++row)
    EXPECT_NEAR(row->stress.norm(), 0.0, 0.0);
}

// A regularised fracture strain (L = 1.3 mm) in the same shear: at band width w the point fails
// at p_f × L / w — later than calibrated for w < L, earlier for w > L — and at w = 0 (a sizeless
// point) at p_f itself. A band width on a material without L is an error, as is a negative one.
TEST(DriverDamage, BandWidthScalesARegularisedFractureStrain) {
  const auto specs = weldox_specs({"materials.weldox460e.damage.regularisation_length=0.0013"});
  const Material m = without_eos(Material::from(entry(specs, "weldox460e")));
  DriverOptions o = shear_to(5.0);
  const double p_f = (0.0705 + 1.732) * std::pow(1.0 + 2.0, -0.015);
  for (const double w : {0.0, 0.001, 0.0024}) {
    o.band_width = w;
    const auto rows = drive_material(m, o);
    const auto failed = first_failure(rows);
    ASSERT_NE(failed, rows.end()) << "w = " << w;
    const double expected = w > 0 ? p_f * 0.0013 / w : p_f;
    EXPECT_NEAR(failed->plastic_strain, expected, 0.01 * expected) << "w = " << w;
  }
  o.band_width = -1e-3;
  EXPECT_THROW(drive_material(m, o), Error);
  o.band_width = 0.0024;
  const auto plain = weldox_specs();
  EXPECT_THROW(drive_material(Material::from(entry(plain, "weldox460e")), o), Error);
}

// Elastic paths against their exact solutions (steel of cases/materials/bar_steel.yaml, no EOS):
// uniaxial strain σ_xx = (4G/3) ε − K (e^−ε − 1) with ε logarithmic and ρ = ρ0 e^−ε; simple
// shear with the Jaumann rate σ_xy = G sin γ, σ_xx = −σ_yy = G (1 − cos γ). The update rotates
// the old deviator and then adds 2G D′ Δt unrotated, so in shear it is first order in Δγ (the
// normal stresses lag by about G γ Δγ/2) although the rotation itself is second order.
TEST(DriverElasticPaths, MatchExactSolutions) {
  const auto specs =
      read_materials(std::string(SPHFEM_SOURCE_DIR) + "/cases/materials/bar_steel.yaml");
  const MaterialSpec& spec = entry(specs, "steel");
  const Material m = Material::from(spec);
  const double G = sphfem_test::shear_modulus(spec), K = sphfem_test::bulk_modulus(spec);

  DriverOptions o;
  o.path = StrainPath::UniaxialStrain;
  o.strain_rate = -1e3;
  o.final_strain = -0.05;
  o.increments = 100;
  for (const DriverRow& r : drive_material(m, o)) {
    const double e = r.strain;
    const double sxx = 4 * G / 3 * e - K * (std::exp(-e) - 1);
    EXPECT_NEAR(r.stress(0, 0), sxx, 1e-9 * std::abs(sxx) + 1e-3) << "strain " << e;
    EXPECT_NEAR(r.density, 7830 * std::exp(-e), 1e-9);
  }

  // Shear to γ = 1 at Δγ = 1e-3 and 5e-4: the error is below Δγ/2 · G and halves with Δγ.
  o.path = StrainPath::Shear;
  o.strain_rate = 1.0;
  o.final_strain = 1.0;
  std::vector<double> errors;
  for (const int n : {1000, 2000}) {
    o.increments = n;
    double worst = 0;
    for (const DriverRow& r : drive_material(m, o)) {
      const double g = r.strain;
      worst = std::max({worst, std::abs(r.stress(0, 1) - G * std::sin(g)),
                        std::abs(r.stress(0, 0) - G * (1 - std::cos(g)))});
      EXPECT_NEAR(r.stress(1, 1), -r.stress(0, 0), 1e-12 * G);
    }
    EXPECT_LT(worst, 0.5 * G / n);
    errors.push_back(worst);
  }
  EXPECT_NEAR(errors[0] / errors[1], 2.0, 0.1); // first order
}

// Bad options are errors, not NaNs.
TEST(Driver, RejectsBadOptions) {
  const auto specs = weldox_specs();
  const Material m = Material::from(entry(specs, "weldox460e"));
  DriverOptions o;
  o.strain_rate = 0;
  EXPECT_THROW(drive_material(m, o), Error);
  o.strain_rate = 1;
  o.final_strain = -1;
  EXPECT_THROW(drive_material(m, o), Error);
  o.final_strain = 1;
  o.increments = 0;
  EXPECT_THROW(drive_material(m, o), Error);
}

} // namespace
} // namespace sphfem
