// Unit tests of one material-point update (solver/material/material_point.hpp) and of the
// Mie–Grüneisen EOS (METHOD.md §5): the radial return lands on the damaged, rate- and
// temperature-dependent yield surface; heating and damage grow as their laws say; a point yields
// at its static flow stress; an elastic step stays elastic; the EOS matches its formula, its
// slope and its isentropic sound speed.
#include "reference.hpp"
#include "solver/material/material.hpp"
#include "solver/material/material_point.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <new>

namespace sphfem {
namespace {

using sphfem_test::entry;
using sphfem_test::weldox_specs;

double equivalent(const Mat3& S) {
  return std::sqrt(1.5 * (S.array() * S.array()).sum());
}

// A point part-way along its life: some plastic strain, damage and heat.
MaterialPoint worn_point() {
  MaterialPoint point;
  point.plastic_strain = 0.3;
  point.damaged_strain = 0.27;
  point.damage = 0.1;
  point.temperature = 500.0;
  return point;
}

// The damage a worn point gains in one step of a deviatoric stretch under tension, as a point of
// band `width` (m; 0: no size).
double damage_step(const Material& m, double width) {
  MaterialPoint point = worn_point();
  Mat3 S = Mat3::Zero();
  double pressure = -300e6;
  const Mat3 D = Vec3(100.0, -50.0, -50.0).asDiagonal();
  update_point(m, D, Mat3::Zero(), 1e-4, 7800.0, pressure, S, point, width);
  return point.damage - 0.1;
}

class ReturnMapping : public testing::TestWithParam<std::string> {};

// A deviatoric stretch far past yield (W = 0, so the trial deviator is S0 + 2G D′ Δt): the
// returned deviator is the trial scaled radially, and its equivalent stress is the flow stress
// (1 − D) σ_Y(r + (1 − D)Δp, (1 − D)Δp/Δt, T) at the start-of-step D and T, to the return's
// tolerance (|g| ≤ 1e-10 σ_trial, so 1e-8 relative is ample).
TEST_P(ReturnMapping, LandsOnTheYieldSurface) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, GetParam());
  const Material m = Material::from(spec);
  const double G = sphfem_test::shear_modulus(spec);
  const double dt = 1e-4;
  const Mat3 D = Vec3(100.0, -50.0, -50.0).asDiagonal(); // 1% axial strain in the step
  Mat3 S0 = Mat3::Zero();
  S0(0, 1) = S0(1, 0) = 200e6;
  const Mat3 trial = S0 + 2.0 * G * dt * D; // D is deviatoric already

  for (const double rate_scale : {1e-6, 1.0, 1e3}) { // ṗ* ≈ 0.15 (log clamp), 2e3, 2e6
    MaterialPoint point = worn_point();
    Mat3 S = S0;
    double pressure = -300e6;
    const Mat3 Ds = D * rate_scale;
    const double dts = dt / rate_scale;
    const double dp = update_point(m, Ds, Mat3::Zero(), dts, 7850.0, pressure, S, point, 0.0);
    ASSERT_GT(dp, 0.0);
    const double intact = 1.0 - 0.1;
    const double expected =
        intact * sphfem_test::jc_flow(spec, 0.27 + intact * dp, intact * dp / dts, 500.0);
    EXPECT_NEAR(equivalent(S), expected, 1e-8 * expected) << "rate scale " << rate_scale;
    // Radial: S = (1 − 3GΔp/σ_trial) S_trial.
    const double sigma_trial = equivalent(trial);
    EXPECT_NEAR((S - (1.0 - 3.0 * G * dp / sigma_trial) * trial).norm(), 0.0, 1e-9 * sigma_trial);
    EXPECT_NEAR(point.plastic_strain, 0.3 + dp, 1e-14);
    EXPECT_NEAR(point.damaged_strain, 0.27 + intact * dp, 1e-14);
  }
}

// Heating ΔT = χ σ_eq Δp/(ρ C_p) and damage ΔD = D_C Δp/(p_f − p_d), with σ* = −p/σ_eq,
// ṗ* = Δp/(Δt ṗ0) and T* of the step start.
TEST_P(ReturnMapping, HeatsAndDamagesAsTheLawsSay) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, GetParam());
  const Material m = Material::from(spec);
  MaterialPoint point = worn_point();
  Mat3 S = Mat3::Zero();
  double pressure = -300e6;
  const double dt = 1e-4, rho = 7800.0;
  const Mat3 D = Vec3(100.0, -50.0, -50.0).asDiagonal();
  const double dp = update_point(m, D, Mat3::Zero(), dt, rho, pressure, S, point, 0.0);
  const double sigma = equivalent(S);
  const double rise =
      spec.heating->taylor_quinney * sigma * dp / (rho * spec.heating->specific_heat);
  EXPECT_NEAR(point.temperature, 500.0 + rise, 1e-9 * rise);

  // D5 = 0, so the temperature does not enter p_f.
  const double p_f = sphfem_test::fracture_strain(spec, 300e6 / sigma, dp / dt);
  const double increment =
      spec.damage->critical_damage * dp / (p_f - spec.damage->threshold_strain);
  EXPECT_NEAR(point.damage, 0.1 + increment, 1e-9 * increment);
  EXPECT_FALSE(point.failed);
}

