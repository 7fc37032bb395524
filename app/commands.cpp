#include "app/commands.hpp"

#include "app/material_command.hpp"
#include "app/partition_command.hpp"
#include "app/post_commands.hpp"
#include "app/sweep_command.hpp"
#include "mesher/mesher.hpp"
#include "solver/core/error.hpp"
#include "solver/fem/hex_quality.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/io/model_h5.hpp"
#include "solver/io/model_vtu.hpp"
#include "solver/parallel/ranks.hpp"
#include "solver/time/restart_check.hpp"
#include "solver/time/run.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
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
  std::string restart;     // solve and run
  double rebalance = 1.02; // solve and run, distributed
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

void add_solve_options(CLI::App& cmd, CommonOptions& o) {
  cmd.add_option("--restart", o.restart,
                 "continue from a checkpoint (OUT/checkpoint.h5): the case's physics must be the "
                 "checkpoint's; time.end and output keys may change");
  cmd.add_option("--rebalance", o.rebalance,
                 "under mpirun: share the work anew when the busiest rank's cost per step passes "
                 "this multiple of the mean and evening the ranks out would pay for the new cut "
                 "(checked at each history row and frame; 0: never)")
      ->default_val(1.02)
      ->check(CLI::Validator(
          [](const std::string& text) {
            const double v = std::strtod(text.c_str(), nullptr);
            return v == 0 || v >= 1
                       ? std::string()
                       : "expected 0 (never) or a multiple ≥ 1 of the mean, got " + text;
          },
          "0 or ≥ 1"));
}

void set_threads(int threads) {
#ifdef _OPENMP
  if (threads > 0)
    omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

// Each FE body's worst elements: the smallest scaled Jacobian and the shortest L_e (the stable
// step's length), with where they are.
void print_quality(const Case& c, const Model& model) {
  const auto at = [](const Vec3& x) {
    return "(" + std::to_string(x.x()) + ", " + std::to_string(x.y()) + ", " +
           std::to_string(x.z()) + ") m";
  };
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    if (c.bodies[b].method != Method::Fem)
      continue;
    const HexQuality q = hex_quality(model, static_cast<int>(b));
    std::cerr << "mesh: " << c.bodies[b].name << ": " << q.elements
              << " hexahedra, smallest scaled Jacobian " << q.scaled_jacobian << " at "
              << at(q.worst_jacobian_at) << ", shortest L_e " << q.length << " m at "
              << at(q.shortest_at) << "\n";
  }
}

// Meshes the case and writes OUT/model.h5 and OUT/model.vtu.
Model mesh_and_write(const Case& c, const fs::path& out, bool quiet) {
  Model model = mesh_case(c);
  fs::create_directories(out);
  write_model_h5(model, out / "model.h5");
  write_model_vtu(model, out / "model.vtu");
  write_particles_vtu(model, out / "model_particles.vtu");
  if (!quiet) {
    std::cerr << "mesh: " << model.node_count() << " nodes, " << model.element_count()
              << " hexahedra, " << model.particle_count() << " particles → "
              << (out / "model.h5").string() << ", " << (out / "model.vtu").string() << "\n";
    print_quality(c, model);
  }
  return model;
}

