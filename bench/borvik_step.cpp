// Coupled throughput: entity-steps (particles + hexahedra) per second of the whole coupled step on
// the Børvik case (cases/borvik_12mm/case.yaml, quarter model, standard preset unless overridden,
// 303.5 m/s): the projectile's hexahedra, the plate's ring of hexahedra, the SPH core, background
// particles, mirror images and the contact, all in one `Simulation::step`. Each thread
// count gets a fresh simulation, `warm_up` steps into the impact (contact, plasticity and the
// first damage on), then the best of five blocks of `steps` steps. Prints JSON, with the SPH
// pair interactions per second and the nanoseconds per pair interaction per thread.
//   bench_borvik_step [steps=100] [threads...=1 2] [--warm-up N=200] [--set key=value ...]
#include "bench/command_line.hpp"
#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/time/simulation.hpp"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <chrono>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

using namespace sphfem;

constexpr const char* kUsage =
    "usage: bench_borvik_step [steps=100] [threads...=1 2] [--warm-up N=200] [--set key=value "
    "...]\n"
    "Entity-steps per second of the whole coupled step on the Borvik case (quarter, standard,\n"
    "303.5 m/s), after N warm-up steps, best of five blocks; --set overrides a case key. Prints\n"
    "JSON.\n";

int main(int argc, char** argv) {
  bench::help(argc, argv, kUsage);
  int steps = 100, warm_up = 200;
  std::vector<int> positional, threads;
  std::vector<std::string> overrides;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--set" && a + 1 < argc)
      overrides.emplace_back(argv[++a]);
    else if (arg == "--warm-up" && a + 1 < argc)
      warm_up = bench::whole_number(argv[++a], kUsage);
    else
      positional.push_back(bench::whole_number(arg, kUsage));
  }
  if (!positional.empty())
    steps = positional.front();
  threads.assign(positional.begin() + (positional.empty() ? 0 : 1), positional.end());
  if (threads.empty())
    threads = {1, 2};
  const Case c = read_case(SPHFEM_SOURCE_DIR "/cases/borvik_12mm/case.yaml", overrides);
  const Model model = mesh_case(c);
  const double entities = double(model.particle_count() + model.element_count());
  nlohmann::json out{{"benchmark", "borvik_coupled_step"},
                     {"overrides", overrides},
                     {"particles", model.particle_count()},
                     {"elements", model.element_count()},
                     {"warm_up_steps", warm_up},
                     {"steps", steps}};
  double base = 0;
  for (int t : threads) {
    omp_set_num_threads(t);
    Simulation sim(c, model);
    for (int s = 0; s < warm_up; ++s)
      sim.step(sim.stable_dt());
    double wall = std::numeric_limits<double>::infinity();
    for (int block = 0; block < 5; ++block) {
      const auto start = std::chrono::steady_clock::now();
      for (int s = 0; s < steps; ++s)
        sim.step(sim.stable_dt());
      const auto stop = std::chrono::steady_clock::now();
      wall = std::min(wall, std::chrono::duration<double>(stop - start).count());
    }
    double pairs = 0;
    for (int n : sim.particle_system().particles().neighbours_p)
      pairs += n;
    const double rate = entities * steps / wall;
    if (base == 0)
      base = rate;
    // Each step visits every (i, j) entry twice: kinematics and forces.
    const double pair_rate = 2.0 * pairs * steps / wall;
    out["results"].push_back({{"threads", t},
                              {"wall_s", wall},
                              {"time_s", sim.time()},
                              {"entity_steps_per_s", rate},
                              {"ms_per_step", 1e3 * wall / steps},
                              {"pair_interactions_per_s", pair_rate},
                              {"ns_per_pair_interaction_per_thread", 1e9 * t / pair_rate},
                              {"speedup", rate / base}});
  }
  std::cout << out.dump(2) << std::endl;
  return 0;
}
