// Neighbour search throughput: builds the SPH neighbour lists (solver/sph/neighbour_search,
// METHOD.md §2) for 100k particles on a jittered lattice (50 × 50 × 40, jitter ±0.1 Δp,
// h = 1.2 Δp, so ~56 neighbours without skin) at 1 and 2 threads (or the thread counts given),
// without and with a skin of 0.1 × 2h, for two particle orders: lattice order (x fastest, the
// mesher's, which the solver keeps) and shuffled. Best of the repetitions (a shared virtual
// machine's timings scatter). Also times needs_update. Prints JSON.
//   bench_neighbour_search [repetitions] [threads...]
#include "solver/sph/neighbour_search.hpp"
#include "bench/command_line.hpp"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <limits>
#include <numeric>
#include <random>
#include <string>

using namespace sphfem;

namespace {

constexpr double dp = 1e-3;

struct Particles {
  std::vector<Vec3> x;
  std::vector<double> h;
};

Particles jittered_lattice(int nx, int ny, int nz) {
  std::mt19937 rng(2024u);
  std::uniform_real_distribution<double> jitter(-0.1 * dp, 0.1 * dp);
  Particles p;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        p.x.push_back(dp * Vec3(i, j, k) + Vec3(jitter(rng), jitter(rng), jitter(rng)));
        p.h.push_back(1.2 * dp);
      }
  return p;
}

Particles permuted(const Particles& in, const std::vector<Index>& new_to_old) {
  Particles out;
  for (Index old : new_to_old) {
    out.x.push_back(in.x[old]);
    out.h.push_back(in.h[old]);
  }
  return out;
}

template <class Work> double best_ms(int repetitions, Work work) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    const std::chrono::duration<double, std::milli> wall = std::chrono::steady_clock::now() - start;
    best = std::min(best, wall.count());
  }
  return best;
}

} // namespace

constexpr const char* kUsage =
    "usage: bench_neighbour_search [repetitions=7] [threads...=1 2]\n"
    "Builds the SPH neighbour lists for 100k particles in two particle orders, without and with\n"
    "a skin, best of the repetitions. Prints JSON.\n";

int main(int argc, char** argv) {
  bench::help(argc, argv, kUsage);
  const int repetitions = argc > 1 ? bench::whole_number(argv[1], kUsage) : 7;
  std::vector<int> threads;
  for (int i = 2; i < argc; ++i)
    threads.push_back(bench::whole_number(argv[i], kUsage));
  if (threads.empty())
    threads = {1, 2};

  const Particles lattice = jittered_lattice(50, 50, 40);
  std::vector<Index> shuffle(lattice.x.size());
  std::iota(shuffle.begin(), shuffle.end(), 0);
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(7u));
  const Particles shuffled = permuted(lattice, shuffle);

  nlohmann::json runs = nlohmann::json::array();
  for (const double skin : {0.0, 0.24 * dp}) {
    const std::vector<std::pair<std::string, const Particles*>> orders{{"lattice", &lattice},
                                                                       {"shuffled", &shuffled}};
    for (const auto& [order, p] : orders) {
      nlohmann::json timings = nlohmann::json::array();
      double base = 0;
      std::size_t entries = 0;
      for (int t : threads) {
        omp_set_num_threads(t);
        NeighbourSearch search;
        search.build(p->x, p->h, skin); // warm-up: buffers reach their size
        const double build = best_ms(repetitions, [&] { search.build(p->x, p->h, skin); });
        bool update = false;
        const double check =
            best_ms(repetitions, [&] { update = update || search.needs_update(p->x, p->h); });
        entries = search.list().pair_count();
        base = base > 0 ? base : build;
        timings.push_back({{"threads", t},
                           {"build_ms", build},
                           {"pairs_per_s", 0.5 * static_cast<double>(entries) / (build * 1e-3)},
                           {"speedup", base / build},
                           {"needs_update_ms", check},
                           {"needs_update", update}});
      }
      runs.push_back({{"order", order},
                      {"skin_over_dp", skin / dp},
                      {"pairs", entries / 2},
                      {"list_entries", entries},
                      {"neighbours_per_particle",
                       static_cast<double>(entries) / static_cast<double>(p->x.size())},
                      {"timings", timings}});
    }
  }
  const nlohmann::json out{{"benchmark", "sph_neighbour_search"},
                           {"particles", lattice.x.size()},
                           {"h_over_dp", 1.2},
                           {"repetitions", repetitions},
                           {"runs", runs}};
  std::cout << out.dump(2) << '\n';
}