// A point yields (its next update enters the return, which the decomposition weighs) when its
// equivalent stress reaches the static flow stress (1 − D) σ_Y(r, 0, T) of the reference
// formula: a worn point 1% below it does not, 1% above it does; a point just returned lies on
// the rate-hardened surface, above it, and yields; a failed point and an elastic material never.
TEST_P(ReturnMapping, APointYieldsAtItsStaticFlowStress) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, GetParam());
  const Material m = Material::from(spec);
  const MaterialPoint point = worn_point();
  const double flow = (1.0 - 0.1) * sphfem_test::jc_flow(spec, 0.27, 0.0, 500.0);
  Mat3 direction = Mat3::Zero(); // a shear of equivalent stress 1 Pa
  direction(0, 1) = direction(1, 0) = 1.0 / std::sqrt(3.0);
  EXPECT_FALSE(yielding(m, 0.99 * flow * direction, point));
  EXPECT_TRUE(yielding(m, 1.01 * flow * direction, point));

  MaterialPoint returned = worn_point();
  Mat3 S = Mat3::Zero();
  double pressure = 0;
  const Mat3 D = Vec3(100.0, -50.0, -50.0).asDiagonal();
  ASSERT_GT(update_point(m, D, Mat3::Zero(), 1e-4, 7850.0, pressure, S, returned, 0.0), 0.0);
  EXPECT_TRUE(yielding(m, S, returned));

  MaterialPoint failed = worn_point();
  failed.failed = true;
  EXPECT_FALSE(yielding(m, 1.01 * flow * direction, failed));
  MaterialSpec elastic = spec;
  elastic.model = "elastic";
  elastic.johnson_cook.reset();
  elastic.damage.reset();
  elastic.heating.reset();
  EXPECT_FALSE(yielding(Material::from(elastic), 1e3 * flow * direction, point));
}

INSTANTIATE_TEST_SUITE_P(BothRateForms, ReturnMapping,
                         testing::Values("weldox460e", "weldox460e_paper"),
                         [](const auto& info) { return info.param; });

// The regularisation multiplies p_f by L / width (ductile_damage.hpp): one step's damage
// increment D_C Δp / (p_f L / w) (p_d = 0) is w / L times the calibrated one; without L, or for
// a point without a size (width 0), the step is the calibrated one.
TEST(Regularisation, ScalesTheDamageIncrementByWidthOverLength) {
  const double L = 1.5e-3;
  const auto plain = weldox_specs();
  const auto regularised =
      weldox_specs({"materials.weldox460e.damage.regularisation_length=" + std::to_string(L)});
  const Material calibrated = Material::from(entry(plain, "weldox460e"));
  const Material with_L = Material::from(entry(regularised, "weldox460e"));
  const double calibrated_step = damage_step(calibrated, 0.0);
  ASSERT_GT(calibrated_step, 0.0);
  EXPECT_NEAR(damage_step(calibrated, 2.4e-3), calibrated_step, 1e-15);
  EXPECT_NEAR(damage_step(with_L, 0.0), calibrated_step, 1e-15);
  for (const double width : {0.75e-3, 1.5e-3, 2.4e-3, 8e-3})
    EXPECT_NEAR(damage_step(with_L, width), calibrated_step * width / L, 1e-12 * width / L)
        << "width " << width;
}

// With an exponent β the factor is (L / width)^β: the step is (width / L)^β times the
// calibrated one, and at width = L the exponent does nothing.
TEST(Regularisation, AnExponentScalesTheFactorAsAPower) {
  const double L = 1.2e-3, beta = 0.6;
  const auto specs =
      weldox_specs({"materials.weldox460e.damage.regularisation_length=" + std::to_string(L),
                    "materials.weldox460e.damage.regularisation_exponent=" + std::to_string(beta)});
  const Material calibrated = Material::from(entry(weldox_specs(), "weldox460e"));
  const Material with_beta = Material::from(entry(specs, "weldox460e"));
  const double calibrated_step = damage_step(calibrated, 0.0);
  ASSERT_GT(calibrated_step, 0.0);
  EXPECT_NEAR(damage_step(with_beta, L), calibrated_step, 1e-12);
  for (const double width : {0.75e-3, 1.8e-3, 2.4e-3, 3.6e-3}) {
    const double scale = std::pow(width / L, beta);
    EXPECT_NEAR(damage_step(with_beta, width), calibrated_step * scale, 1e-12 * scale)
        << "width " << width;
  }
}