// OUT/model.h5 if it exists, is readable and was made from the same mesh keys, else a fresh mesh.
Model current_model(const Case& c, const fs::path& out, bool quiet) {
  const fs::path file = out / "model.h5";
  if (fs::exists(file)) {
    try {
      Model model = read_model_h5(file);
      if (model.signature == mesh_signature(c))
        return model;
      if (!quiet)
        std::cerr << "mesh: " << file.string() << " is stale (the case's mesh keys changed)\n";
    } catch (const Error& e) { // model.h5 is made from the case: an unreadable one is remade
      if (!quiet)
        std::cerr << "mesh: re-meshing, " << e.what() << "\n";
    }
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

// The model of a run: on one process as the pipeline asks (fresh, or OUT/model.h5 if current);
// in a distributed run rank 0 makes it (and alone writes model.h5) while the other ranks wait,
// then read that file. An error of rank 0's ends every rank (said by rank 0 only).
Model model_of_run(const Case& c, const fs::path& out, bool remesh, bool quiet) {
  const auto make = [&] {
    return remesh ? mesh_and_write(c, out, quiet) : current_model(c, out, quiet);
  };
  if (!ranks::distributed())
    return make();
  Model model;
  std::exception_ptr failure;
  if (ranks::rank() == 0) {
    try {
      model = make();
    } catch (...) {
      failure = std::current_exception();
    }
  }
  if (ranks::max(failure ? 1 : 0) != 0) {
    if (failure)
      std::rethrow_exception(failure);
    throw Error("rank 0 could not make the model");
  }
  if (ranks::rank() != 0)
    model = read_model_h5(out / "model.h5");
  return model;
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
  add_solve_options(*solve_cmd, solve_o);
  solve_cmd->footer(
      "A run writes OUT/checkpoint.h5 at its end, every output.checkpoint.steps steps and\n"
      "output.checkpoint.wall_s seconds (default 600), and when stopped by SIGINT/SIGTERM\n"
      "(Ctrl-C: it finishes the step, writes the checkpoint and exits with 130/143). Continue:\n"
      "  sphfem solve CASE -o OUT --restart OUT/checkpoint.h5 [--set time.end=...]\n"
      "The continued run writes what an uninterrupted one would, bit for bit.");
  auto* run = app.add_subcommand("run", "mesh + solve + report: the one-command pipeline");
  add_common(*run, run_o);
  add_solve_options(*run, run_o);
  run->footer("With --restart it continues the checkpoint's run (as solve does, re-meshing only\n"
              "if OUT/model.h5 is missing or stale) and then writes the report.");

  PostCommands post_commands(app);

  MaterialCommandOptions material_o;
  auto* material_cmd = add_material_command(app, material_o);

  SweepCommandOptions sweep_o;
  auto* sweep_cmd = add_sweep_command(app, sweep_o);

  PartitionCommandOptions partition_o;
  auto* partition_cmd = add_partition_command(app, partition_o);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  // Errors are said once, by rank 0, in a distributed run (every rank meets the same ones
  // before the step; one rank's own error in the step ends the job, run.cpp).
  const bool speaker = ranks::rank() == 0;
  try {
    SPHFEM_CHECK(!ranks::distributed() || run->parsed() || solve_cmd->parsed(), "started on ",
                 ranks::size(),
                 " MPI ranks: only `sphfem run` and `sphfem solve` share their work among ranks; "
                 "run the others without mpirun");
    if (mesh->parsed()) {
      const Case c = read_case(mesh_o.case_file, mesh_o.overrides);
      mesh_and_write(c, mesh_o.out_dir, mesh_o.quiet);
      return 0;
    }
    if (material_cmd->parsed()) {
      run_material_command(material_o);
      return 0;
    }
    if (sweep_cmd->parsed()) {
      run_sweep_command(sweep_o);
      return 0;
    }
    if (partition_cmd->parsed()) {
      const Case c = read_case(partition_o.case_file, partition_o.overrides);
      const Model model = current_model(c, partition_o.out_dir, partition_o.quiet);
      run_partition_command(partition_o, c, model);
      return 0;
    }
    if (post_commands.parsed()) {
      post_commands.run();
      return 0;
    }
    const bool pipeline = run->parsed();
    const CommonOptions& o = pipeline ? run_o : solve_o;
    set_threads(o.threads);
    const Case c = read_case(o.case_file, o.overrides);
    const fs::path out = o.out_dir;
    if (!o.restart.empty()) // refused before anything is meshed or written
      check_restart_case(o.restart, read_checkpoint_meta(o.restart), c);
    const bool remesh = pipeline && o.restart.empty();
    const Model model = model_of_run(c, out, remesh, o.quiet || !speaker);
    const auto summary = solve(c, model, {out, !o.quiet && speaker, o.restart, o.rebalance});
    if (!speaker)
      return 0;
    print_outputs(out, summary);
    if (pipeline)
      write_run_report(out);
    return 0;
  } catch (const Interrupted& e) {
    if (speaker)
      std::cerr << "sphfem: " << e.what() << "\n";
    return 128 + e.signal();
  } catch (const Error& e) {
    if (speaker)
      std::cerr << "sphfem: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    if (speaker)
      std::cerr << "sphfem: internal error: " << e.what() << "\n";
    return 3;
  }
}

} // namespace sphfem
