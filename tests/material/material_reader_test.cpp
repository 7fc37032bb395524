// Tests of reading material blocks (solver/io/case_reader.hpp, read_materials): a library entry
// with every block, the defaults, a case file read as a library, and one test per class of bad
// input, each checking the reported file, line and key path, and a file that is not there.
#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace sphfem {
namespace {

// A library with one Johnson–Cook material; the bad-input tests edit one line of it.
// Line numbers: 1 materials, 2 plate, 3 model, 7 johnson_cook, 8 A, 11 C, 12 rate_form.
const std::string kLibrary = R"(materials:
  plate:
    model: johnson_cook
    density: 7850
    youngs_modulus: 200.0e9
    poisson_ratio: 0.33
    johnson_cook:
      A: 490.0e6
      B: 807.0e6
      n: 0.73
      C: 0.0114
      rate_form: power
      reference_strain_rate: 5.0e-4
)";

// The same, ending in every optional block.
const std::string kFull = kLibrary + R"(      m: 0.94
      melting_temperature: 1800
      reference_temperature: 293
    damage: {D1: 0.0705, D2: 1.732, D3: -0.54, D4: -0.015, critical_damage: 0.3}
    heating: {specific_heat: 452}
    eos: {model: mie_gruneisen, c0: 4569, s: 1.49, gamma0: 2.17, a: 0.46}
    erosion: true
)";

