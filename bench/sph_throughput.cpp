// SPH throughput: particle-steps and pair interactions per second of the particle phase
// (kick, drift, neighbour upkeep, kinematics, material update, forces) on a ~100k-particle
// steel block (h = 1.2 Δp, artificial viscosity, stress and XSPH on) set spinning and
// stretching, at 1 and 2 threads (or the thread counts given), with the default neighbour
// skin (0.1 × 2h, lists kept until a particle may have been missed) and with no skin (lists
// rebuilt every step); best of three. Prints JSON.
//   bench_sph_throughput [steps=50] [threads...=1 2]
#include "bench/stepping.hpp"
#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/time/simulation.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <iostream>

using namespace sphfem;

namespace {

const char* block_case = R"(
name: sph_throughput
time: {end: 1.0, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  block:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.046, 0.046, 0.046]}}
    spacing: 0.001
    material: steel
    velocity: [0, 0, 20.0]
)";

} // namespace

constexpr const char* kUsage =
    "usage: bench_sph_throughput [steps=50] [threads...=1 2]\n"
    "Particle-steps and pair interactions per second of the particle phase on a ~100k-particle\n"
    "block, with and without the neighbour skin, best of three. Prints JSON.\n";

int main(int argc, char** argv) {
  const bench::Options o = bench::parse(argc, argv, 50, kUsage);
  const Case with_skin = read_case_text(block_case, "sph_throughput.yaml");
  const Model model = mesh_case(with_skin);
  Case no_skin = with_skin;
  no_skin.sph.skin = 0.0;
  nlohmann::json out{{"benchmark", "sph_particle_phase"},
                     {"particles", model.particle_count()},
                     {"steps", o.steps}};
  double base = 0;
  for (const Case* c : std::array<const Case*, 2>{&with_skin, &no_skin})
    for (int t : o.threads) {
      double pairs = 0;
      long long rebuilds = 0;
      const double wall = bench::best_wall(*c, model, o.steps, t, [&](const Simulation& sim) {
        pairs = 0;
        for (int n : sim.particle_system().particles().neighbours_p)
          pairs += n;
        rebuilds = sim.particle_system().rebuilds();
      });
      const double rate = double(model.particle_count()) * o.steps / wall;
      if (base == 0)
        base = rate;
      // Each step visits every (i, j) entry twice: kinematics and forces.
      const double pair_rate = 2.0 * pairs * o.steps / wall;
      out["results"].push_back({{"threads", t},
                                {"skin", c->sph.skin},
                                {"neighbour_rebuilds", rebuilds},
                                {"wall_s", wall},
                                {"particle_steps_per_s", rate},
                                {"pair_interactions_per_s", pair_rate},
                                {"ns_per_pair_interaction_per_thread", 1e9 * t / pair_rate},
                                {"mean_neighbours", pairs / model.particle_count()},
                                {"speedup", rate / base}});
    }
  std::cout << out.dump(2) << std::endl;
  return 0;
}
