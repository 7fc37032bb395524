// Scaling: the cost per entity-step of the particle phase and of the hexahedral step at four
// sizes spanning 30× (SPH blocks of 22³ … 68³ particles, FE blocks of 5 000 … 152 000
// hexahedra), at 1 and 2 threads (or the thread counts given). Linear cost means a constant
// cost per entity-step; the JSON gives each size's ns per entity-step and its ratio to the
// smallest size's. Same scenes as bench_sph_throughput and bench_fe_throughput; best of three.
//   bench_scaling [steps=20] [threads...=1 2]
#include "bench/stepping.hpp"
#include "mesher/mesher.hpp"
#include "solver/io/case_reader.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <iostream>
#include <string>

using namespace sphfem;

namespace {

const std::string head = R"(
time: {end: 1.0, output_interval: 1.0}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
)";

// A cube of n³ particles at Δp = 1 mm (cell-centred), translating at 20 m/s.
std::string sph_block(int n) {
  const std::string edge = std::to_string(n * 1e-3);
  return "name: sph_scaling" + head +
         "bodies:\n  block:\n    method: sph\n    geometry: {box: {min: [0, 0, 0], max: [" + edge +
         ", " + edge + ", " + edge +
         "]}}\n    spacing: 0.001\n    material: steel\n    velocity: [0, 0, 20.0]\n";
}

// A block of nx × ny × nz hexahedra of 2 mm, driven at one face.
std::string fe_block(int nx, int ny, int nz) {
  const auto mm = [](int n) { return std::to_string(n * 2e-3); };
  return "name: fe_scaling" + head +
         "bodies:\n  block:\n    method: fem\n    geometry: {box: {min: [0, 0, 0], max: [" +
         mm(nx) + ", " + mm(ny) + ", " + mm(nz) +
         "]}}\n    element_size: 0.002\n    material: steel\n"
         "boundary_conditions:\n"
         "  - {type: velocity, body: block, face: zmin, velocity: [0, 0, 50.0]}\n";
}

} // namespace

constexpr const char* kUsage =
    "usage: bench_scaling [steps=20] [threads...=1 2]\n"
    "Cost per entity-step of the particle phase and the hexahedral step at four sizes spanning\n"
    "30x, best of three. Prints JSON.\n";

int main(int argc, char** argv) {
  const bench::Options o = bench::parse(argc, argv, 20, kUsage);
  nlohmann::json out{{"benchmark", "scaling"}, {"steps", o.steps}};
  const std::array<int, 4> cube{22, 32, 46, 68};
  const std::array<std::array<int, 3>, 4> boxes{
      {{25, 20, 10}, {35, 35, 12}, {50, 50, 20}, {75, 75, 27}}};
  for (int t : o.threads)
    for (const bool sph : {true, false}) {
      double smallest = 0;
      for (std::size_t s = 0; s < 4; ++s) {
        const std::string text =
            sph ? sph_block(cube[s]) : fe_block(boxes[s][0], boxes[s][1], boxes[s][2]);
        const Case c = read_case_text(text, "scaling.yaml");
        const Model model = mesh_case(c);
        const double entities = double(model.particle_count() + model.element_count());
        const double wall = bench::best_wall(c, model, o.steps, t, [](const Simulation&) {});
        const double ns = 1e9 * wall / (entities * o.steps);
        if (s == 0)
          smallest = ns;
        out["results"].push_back({{"kind", sph ? "sph_particles" : "fe_hexahedra"},
                                  {"threads", t},
                                  {"entities", entities},
                                  {"wall_s", wall},
                                  {"ns_per_entity_step", ns},
                                  {"relative_to_smallest", ns / smallest}});
      }
    }
  std::cout << out.dump(2) << std::endl;
  return 0;
}