// Sheared at a constant rate with no pressure (σ* = 0), a point fails once p reaches
// p_f = (D1 + D2) (1 + ṗ*)^D4, times L / width with the regularisation: half the strain, so
// half the work per unit volume, in a band twice as wide.
TEST(Regularisation, APointInShearFailsAtTheScaledFractureStrain) {
  const double L = 1.2e-3;
  const auto specs =
      weldox_specs({"materials.weldox460e.damage.regularisation_length=" + std::to_string(L)});
  const MaterialSpec& spec = entry(specs, "weldox460e");
  const Material m = Material::from(spec);
  const double rate = 1e4, dt = 2e-8; // γ̇ = 2 × 10⁴ 1/s: ṗ ≈ 1.15 × 10⁴, Δp ≈ 2.3e-4 a step
  Mat3 D = Mat3::Zero();
  D(0, 1) = D(1, 0) = rate;
  for (const double width : {1.2e-3, 2.4e-3, 3.6e-3}) {
    MaterialPoint point = MaterialPoint::initial(m);
    point.temperature = spec.johnson_cook->reference_temperature;
    Mat3 S = Mat3::Zero();
    double dp = 0;
    for (int step = 0; step < 100000 && !point.failed; ++step) {
      double pressure = 0;
      dp = update_point(m, D, Mat3::Zero(), dt, 7850.0, pressure, S, point, width);
    }
    ASSERT_TRUE(point.failed) << "width " << width;
    const double p_f = sphfem_test::fracture_strain(spec, 0.0, dp / dt) * L / width;
    EXPECT_NEAR(point.plastic_strain, p_f, dp) << "width " << width;
  }
}

// Below yield the step is elastic: Δp = 0 and S = S0 + 2G D′ Δt exactly.
TEST(MaterialPoint, ElasticStepBelowYield) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, "weldox460e");
  const Material m = Material::from(spec);
  MaterialPoint point = worn_point();
  Mat3 S = Mat3::Zero();
  S(0, 0) = 100e6;
  S(1, 1) = S(2, 2) = -50e6;
  const Mat3 S0 = S;
  Mat3 D = Mat3::Zero();
  D(0, 1) = D(1, 0) = 1.0;
  D(2, 2) = 0.3; // a volumetric part too: only its deviator acts on S
  const double dt = 1e-5, G = sphfem_test::shear_modulus(spec);
  double pressure = 0;
  const double dp = update_point(m, D, Mat3::Zero(), dt, 7850.0, pressure, S, point, 0.0);
  EXPECT_NEAR(dp, 0.0, 0.0); // exactly: the return is not entered
  const Mat3 deviator = D - (0.3 / 3.0) * Mat3::Identity();
  EXPECT_NEAR((S - (S0 + 2.0 * G * dt * deviator)).norm(), 0.0, 1e-6); // Pa
  EXPECT_NEAR(point.plastic_strain, 0.3, 0.0);
  EXPECT_NEAR(point.damage, 0.1, 0.0);
  EXPECT_NEAR(point.temperature, 500.0, 0.0);
}

// A failed point carries no deviator and no tension, whatever it is given.
TEST(MaterialPoint, FailedPointIsStressFreeInTension) {
  const auto specs = weldox_specs();
  const Material m = Material::from(entry(specs, "weldox460e"));
  MaterialPoint point = worn_point();
  point.failed = true;
  Mat3 S = Mat3::Constant(1e8);
  double tension = -1e8, compression = 2e8;
  // Exact zeros: the failed branch sets them.
  EXPECT_NEAR(update_point(m, Mat3::Identity(), Mat3::Zero(), 1e-6, 7850, tension, S, point, 0.0),
              0.0, 0.0);
  EXPECT_NEAR(S.norm(), 0.0, 0.0);
  EXPECT_NEAR(tension, 0.0, 0.0);
  update_point(m, Mat3::Identity(), Mat3::Zero(), 1e-6, 7850, compression, S, point, 0.0);
  EXPECT_NEAR(compression, 2e8, 0.0); // crushed material still carries pressure
}

// ---- Mie–Grüneisen --------------------------------------------------------------------

// The EOS of the weldox entry, with its constants: ρ0 = 7850, c0 = 4569, s = 1.49,
// γ0 = 2.17, a = 0.46 (cases/materials/weldox460e.yaml).
struct Eos {
  double rho0 = 7850, c0 = 4569, s = 1.49, gamma0 = 2.17, a = 0.46;