// `text` with its one occurrence of `from` replaced by `to`.
std::string edited(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the library";
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// The message of the Error that reading `text` as "lib.yaml" throws.
std::string error_of(const std::string& text) {
  try {
    read_materials_text(text, "lib.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// `message` starts with `location_and_key` ("lib.yaml:12: materials.plate...: ") and holds `what`.
testing::AssertionResult reports(const std::string& message, const std::string& location_and_key,
                                 const std::string& what) {
  if (message.starts_with(location_and_key) && message.find(what) != std::string::npos)
    return testing::AssertionSuccess();
  return testing::AssertionFailure() << "message was: " << message;
}

TEST(MaterialReader, ReadsEveryBlock) {
  const auto specs = read_materials_text(kFull, "lib.yaml");
  ASSERT_EQ(specs.size(), 1u);
  const MaterialSpec& s = specs[0];
  EXPECT_EQ(s.name, "plate");
  EXPECT_EQ(s.model, "johnson_cook");
  ASSERT_TRUE(s.johnson_cook && s.damage && s.heating && s.eos);
  EXPECT_NEAR(s.johnson_cook->A, 490e6, 1e-6);
  EXPECT_NEAR(s.johnson_cook->n, 0.73, 1e-15);
  EXPECT_EQ(s.johnson_cook->rate_form, RateForm::Power);
  EXPECT_NEAR(s.johnson_cook->m, 0.94, 1e-15);
  EXPECT_NEAR(s.damage->D3, -0.54, 1e-15);
  EXPECT_EQ(s.damage->rate_form, RateForm::Power); // inherited from the flow stress
  EXPECT_NEAR(s.damage->D5, 0.0, 0.0);             // default
  EXPECT_NEAR(s.damage->threshold_strain, 0.0, 0.0);
  EXPECT_NEAR(s.damage->critical_damage, 0.3, 1e-15);
  EXPECT_NEAR(s.damage->regularisation_length, 0.0, 0.0); // default: p_f as calibrated
  EXPECT_NEAR(s.heating->taylor_quinney, 0.9, 1e-15);     // default
  EXPECT_NEAR(s.heating->specific_heat, 452, 1e-12);
  EXPECT_NEAR(s.eos->gamma0, 2.17, 1e-15);
  EXPECT_TRUE(s.erosion);
}

TEST(MaterialReader, ReadsTheMaterialsOfACaseFile) {
  const auto specs =
      read_materials(std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_pressed_fe/case.yaml");
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].name, "steel");
  EXPECT_EQ(specs[0].model, "elastic");
  EXPECT_FALSE(specs[0].johnson_cook);
}

TEST(MaterialReader, ReadsTheLibraries) {
  for (const char* file : {"weldox460e.yaml", "arne.yaml", "bar_steel.yaml"})
    EXPECT_NO_THROW(read_materials(std::string(SPHFEM_SOURCE_DIR) + "/cases/materials/" + file))
        << file;
}

TEST(MaterialReader, RejectsUnknownKeyInABlock) {
  EXPECT_TRUE(
      reports(error_of(edited(kLibrary, "      C: 0.0114\n", "      C: 0.0114\n      Q: 1\n")),
              "lib.yaml:12: materials.plate.johnson_cook.Q: ",
              "unknown key (expected one of: A, B, n, C, rate_form,"));
}

TEST(MaterialReader, RejectsJohnsonCookWithoutItsConstants) {
  const std::size_t block = kLibrary.find("    johnson_cook:");
  EXPECT_TRUE(reports(error_of(kLibrary.substr(0, block)),
                      "lib.yaml:3: materials.plate.johnson_cook: ", "missing key"));
}

TEST(MaterialReader, RejectsInelasticBlocksOnAnElasticMaterial) {
  const std::string elastic = R"(materials:
  plate:
    model: elastic
    density: 7850
    youngs_modulus: 200.0e9
    poisson_ratio: 0.33
    damage: {D1: 0.0705, D2: 1.732, D3: -0.54, D4: -0.015}
)";
  EXPECT_TRUE(reports(error_of(elastic),
                      "lib.yaml:7: materials.plate.damage: ", "needs model: johnson_cook"));
  EXPECT_TRUE(reports(error_of(edited(elastic,
                                      "damage: {D1: 0.0705, D2: 1.732, D3: -0.54, "
                                      "D4: -0.015}",
                                      "heating: {specific_heat: 452}")),
                      "lib.yaml:7: materials.plate.heating: ", "needs model: johnson_cook"));
}

TEST(MaterialReader, RejectsUnknownRateForm) {
  EXPECT_TRUE(reports(error_of(edited(kLibrary, "rate_form: power", "rate_form: linear")),
                      "lib.yaml:12: materials.plate.johnson_cook.rate_form: ",
                      "unknown rate form 'linear' (expected one of: power, log)"));
}

TEST(MaterialReader, RejectsBadValues) {
  EXPECT_TRUE(reports(error_of(edited(kLibrary, "n: 0.73", "n: 0")),
                      "lib.yaml:10: materials.plate.johnson_cook.n: ", "must be > 0"));
  EXPECT_TRUE(reports(error_of(edited(kFull, "critical_damage: 0.3", "critical_damage: 1.5")),
                      "lib.yaml:17: materials.plate.damage.critical_damage: ", "in (0, 1]"));
  EXPECT_TRUE(
      reports(error_of(edited(kFull, "critical_damage: 0.3",
                              "critical_damage: 0.3, regularisation_length: -1e-3")),
              "lib.yaml:17: materials.plate.damage.regularisation_length: ", "must be > 0 (m)"));
  EXPECT_TRUE(
      reports(error_of(edited(kFull, "critical_damage: 0.3",
                              "critical_damage: 0.3, regularisation_length: 1e-3, "
                              "regularisation_exponent: 0")),
              "lib.yaml:17: materials.plate.damage.regularisation_exponent: ", "in (0, 2]"));
  EXPECT_TRUE(reports(error_of(edited(kFull, "critical_damage: 0.3",
                                      "critical_damage: 0.3, regularisation_exponent: 0.5")),
                      "lib.yaml:17: materials.plate.damage.regularisation_exponent: ",
                      "give regularisation_length too"));
  EXPECT_TRUE(reports(error_of(edited(kFull, "model: mie_gruneisen", "model: ideal_gas")),
                      "lib.yaml:19: materials.plate.eos.model: ", "mie_gruneisen"));
  EXPECT_TRUE(reports(error_of(edited(kFull, "erosion: true", "erosion: 1.5")),
                      "lib.yaml:20: materials.plate.erosion: ", "true or false"));
}

TEST(MaterialReader, ErosionNeedsADamageBlock) {
  EXPECT_EQ(error_of(kLibrary + "    erosion: true\n"),
            "lib.yaml:14: materials.plate.erosion: needs a damage block: only failed elements are "
            "eroded");
}

TEST(MaterialReader, ReportsAMissingFile) {
  const std::string file = "no_such_library.yaml";
  try {
    read_materials(file);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(file + ": cannot open the materials file (", 0), 0u)
        << e.what();
  }
}

TEST(MaterialReader, MeltingMustExceedTheReferenceTemperature) {
  // Line 7: the johnson_cook block; its reference temperature above the default melting point.
  EXPECT_TRUE(reports(error_of(edited(kLibrary, "      A: 490.0e6",
                                      "      reference_temperature: 2000\n      A: 490.0e6")),
                      "lib.yaml:8: materials.plate.johnson_cook: ",
                      "melting_temperature (1800.000000 K) must exceed reference_temperature"));
}

} // namespace
} // namespace sphfem
