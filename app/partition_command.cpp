// `sphfem partition` (partition_command.hpp): options, the table, partition.json and the VTU
// files. No physics here: solver/parallel/.
#include "app/partition_command.hpp"

#include "post/run_balance.hpp"
#include "solver/coupling/interface_ties.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/model_vtu.hpp"
#include "solver/parallel/decomposition.hpp"
#include "solver/parallel/halo.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace sphfem {

namespace {

namespace fs = std::filesystem;

// One line in printf form.
template <typename... Values> std::string line(const char* pattern, Values... values) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

// The neighbour-list skin a run of this model would use (sph/particle_system.cpp): sph.skin ×
// twice the largest smoothing length of the particles and background particles.
double run_skin(const Case& c, const Model& model) {
  double largest_h = 0;
  for (const double h : model.h_p)
    largest_h = std::max(largest_h, h);
  for (const double h : model.h_background)
    largest_h = std::max(largest_h, h);
  return c.sph.skin * 2.0 * largest_h;
}

// [[x, y, z] low, [x, y, z] high]; null for an unbounded side.
nlohmann::json region(const Decomposition::Region& r) {
  nlohmann::json corners = nlohmann::json::array();
  for (const Vec3& x : {r.lo, r.hi}) {
    nlohmann::json corner = nlohmann::json::array();
    for (int k = 0; k < 3; ++k)
      corner.push_back(std::isfinite(x[k]) ? nlohmann::json(x[k]) : nlohmann::json(nullptr));
    corners.push_back(corner);
  }
  return corners;
}

} // namespace

CLI::App* add_partition_command(CLI::App& app, PartitionCommandOptions& o) {
  auto* cmd = app.add_subcommand(
      "partition", "share a case among N MPI ranks: the decomposition, its balance and halos");
  cmd->add_option("case", o.case_file, "case file (YAML, SI units)")->required();
  cmd->add_option("-o,--out", o.out_dir, "output folder (model.h5 is made or reused there)")
      ->required();
  cmd->add_option("-n,--ranks", o.ranks, "number of ranks (parts)")
      ->required()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--set", o.overrides, "override a case key (repeatable; value is YAML)")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_option("--run", o.run_dir,
                  "a finished run of the case (its OUT): each rank's cost frame by frame, "
                  "to OUT/partition_run.csv and .png");
  cmd->add_flag("-q,--quiet", o.quiet, "no table on stderr");
  cmd->footer(
      "Recursive coordinate bisection (Zoltan) of the particles and the hexahedra, weighted by\n"
      "each one's cost per step (bench/README.md's figures and its neighbour count); nodes go\n"
      "with their elements. Per rank: what it owns, its ghost points (particles and background\n"
      "particles of other ranks within h_i + h_j + skin of its own), its foreign nodes (nodes of\n"
      "its elements owned by another rank) and the halo fraction (ghosts + foreign nodes) /\n"
      "(own particles + own nodes). Writes OUT/partition.json, OUT/partition.vtu (hexahedra,\n"
      "cell and point array 'rank', point array 'shared') and OUT/partition_particles.vtu.\n"
      "With --run RUN (a finished run of the same case): each rank's cost per step in every\n"
      "frame, the particles alive then at their neighbour counts then, the elements not eroded,\n"
      "each entity kept on its rank of t = 0 or owned by the rank whose region (RCB's box) it\n"
      "is in then (OUT/partition_run.csv, .png; 'run' in partition.json) — how far the work\n"
      "drifts from the balance of t = 0 as the plug and debris leave.");
  return cmd;
}