  double pressure(double mu, double E) const {
    const double k = rho0 * c0 * c0;
    if (mu > 0)
      return k * mu * (1 + (1 - gamma0 / 2) * mu - (a / 2) * mu * mu) /
                 std::pow(1 - (s - 1) * mu, 2) +
             (gamma0 + a * mu) * E;
    return k * mu + (gamma0 + a * mu) * E;
  }
};

// A checkpoint stores a point's bytes: a point made where memory held other bytes, and copied,
// has the same bytes as one made on zeroed memory.
TEST(MaterialPoint, ItsBytesAreItsValues) {
  alignas(MaterialPoint) unsigned char dirty[sizeof(MaterialPoint)], clean[sizeof(MaterialPoint)];
  std::memset(dirty, 0xA5, sizeof dirty);
  std::memset(clean, 0, sizeof clean);
  auto* a = new (dirty) MaterialPoint(worn_point());
  auto* b = new (clean) MaterialPoint(worn_point());
  a->failed = b->failed = true;
  EXPECT_EQ(std::memcmp(dirty, clean, sizeof(MaterialPoint)), 0);
  std::memset(clean, 0x5A, sizeof clean);
  b = new (clean) MaterialPoint();
  *b = *a;
  EXPECT_EQ(std::memcmp(dirty, clean, sizeof(MaterialPoint)), 0);
}

TEST(MieGruneisen, PressureMatchesTheFormula) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, "weldox460e");
  ASSERT_TRUE(spec.eos);
  const Eos eos;
  EXPECT_NEAR(spec.density, eos.rho0, 0.0);
  for (const double mu : {0.1, 0.3, -0.05})
    for (const double E : {0.0, 2e8, -1e8}) {
      const double expected = eos.pressure(mu, E);
      EXPECT_NEAR(spec.eos->pressure(spec.density, mu, E), expected, 1e-12 * std::abs(expected))
          << "mu " << mu << ", E " << E;
      // Material::pressure takes the density.
      const Material m = Material::from(spec);
      EXPECT_NEAR(m.pressure(eos.rho0 * (1 + mu), E), expected, 1e-9 * std::abs(expected));
    }
}

// ∂p/∂μ at constant E against a central difference (step 1e-6: truncation ~1e-12, round-off
// ~1e-10 relative).
TEST(MieGruneisen, SlopeMatchesCentralDifference) {
  const auto specs = weldox_specs();
  const MieGruneisen& eos = *entry(specs, "weldox460e").eos;
  const Eos reference;
  const double h = 1e-6;
  for (const double mu : {0.1, 0.3, -0.05})
    for (const double E : {0.0, 2e8}) {
      const double fd = (reference.pressure(mu + h, E) - reference.pressure(mu - h, E)) / (2 * h);
      EXPECT_NEAR(eos.pressure_slope(7850, mu, E), fd, 1e-7 * fd) << "mu " << mu << ", E " << E;
    }
}

// Bulk sound speed² = dp/dρ along an isentrope, de = (p/ρ²) dρ with e = E/ρ0: a central
// difference along it (relative step 1e-6).
TEST(MieGruneisen, BulkSoundSpeedIsTheIsentropicSlope) {
  const auto specs = weldox_specs();
  const MieGruneisen& eos = *entry(specs, "weldox460e").eos;
  const Eos r;
  for (const double mu : {0.1, 0.3, -0.05})
    for (const double E : {0.0, 2e8}) {
      const double rho = r.rho0 * (1 + mu), p = r.pressure(mu, E);
      const double h = 1e-6 * rho, dE = r.rho0 * p / (rho * rho) * h;
      const double fd = (r.pressure((rho + h) / r.rho0 - 1, E + dE) -
                         r.pressure((rho - h) / r.rho0 - 1, E - dE)) /
                        (2 * h);
      EXPECT_NEAR(eos.bulk_sound_speed_squared(r.rho0, mu, E), fd, 1e-6 * fd)
          << "mu " << mu << ", E " << E;
    }
}

// The wave speed stays real over the range impacts reach, and at the reference state it is
// √(c0² + 4G/3ρ0).
TEST(MieGruneisen, SoundSpeedIsPositiveAndRightAtRest) {
  const auto specs = weldox_specs();
  const MaterialSpec& spec = entry(specs, "weldox460e");
  const Material m = Material::from(spec);
  for (int i = -10; i <= 30; ++i)
    for (const double E : {0.0, 5e8}) {
      const double c = m.sound_speed(spec.density * (1 + 0.01 * i), E);
      EXPECT_TRUE(std::isfinite(c) && c > 0) << "mu " << 0.01 * i << ", E " << E;
    }
  const double G = sphfem_test::shear_modulus(spec);
  const double expected = std::sqrt(4569.0 * 4569.0 + 4 * G / (3 * 7850.0));
  EXPECT_NEAR(m.sound_speed(7850.0, 0.0), expected, 1e-12 * expected);
}

} // namespace
} // namespace sphfem
