// FE throughput: element-steps per second of the explicit hexahedral step (element phase,
// gather, integration, constraints) on a ~50k-element block driven at one face, at 1 and 2
// threads (or the thread counts given as arguments); best of three repetitions each, since
// a shared virtual machine's timings scatter by ±20%. Prints JSON.
//   bench_fe_throughput [steps] [threads...]
#include "bench/stepping.hpp"
#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/time/simulation.hpp"

#include <nlohmann/json.hpp>

#include <iostream>

using namespace sphfem;

namespace {

const char* block_case = R"(
name: fe_throughput
time: {end: 1.0, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  block:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.04]}}
    element_size: 0.002
    material: steel
boundary_conditions:
  - {type: velocity, body: block, face: zmin, velocity: [0, 0, 50.0]}
)";

} // namespace

constexpr const char* kUsage =
    "usage: bench_fe_throughput [steps=200] [threads...=1 2]\n"
    "Element-steps per second of the explicit hexahedral step on a ~50k-element block, best of\n"
    "three per thread count. Prints JSON.\n";

int main(int argc, char** argv) {
  const bench::Options o = bench::parse(argc, argv, 200, kUsage);
  const Case c = read_case_text(block_case, "fe_throughput.yaml");
  const Model model = mesh_case(c);
  nlohmann::json out{{"benchmark", "fe_hex8_step"},
                     {"elements", model.element_count()},
                     {"nodes", model.node_count()},
                     {"steps", o.steps}};
  double base = 0;
  for (int t : o.threads) {
    const double wall = bench::best_wall(c, model, o.steps, t, [](const Simulation&) {});
    const double rate = double(model.element_count()) * o.steps / wall;
    if (base == 0)
      base = rate;
    out["results"].push_back({{"threads", t},
                              {"wall_s", wall},
                              {"element_steps_per_s", rate},
                              {"ns_per_element_step", 1e9 / rate},
                              {"speedup", rate / base}});
  }
  std::cout << out.dump(2) << std::endl;
  return 0;
}
