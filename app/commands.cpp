#include "app/commands.hpp"

#include "app/material_command.hpp"
#include "mesher/mesher.hpp"
#include "post/history_plot.hpp"
#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/io/model_h5.hpp"
#include "solver/io/model_vtu.hpp"
#include "solver/time/run.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <tuple>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sphfem {

namespace {

namespace fs = std::filesystem;

struct CommonOptions {
  std::string case_file;
  std::string out_dir;
  std::vector<std::string> overrides;
  int threads = 0;
  bool quiet = false;
};

void add_common(CLI::App& cmd, CommonOptions& o) {
  cmd.add_option("case", o.case_file, "case file (YAML, SI units)")->required();
  cmd.add_option("-o,--out", o.out_dir, "output folder")->required();
  cmd.add_option("--set", o.overrides,
                 "override a case key, e.g. --set time.end=1e-5 (repeatable; value is YAML)")
      ->take_all()
      ->allow_extra_args(false);
  cmd.add_option("-j,--threads", o.threads, "OpenMP threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  cmd.add_flag("-q,--quiet", o.quiet, "no log or progress on stderr (run.log still written)");
}

void set_threads(int threads) {
#ifdef _OPENMP
  if (threads > 0)
    omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

// Meshes the case and writes OUT/model.h5 and OUT/model.vtu.
Model mesh_and_write(const Case& c, const fs::path& out, bool quiet) {
  Model model = mesh_case(c);
  fs::create_directories(out);
  write_model_h5(model, out / "model.h5");
  write_model_vtu(model, out / "model.vtu");
  write_particles_vtu(model, out / "model_particles.vtu");
  if (!quiet)
    std::cerr << "mesh: " << model.node_count() << " nodes, " << model.element_count()
              << " hexahedra, " << model.particle_count() << " particles → "
              << (out / "model.h5").string() << ", " << (out / "model.vtu").string() << "\n";
  return model;
}

// OUT/model.h5 if it exists and was made from the same mesh keys, else a fresh mesh.
Model current_model(const Case& c, const fs::path& out, bool quiet) {
  const fs::path file = out / "model.h5";
  if (fs::exists(file)) {
    Model model = read_model_h5(file);
    if (model.signature == mesh_signature(c))
      return model;
    if (!quiet)
      std::cerr << "mesh: " << file.string() << " is stale (the case's mesh keys changed)\n";
  }
  return mesh_and_write(c, out, quiet);
}

void print_outputs(const fs::path& out, const nlohmann::json& summary) {
  std::cout << "results:  " << (out / "results.pvd").string() << "  (open in ParaView)\n"
            << "summary:  " << (out / "summary.json").string() << "\n"
            << "history:  " << (out / "history.csv").string() << "\n"
            << "energy balance error " << summary["energy"]["balance_error"].get<double>() << ", "
            << summary["steps"].get<long long>() << " steps in " << summary["wall_s"].get<double>()
            << " s\n";
}

void add_post_history(CLI::App& post, post::HistoryPlotOptions& o, std::string& size) {
  auto* history = post.add_subcommand(
      "history", "charts of run histories: one PNG and one CSV per column, runs compared");
  history->footer(
      "Writes DIR/<column>.png (the column against time, one curve per run, the reference\n"
      "dashed) and DIR/<column>.csv (series,time,value: exactly what is plotted, in the chart's\n"
      "units); DIR is -o, else RUN/post. Units: time by --time-unit, velocity m/s, stress and\n"
      "pressure GPa, displacement mm, energy J. Needs no display. Example:\n"
      "  sphfem post history out/bar_pressed_fe --compare out/bar_pressed_sph --columns mid.vz");
  history->add_option("RUN", o.run, "run folder (holding history.csv)")->required();
  history
      ->add_option("--columns", o.columns,
                   "columns to plot, comma-separated (default: every probe's vz and szz and "
                   "every body's vz)")
      ->delimiter(',');
  history->add_option("--compare", o.compare, "more run folders on the same axes")->expected(1, -1);
  history
      ->add_option("--label", o.labels,
                   "legend names of the run, then of each compared run (default: folder names)")
      ->expected(1, -1);
  history->add_option("--reference", o.reference,
                      "CSV with a time column (s) and columns named as in history.csv (SI), "
                      "plotted dashed");
  history->add_option("-o,--out", o.out_dir, "output folder (default: RUN/post)");
  history->add_option("--time-unit", o.time_unit, "time axis unit: s, ms, us or ns")
      ->capture_default_str();
  history->add_option("--size", size, "image size in pixels, WIDTHxHEIGHT")->capture_default_str();
}

} // namespace

int run_command_line(int argc, char** argv) {
  CLI::App app{"sphfem — coupled SPH–FEM impact dynamics (Zhang, Qiang & Gao 2011)", "sphfem"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sphfem 0.1.0");

  CommonOptions mesh_o, solve_o, run_o;
  auto* mesh = app.add_subcommand("mesh", "make OUT/model.h5 and OUT/model.vtu from a case");
  add_common(*mesh, mesh_o);
  auto* solve_cmd = app.add_subcommand(
      "solve", "run the simulation (meshes first if OUT/model.h5 is missing or stale)");
  add_common(*solve_cmd, solve_o);
  auto* run = app.add_subcommand("run", "mesh + solve: the one-command pipeline");
  add_common(*run, run_o);

  auto* post_cmd = app.add_subcommand("post", "charts and tables from a run's results");
  post_cmd->require_subcommand(1);
  post::HistoryPlotOptions history_o;
  std::string history_size = "900x560";
  add_post_history(*post_cmd, history_o, history_size);

  MaterialCommandOptions material_o;
  auto* material_cmd = add_material_command(app, material_o);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (mesh->parsed()) {
      const Case c = read_case(mesh_o.case_file, mesh_o.overrides);
      mesh_and_write(c, mesh_o.out_dir, mesh_o.quiet);
      return 0;
    }
    if (material_cmd->parsed()) {
      run_material_command(material_o);
      return 0;
    }
    if (post_cmd->parsed()) {
      std::tie(history_o.width, history_o.height) = post::parse_image_size(history_size);
      for (const auto& plot : post::plot_history(history_o))
        std::cout << "chart:  " << plot.png.string() << "  (data: " << plot.csv.string() << ")\n";
      return 0;
    }
    const bool remesh = run->parsed();
    const CommonOptions& o = remesh ? run_o : solve_o;
    set_threads(o.threads);
    const Case c = read_case(o.case_file, o.overrides);
    const fs::path out = o.out_dir;
    const Model model = remesh ? mesh_and_write(c, out, o.quiet) : current_model(c, out, o.quiet);
    const auto summary = solve(c, model, {out, !o.quiet});
    print_outputs(out, summary);
    return 0;
  } catch (const Error& e) {
    std::cerr << "sphfem: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "sphfem: internal error: " << e.what() << "\n";
    return 3;
  }
}

} // namespace sphfem