void run_partition_command(const PartitionCommandOptions& o, const Case& c, const Model& model) {
  const EntityCosts costs = entity_costs(model, c.body_groups(), MirrorParticles(c));
  Decomposition d = decompose(model, costs, o.ranks);
  const InterfaceTies ties(c, model); // as the run shares them
  for (Index k = 0; k < ties.size(); ++k)
    d.tie(ties.particle_id(k), ties.node(k));
  const HaloCensus census = halo_census(model, costs, d, run_skin(c, model));

  nlohmann::json parts = nlohmann::json::array();
  double largest_halo = 0, halo_sum = 0;
  for (std::size_t q = 0; q < census.parts.size(); ++q) {
    const PartLoad& p = census.parts[q];
    largest_halo = std::max(largest_halo, p.halo_fraction());
    halo_sum += p.halo_fraction();
    parts.push_back({{"particles", p.particles},
                     {"elements", p.elements},
                     {"nodes", p.nodes},
                     {"shared_nodes", p.shared_nodes},
                     {"ghost_points", p.ghost_points},
                     {"foreign_nodes", p.foreign_nodes},
                     {"cost_s_per_step", p.cost_s},
                     {"halo_fraction", p.halo_fraction()},
                     {"region_m", region(d.regions[q])},
                     {"particle_region_m", region(d.particle_regions[q])}});
  }
  nlohmann::json summary = {
      {"ranks", o.ranks},
      {"method", "RCB (Zoltan) of the particles and of the hexahedra, weighted by cost per step"},
      {"skin_m", census.skin},
      {"imbalance", census.imbalance},
      {"halo_fraction", {{"max", largest_halo}, {"mean", halo_sum / o.ranks}}},
      {"parts", parts}};
  const fs::path out = o.out_dir;
  post::RunBalance run;
  if (!o.run_dir.empty()) {
    run = post::run_balance(o.run_dir, d, costs);
    // The largest imbalance of a series and when: {value, time_s}.
    const auto largest = [&run](const std::vector<double>& series) {
      const auto worst = std::max_element(series.begin(), series.end());
      return nlohmann::json{{"value", *worst}, {"at_s", run.time_s[worst - series.begin()]}};
    };
    summary["run"] = {{"dir", o.run_dir},
                      {"frames", run.time_s.size()},
                      {"entities_kept",
                       {{"imbalance_first", run.imbalance.front()},
                        {"imbalance_last", run.imbalance.back()},
                        {"imbalance_max", largest(run.imbalance)}}},
                      {"by_region",
                       {{"imbalance_first", run.region_imbalance.front()},
                        {"imbalance_last", run.region_imbalance.back()},
                        {"imbalance_max", largest(run.region_imbalance)}}}};
  }
  fs::create_directories(out);
  if (!run.time_s.empty())
    post::write_run_balance(run, out / "partition_run.csv", out / "partition_run.png");
  write_text_atomically(out / "partition.json", summary.dump(2) + "\n");

  VtuIntFields mesh, particles;
  mesh.cells["rank"] = d.part_e;
  mesh.points["rank"] = d.part_n;
  mesh.points["shared"].assign(d.shared_n.begin(), d.shared_n.end());
  particles.points["rank"] = d.part_p;
  write_model_vtu(model, out / "partition.vtu", mesh);
  write_particles_vtu(model, out / "partition_particles.vtu", particles);

  if (o.quiet)
    return;
  std::cerr << line("%5s %10s %10s %10s %8s %8s %8s %12s %6s\n", "rank", "particles", "elements",
                    "nodes", "shared", "ghosts", "foreign", "cost ms/step", "halo");
  for (std::size_t q = 0; q < census.parts.size(); ++q) {
    const PartLoad& p = census.parts[q];
    std::cerr << line("%5d %10d %10d %10d %8d %8d %8d %12.3f %6.3f\n", static_cast<int>(q),
                      p.particles, p.elements, p.nodes, p.shared_nodes, p.ghost_points,
                      p.foreign_nodes, p.cost_s * 1e3, p.halo_fraction());
  }
  std::cerr << line("imbalance %.4f (the worse phase's largest rank cost / mean), halo fraction "
                    "max %.3f mean "
                    "%.3f, skin %.3g m\n",
                    census.imbalance, largest_halo, halo_sum / o.ranks, census.skin)
            << "partition: " << (out / "partition.json").string() << ", "
            << (out / "partition.vtu").string() << "\n";
  if (!run.time_s.empty())
    std::cerr << "run " << o.run_dir
              << line(", %zu frames: imbalance, entities kept on their rank: %.4f first, %.4f "
                      "last; entities owned by their region: %.4f first, %.4f last",
                      run.time_s.size(), run.imbalance.front(), run.imbalance.back(),
                      run.region_imbalance.front(), run.region_imbalance.back())
              << " → " << (out / "partition_run.csv").string() << ", .png\n";
}

} // namespace sphfem
