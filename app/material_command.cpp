// `sphfem material` (material_command.hpp): options, the chosen material, the driver's rows as
// CSV, the charts and the summary. No physics here: solver/material/material_driver.cpp.
#include "app/material_command.hpp"

#include "post/line_chart.hpp"
#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/material/material_driver.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace sphfem {

namespace {

namespace fs = std::filesystem;

const std::map<std::string, StrainPath> strain_paths{
    {"uniaxial-stress", StrainPath::UniaxialStress},
    {"uniaxial-strain", StrainPath::UniaxialStrain},
    {"shear", StrainPath::Shear}};

// %.10g: full enough to re-read the curve without visible round-off.
std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

Material chosen_material(const MaterialCommandOptions& o) {
  const std::vector<MaterialSpec> specs = read_materials(o.file);
  const auto spec = std::ranges::find(specs, o.material, &MaterialSpec::name);
  if (spec == specs.end()) {
    std::string names;
    for (const MaterialSpec& s : specs)
      names += (names.empty() ? "" : ", ") + s.name;
    throw Error(o.file + ": no material '" + o.material + "' (available: " + names + ")");
  }
  Material m = Material::from(*spec);
  if (o.no_heating)
    m.heating.reset();
  if (o.no_damage)
    m.damage.reset();
  return m;
}

std::string csv_text(const MaterialCommandOptions& o, const std::vector<DriverRow>& rows) {
  std::string text =
      "# sphfem material " + o.file + " --material " + o.material + " --path " + o.path +
      " --strain-rate " + number(o.strain_rate) + " --to " + number(o.to) +
      (o.temperature ? " --temperature " + number(*o.temperature) : "") +
      (o.no_heating ? " --no-heating" : "") + (o.no_damage ? " --no-damage" : "") +
      (o.band_width ? " --band-width " + number(*o.band_width) : "") + " --increments " +
      std::to_string(o.increments) + "\n" +
      "# strain: logarithmic strain eps = rate * t along x (shear: gamma = rate * t); stress: "
      "Cauchy, tension positive; pressure: compression positive\n"
      "time_s,strain,strain_rate_1_per_s,stress_xx_Pa,stress_yy_Pa,stress_zz_Pa,stress_xy_Pa,"
      "stress_yz_Pa,stress_zx_Pa,von_mises_Pa,pressure_Pa,plastic_strain,"
      "plastic_strain_rate_1_per_s,damage,temperature_K,density_kg_per_m3,failed\n";
  for (const DriverRow& r : rows) {
    const Mat3& s = r.stress;
    for (const double v : {r.time, r.strain, r.strain_rate, s(0, 0), s(1, 1), s(2, 2), s(0, 1),
                           s(1, 2), s(2, 0), r.von_mises, r.pressure, r.plastic_strain,
                           r.plastic_strain_rate, r.damage, r.temperature, r.density})
      text += number(v) + ",";
    text += r.failed ? "1\n" : "0\n";
  }
  return text;
}

void write_chart(const post::LineChart& chart, const fs::path& file) {
  chart.write_png(file);
}

// The von Mises stress against strain; with damage, a second chart <stem>_damage.png of plastic
// strain and damage. Returns the files written.
std::vector<fs::path> write_charts(const MaterialCommandOptions& o, const Material& m,
                                   const std::vector<DriverRow>& rows) {
  std::vector<double> strain, stress, plastic, damage;
  for (const DriverRow& r : rows) {
    strain.push_back(r.strain);
    stress.push_back(r.von_mises * 1e-6);
    plastic.push_back(r.plastic_strain);
    damage.push_back(r.damage);
  }
  const std::string x_label = o.path == "shear" ? "shear strain gamma" : "logarithmic strain";
  const std::string title = o.material + ", " + o.path + " at " + number(o.strain_rate) + " 1/s";
  const fs::path png = o.plot;
  std::vector<fs::path> written{png};

  post::LineChart chart(900, 560);
  chart.set_title(title);
  chart.set_x_label(x_label);
  chart.set_y_label("von Mises stress (MPa)");
  chart.add_series("von Mises", strain, stress, {post::LineChart::palette(0), 2.0, false});
  write_chart(chart, png);

  if (m.damage) {
    post::LineChart history(900, 560);
    history.set_title(title);
    history.set_x_label(x_label);
    history.set_y_label("plastic strain, damage");
    history.add_series("plastic strain", strain, plastic,
                       {post::LineChart::palette(0), 2.0, false});
    history.add_series("damage", strain, damage, {post::LineChart::palette(1), 2.0, false});
    written.push_back(png.parent_path() /
                      (png.stem().string() + "_damage" + png.extension().string()));
    write_chart(history, written.back());
  }
  return written;
}

void print_summary(const MaterialCommandOptions& o, const std::vector<DriverRow>& rows) {
  const auto peak = std::ranges::max_element(rows, {}, &DriverRow::von_mises);
  const auto failure = std::ranges::find(rows, true, &DriverRow::failed);
  std::cout << "material " << o.material << ": " << o.path << " at " << number(o.strain_rate)
            << " 1/s to strain " << number(o.to) << " in " << o.increments << " increments\n"
            << "peak von Mises " << number(peak->von_mises * 1e-6) << " MPa at strain "
            << number(peak->strain) << " (plastic strain " << number(peak->plastic_strain) << ")\n";
  if (failure != rows.end())
    std::cout << "failed at strain " << number(failure->strain) << ", plastic strain "
              << number(failure->plastic_strain) << " (damage " << number(failure->damage) << ")\n";
  else
    std::cout << "no failure: plastic strain " << number(rows.back().plastic_strain) << ", damage "
              << number(rows.back().damage) << " at the end\n";
  std::cout << "temperature " << number(rows.front().temperature) << " K to "
            << number(rows.back().temperature) << " K\n";
}

} // namespace

