// `sphfem material`: one material of a library or case file taken along a strain path by the
// material-point driver (solver/material/material_driver.hpp, METHOD.md §5), written as CSV
// (and a PNG chart), with a short summary on stdout. Verified by
// tests/material/material_command_test.cpp.
#pragma once

#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace sphfem {

struct MaterialCommandOptions {
  std::string file;     // material library or case file
  std::string material; // its name there
  std::string path = "uniaxial-stress";
  double strain_rate = 0; // 1/s
  double to = 0;          // final strain
  std::optional<double> temperature;
  bool no_heating = false;
  bool no_damage = false;
  int increments = 2000;
  std::optional<double> band_width; // m; scales a regularised fracture strain by L / band_width
  std::string csv;
  std::string plot; // PNG; empty: none
};

// Adds the subcommand to `app`, filling `o` when it is parsed.
CLI::App* add_material_command(CLI::App& app, MaterialCommandOptions& o);

// Runs it; throws sphfem::Error on bad input.
void run_material_command(const MaterialCommandOptions& o);

} // namespace sphfem