CLI::App* add_material_command(CLI::App& app, MaterialCommandOptions& o) {
  auto* cmd = app.add_subcommand(
      "material", "take one material point along a strain path: the solver's own stress update");
  cmd->footer(
      "Paths (x is the loading direction; strain is logarithmic, eps = rate * t):\n"
      "  uniaxial-stress  D = diag(rate, d, d); the lateral rate d is solved each increment so\n"
      "                   that the lateral stresses vanish: a tensile (rate > 0) or compression\n"
      "                   test, triaxiality 1/3 (or -1/3).\n"
      "  uniaxial-strain  D = diag(rate, 0, 0): the lateral strain held at zero, as behind a\n"
      "                   plane wave; pressure from the EOS.\n"
      "  shear            simple shear, velocity gradient L(x, y) = rate; strain is the shear\n"
      "                   gamma = rate * t. The volume is held, so the triaxiality is 0 only\n"
      "                   without an EOS: a Mie-Gruneisen EOS turns the work into pressure.\n"
      "Every increment runs the update the solver runs: density from the strain rate, pressure\n"
      "from the EOS, then the point update (Jaumann trial deviator, rate-dependent radial\n"
      "return, heating, damage, failure). --no-heating holds the temperature; the EOS still\n"
      "sees the work as internal energy. --band-width W: a regularised material (its\n"
      "damage.regularisation_length L) fails at p_f * L / W, as a point of that band width\n"
      "does in a run. Writes one CSV row per increment (SI units in the\n"
      "column names); see docs/materials.md. Example:\n"
      "  sphfem material cases/materials/weldox460e.yaml --material weldox460e \\\n"
      "    --path uniaxial-stress --strain-rate 1e-3 --to 2.0 -o weldox.csv --plot weldox.png");
  cmd->add_option("FILE", o.file, "material library (cases/materials/*.yaml) or case file")
      ->required();
  cmd->add_option("--material", o.material, "the material's name in FILE")->required();
  cmd->add_option("--path", o.path, "strain path: uniaxial-stress, uniaxial-strain or shear")
      ->check(CLI::IsMember(strain_paths))
      ->capture_default_str();
  cmd->add_option("--strain-rate", o.strain_rate,
                  "imposed strain rate, 1/s (negative: compression or reverse shear)")
      ->required();
  cmd->add_option("--to", o.to, "final strain, of the sign of the strain rate")->required();
  cmd->add_option_function<double>(
         "--temperature", [&o](const double& t) { o.temperature = t; },
         "initial temperature, K (default: the material's reference_temperature)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--no-heating", o.no_heating, "drop the material's adiabatic heating");
  cmd->add_flag("--no-damage", o.no_damage, "drop the material's damage (and so its failure)");
  cmd->add_option_function<double>(
         "--band-width", [&o](const double& w) { o.band_width = w; },
         "m: the point's band width in a run (2 h0 of a particle, the element size of a "
         "hexahedron); a regularised fracture strain is scaled by L / band width as the solver "
         "scales it (default: the calibrated law)")
      ->check(CLI::PositiveNumber)
      ->excludes("--no-damage");
  cmd->add_option("--increments", o.increments, "equal strain increments")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("-o,--out", o.csv, "output CSV file")->required();
  cmd->add_option("--plot", o.plot,
                  "PNG chart of von Mises stress against strain (with damage, also "
                  "<stem>_damage.png: plastic strain and damage)");
  return cmd;
}

void run_material_command(const MaterialCommandOptions& o) {
  const Material m = chosen_material(o);
  DriverOptions options;
  options.path = strain_paths.at(o.path);
  options.strain_rate = o.strain_rate;
  options.final_strain = o.to;
  options.increments = o.increments;
  options.initial_temperature = o.temperature;
  if (o.band_width) {
    SPHFEM_CHECK(m.regularised(), o.file, ": material '", o.material,
                 "' has no damage.regularisation_length, so --band-width changes nothing");
    options.band_width = *o.band_width;
  }
  const std::vector<DriverRow> rows = drive_material(m, options);

  write_text_atomically(o.csv, csv_text(o, rows));
  print_summary(o, rows);
  std::cout << "csv:    " << o.csv << "\n";
  if (!o.plot.empty())
    for (const fs::path& png : write_charts(o, m, rows))
      std::cout << "chart:  " << png.string() << "\n";
}

} // namespace sphfem
