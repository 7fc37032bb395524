// Entity costs, Zoltan's RCB and its regions, node ownership and the costs of a later state
// (decomposition.hpp). Verified by tests/parallel/decomposition_test.cpp.
#include "solver/parallel/decomposition.hpp"

#include "solver/core/error.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/time/cost_estimate.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <string>

#ifdef SPHFEM_HAVE_ZOLTAN
#include <mpi.h>
#include <zoltan.h>
#endif

namespace sphfem {

EntityCosts entity_costs(const Model& m, const std::vector<int>& body_group,
                         const MirrorParticles& mirrors) {
  const Index np = m.particle_count(), nb = static_cast<Index>(m.background_nodes.size());
  std::vector<Vec3> x(m.x_p);
  std::vector<double> h(m.h_p);
  std::vector<int> body(m.body_p);
  for (Index k = 0; k < nb; ++k) {
    const auto n = static_cast<std::size_t>(m.background_nodes[k]);
    x.push_back(m.x_n[n]);
    h.push_back(m.h_background[k]);
    body.push_back(m.body_n[n]);
  }
  // Mirror images, counted as neighbours only, chosen as the solver chooses them.
  if (!mirrors.empty()) {
    const double reach = 2.0 * *std::max_element(h.begin(), h.end());
    const std::size_t points = x.size();
    for (std::size_t i = 0; i < points; ++i) {
      const auto b = static_cast<std::size_t>(body[i]);
      if (b >= body_group.size())
        throw Error("decomposition: no group for body " + std::to_string(body[i]));
      for (const Vec3& image : mirrors.images_of(x[i], body_group[b], reach)) {
        x.push_back(image);
        h.push_back(h[i]);
      }
    }
  }
  NeighbourList list;
  if (!x.empty()) {
    NeighbourSearch search;
    search.build(x, h, 0.0);
    list = search.list();
  }
  const auto entries = [&list](Index row) {
    return static_cast<double>(list.offsets[row + 1] - list.offsets[row]);
  };

  EntityCosts costs;
  costs.particle.resize(static_cast<std::size_t>(np));
  for (Index i = 0; i < np; ++i)
    costs.particle[i] = StepCost::particle + StepCost::entry * entries(i);

  // A background particle's pair entries cost in the particle phase; a node's cost is shared
  // by its elements.
  costs.background.resize(static_cast<std::size_t>(nb));
  for (Index k = 0; k < nb; ++k)
    costs.background[k] = StepCost::entry * entries(np + k);
  std::vector<int> holders(m.x_n.size(), 0);
  for (const Hex& e : m.hex_e)
    for (const Index n : e)
      ++holders[static_cast<std::size_t>(n)];
  costs.element.resize(m.hex_e.size());
  for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
    double c = StepCost::element;
    for (const Index n : m.hex_e[e])
      c += StepCost::node / holders[static_cast<std::size_t>(n)];
    costs.element[e] = c;
  }
  return costs;
}

namespace {

// What one RCB cuts: the particles, or the elements at their centroids.
struct Objects {
  std::vector<Vec3> x;
  std::vector<float> weight; // ns per step: Zoltan takes single-precision weights
};

} // namespace

#ifdef SPHFEM_HAVE_ZOLTAN

namespace {

int object_count(void* data, int* ierr) {
  *ierr = ZOLTAN_OK;
  return static_cast<int>(static_cast<const Objects*>(data)->x.size());
}

void object_list(void* data, int, int, ZOLTAN_ID_PTR global_ids, ZOLTAN_ID_PTR local_ids, int,
                 float* weights, int* ierr) {
  const auto& o = *static_cast<const Objects*>(data);
  for (std::size_t i = 0; i < o.x.size(); ++i) {
    global_ids[i] = static_cast<ZOLTAN_ID_TYPE>(i);
    local_ids[i] = static_cast<ZOLTAN_ID_TYPE>(i);
    weights[i] = o.weight[i];
  }
  *ierr = ZOLTAN_OK;
}

int dimension(void*, int* ierr) {
  *ierr = ZOLTAN_OK;
  return 3;
}

void coordinates(void* data, int, int, int count, ZOLTAN_ID_PTR, ZOLTAN_ID_PTR local_ids, int,
                 double* xyz, int* ierr) {
  const auto& o = *static_cast<const Objects*>(data);
  for (int k = 0; k < count; ++k)
    for (int d = 0; d < 3; ++d)
      xyz[3 * k + d] = o.x[local_ids[k]][d];
  *ierr = ZOLTAN_OK;
}

// Zoltan needs MPI; a process that no launcher started starts it alone (Open MPI's singleton)
// and ends it at exit, after MpiSession, which ends only what it started.
void ensure_mpi() {
  int started = 0;
  MPI_Initialized(&started);
  if (started)
    return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  std::atexit([] {
    int ended = 0;
    MPI_Finalized(&ended);
    if (!ended)
      MPI_Finalize();
  });
}

void set(Zoltan_Struct* zz, const char* name, const std::string& value) {
  if (Zoltan_Set_Param(zz, name, value.c_str()) != ZOLTAN_OK)
    throw Error("decomposition: Zoltan refused its parameter " + std::string(name) + " = " + value);
}

// Part of each object by Zoltan's RCB, and each part's region.
std::vector<int> rcb_parts(Objects& o, int parts, std::vector<Decomposition::Region>& regions) {
  ensure_mpi();
  float version = 0;
  if (Zoltan_Initialize(0, nullptr, &version) != ZOLTAN_OK)
    throw Error("decomposition: Zoltan failed to start");
  Zoltan_Struct* zz = Zoltan_Create(MPI_COMM_SELF);
  std::vector<int> part(o.x.size(), 0);
  try {
    set(zz, "DEBUG_LEVEL", "0");
    set(zz, "LB_METHOD", "RCB");
    set(zz, "NUM_GID_ENTRIES", "1");
    set(zz, "NUM_LID_ENTRIES", "1");
    set(zz, "OBJ_WEIGHT_DIM", "1");
    set(zz, "NUM_GLOBAL_PARTS", std::to_string(parts));
    set(zz, "RETURN_LISTS", "PARTS");
    set(zz, "IMBALANCE_TOL", "1.01");
    set(zz, "KEEP_CUTS", "1");    // for the regions
    set(zz, "AVERAGE_CUTS", "1"); // half-way between the entities on either side
    Zoltan_Set_Num_Obj_Fn(zz, object_count, &o);
    Zoltan_Set_Obj_List_Fn(zz, object_list, &o);
    Zoltan_Set_Num_Geom_Fn(zz, dimension, &o);
    Zoltan_Set_Geom_Multi_Fn(zz, coordinates, &o);

    int changes = 0, gid_entries = 0, lid_entries = 0, imports = 0, exports = 0;
    ZOLTAN_ID_PTR import_gids = nullptr, import_lids = nullptr;
    ZOLTAN_ID_PTR export_gids = nullptr, export_lids = nullptr;
    int *import_procs = nullptr, *import_parts = nullptr;
    int *export_procs = nullptr, *export_parts = nullptr;
    const int status =
        Zoltan_LB_Partition(zz, &changes, &gid_entries, &lid_entries, &imports, &import_gids,
                            &import_lids, &import_procs, &import_parts, &exports, &export_gids,
                            &export_lids, &export_procs, &export_parts);
    if (status != ZOLTAN_OK)
      throw Error("decomposition: Zoltan's RCB failed (status " + std::to_string(status) + ")");
    for (int k = 0; k < exports; ++k) // with RETURN_LISTS = PARTS: every object, with its part
      part[export_lids[k]] = export_parts[k];
    regions.resize(static_cast<std::size_t>(parts));
    for (int q = 0; q < parts; ++q) {
      int dimensions = 0;
      Vec3& lo = regions[static_cast<std::size_t>(q)].lo;
      Vec3& hi = regions[static_cast<std::size_t>(q)].hi;
      if (Zoltan_RCB_Box(zz, q, &dimensions, &lo.x(), &lo.y(), &lo.z(), &hi.x(), &hi.y(),
                         &hi.z()) != ZOLTAN_OK)
        throw Error("decomposition: Zoltan gave no region for part " + std::to_string(q));
      for (int k = 0; k < 3; ++k) { // Zoltan's ±DBL_MAX: unbounded
        if (lo[k] <= -std::numeric_limits<double>::max())
          lo[k] = -std::numeric_limits<double>::infinity();
        if (hi[k] >= std::numeric_limits<double>::max())
          hi[k] = std::numeric_limits<double>::infinity();
      }
    }
    Zoltan_LB_Free_Part(&import_gids, &import_lids, &import_procs, &import_parts);
    Zoltan_LB_Free_Part(&export_gids, &export_lids, &export_procs, &export_parts);
  } catch (...) {
    Zoltan_Destroy(&zz);
    throw;
  }
  Zoltan_Destroy(&zz);
  return part;
}

} // namespace

bool decomposition_available() {
  return true;
}

#else

namespace {

std::vector<int> rcb_parts(Objects&, int, std::vector<Decomposition::Region>&) {
  throw Error("decomposition: this sphfem was built without MPI and Zoltan (Debian: "
              "libopenmpi-dev, libtrilinos-zoltan-dev; CMake -DSPHFEM_MPI=ON)");
}

} // namespace

bool decomposition_available() {
  return false;
}

#endif

namespace {

// A node goes with the lowest part among its elements' (`parts` for a node no element holds).
std::vector<int> node_parts(const Model& m, const std::vector<int>& part_e, int parts) {
  std::vector<int> part_n(m.x_n.size(), parts);
  for (std::size_t e = 0; e < m.hex_e.size(); ++e)
    for (const Index n : m.hex_e[e])
      part_n[static_cast<std::size_t>(n)] =
          std::min(part_n[static_cast<std::size_t>(n)], part_e[e]);
  return part_n;
}

// The two cuts number their parts each on its own: where they cut alike but in another order
// (a tie between two equally long sides, say), one region has two numbers, and every background
// particle there — stepped by its particles' part, filled by its node's — crosses ranks twice a
// step. So the elements' parts are renamed after the particles' parts their background
// particles fall in: the greatest overlaps first (ties by part number), the rest in order. A
// renaming only: each part's entities, and so the balance, are unchanged.
void match_element_parts(Decomposition& d, const Model& m) {
  const auto parts = static_cast<std::size_t>(d.parts);
  const std::vector<int> node_part = node_parts(m, d.part_e, d.parts);
  std::vector<long long> overlap(parts * parts, 0); // [element part][particle part]
  for (std::size_t k = 0; k < m.background_nodes.size(); ++k) {
    const int q = node_part[static_cast<std::size_t>(m.background_nodes[k])];
    if (q < d.parts)
      ++overlap[static_cast<std::size_t>(q) * parts + static_cast<std::size_t>(d.part_b[k])];
  }
  std::vector<std::size_t> pairs;
  for (std::size_t k = 0; k < overlap.size(); ++k)
    if (overlap[k] > 0)
      pairs.push_back(k);
  std::stable_sort(pairs.begin(), pairs.end(),
                   [&](std::size_t a, std::size_t b) { return overlap[a] > overlap[b]; });
  std::vector<int> name(parts, -1);
  std::vector<unsigned char> taken(parts, 0);
  for (const std::size_t k : pairs) {
    const std::size_t q = k / parts, p = k % parts;
    if (name[q] < 0 && !taken[p]) {
      name[q] = static_cast<int>(p);
      taken[p] = 1;
    }
  }
  std::size_t next = 0;
  for (int& n : name)
    if (n < 0) {
      while (taken[next])
        ++next;
      n = static_cast<int>(next);
      taken[next] = 1;
    }
  for (int& q : d.part_e)
    q = name[static_cast<std::size_t>(q)];
  std::vector<Decomposition::Region> regions(parts);
  for (std::size_t q = 0; q < parts; ++q)
    regions[static_cast<std::size_t>(name[q])] = d.regions[q];
  d.regions = std::move(regions);
}

} // namespace

Decomposition decompose(const Model& m, const EntityCosts& costs, int parts) {
  if (parts < 1)
    throw Error("decomposition: the number of parts must be at least 1, got " +
                std::to_string(parts));
  if (costs.particle.size() != m.x_p.size() || costs.element.size() != m.hex_e.size() ||
      costs.background.size() != m.background_nodes.size())
    throw Error("decomposition: the entity costs do not match the model");

  Decomposition d;
  d.parts = parts;
  d.part_p.assign(m.x_p.size(), 0);
  d.part_b.assign(m.background_nodes.size(), 0);
  d.part_e.assign(m.hex_e.size(), 0);
  constexpr double infinity = std::numeric_limits<double>::infinity();
  d.regions.assign(1, {Vec3::Constant(-infinity), Vec3::Constant(infinity)});
  if (parts > 1) {
    // The step's two phases, the elements' and then the particles', are separated by exchanges:
    // each is balanced on its own (one RCB of the hexahedra, one of the particles and the
    // background particles), so that no rank idles through one phase while the others finish it.
    if (!m.x_p.empty()) {
      Objects o;
      for (std::size_t i = 0; i < m.x_p.size(); ++i) {
        o.x.push_back(m.x_p[i]);
        o.weight.push_back(static_cast<float>(costs.particle[i] * 1e9));
      }
      for (std::size_t k = 0; k < m.background_nodes.size(); ++k) {
        o.x.push_back(m.x_n[static_cast<std::size_t>(m.background_nodes[k])]);
        o.weight.push_back(static_cast<float>(costs.background[k] * 1e9));
      }
      const std::vector<int> part = rcb_parts(o, parts, d.particle_regions);
      d.part_p.assign(part.begin(), part.begin() + static_cast<std::ptrdiff_t>(m.x_p.size()));
      d.part_b.assign(part.begin() + static_cast<std::ptrdiff_t>(m.x_p.size()), part.end());
    }
    if (!m.hex_e.empty()) {
      Objects o;
      for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
        Vec3 c = Vec3::Zero();
        for (const Index n : m.hex_e[e])
          c += m.x_n[static_cast<std::size_t>(n)];
        o.x.push_back(c / 8.0);
        o.weight.push_back(static_cast<float>(costs.element[e] * 1e9));
      }
      d.part_e = rcb_parts(o, parts, d.regions);
    }
    if (!m.x_p.empty() && !m.hex_e.empty())
      match_element_parts(d, m);
    if (m.x_p.empty())
      d.particle_regions = d.regions;
    if (m.hex_e.empty())
      d.regions = d.particle_regions;
  } else {
    d.particle_regions = d.regions;
  }

  d.part_n = node_parts(m, d.part_e, parts);
  d.shared_n.assign(m.x_n.size(), 0);
  for (std::size_t e = 0; e < m.hex_e.size(); ++e)
    for (const Index n : m.hex_e[e])
      if (d.part_n[static_cast<std::size_t>(n)] != d.part_e[e])
        d.shared_n[static_cast<std::size_t>(n)] = 1;
  for (int& owner : d.part_n)
    if (owner == parts) // a node no element holds (none in a meshed model)
      owner = 0;
  if (m.x_p.empty()) // background particles without particles: with their nodes
    for (std::size_t k = 0; k < m.background_nodes.size(); ++k)
      d.part_b[k] = d.part_n[static_cast<std::size_t>(m.background_nodes[k])];
  return d;
}

namespace {

int part_in(const std::vector<Decomposition::Region>& regions, const Vec3& x, int current,
            double slack = 0) {
  const auto parts = static_cast<int>(regions.size());
  if (current >= 0 && current < parts) {
    Decomposition::Region near = regions[static_cast<std::size_t>(current)];
    near.lo.array() -= slack;
    near.hi.array() += slack;
    if (near.holds(x))
      return current;
  }
  for (std::size_t q = 0; q < regions.size(); ++q)
    if (regions[q].holds(x))
      return static_cast<int>(q);
  throw Error("decomposition: no region holds the point (" + std::to_string(x.x()) + ", " +
              std::to_string(x.y()) + ", " + std::to_string(x.z()) + ") m");
}

} // namespace

int Decomposition::part_at(const Vec3& x, int current) const {
  return part_in(regions, x, current);
}

int Decomposition::particle_part_at(const Vec3& x, int current, double slack) const {
  return part_in(particle_regions, x, current, slack);
}

double live_particle_cost(int neighbours, bool yielding) {
  return StepCost::particle + StepCost::entry * neighbours +
         (yielding ? StepCost::yielding_point : 0.0);
}

double live_element_cost(double reference, bool yielding) {
  return reference + (yielding ? StepCost::yielding_point : 0.0);
}

EntityCosts current_costs(const EntityCosts& costs, std::span<const int> neighbours_p,
                          std::span<const unsigned char> live_p,
                          std::span<const unsigned char> live_e,
                          std::span<const unsigned char> yielding_p,
                          std::span<const unsigned char> yielding_e) {
  const std::size_t np = costs.particle.size(), ne = costs.element.size();
  if (neighbours_p.size() != np || live_p.size() != np || live_e.size() != ne ||
      (!yielding_p.empty() && yielding_p.size() != np) ||
      (!yielding_e.empty() && yielding_e.size() != ne))
    throw Error("decomposition: the state's particles or elements are not the decomposition's");
  const auto yields = [](std::span<const unsigned char> flags, std::size_t k) {
    return !flags.empty() && flags[k] != 0;
  };
  EntityCosts now = costs;
  for (std::size_t i = 0; i < np; ++i)
    now.particle[i] = live_p[i] ? live_particle_cost(neighbours_p[i], yields(yielding_p, i)) : 0.0;
  for (std::size_t e = 0; e < ne; ++e)
    now.element[e] = live_e[e] ? live_element_cost(costs.element[e], yields(yielding_e, e)) : 0.0;
  return now;
}

PhaseCosts phase_costs(const Decomposition& d, const EntityCosts& costs) {
  if (costs.particle.size() != d.part_p.size() || costs.element.size() != d.part_e.size() ||
      costs.background.size() != d.part_b.size())
    throw Error("decomposition: the state's particles or elements are not the decomposition's");
  PhaseCosts c{std::vector<double>(static_cast<std::size_t>(d.parts), 0.0),
               std::vector<double>(static_cast<std::size_t>(d.parts), 0.0)};
  for (std::size_t i = 0; i < d.part_p.size(); ++i)
    c.particle[static_cast<std::size_t>(d.part_p[i])] += costs.particle[i];
  for (std::size_t k = 0; k < d.part_b.size(); ++k)
    c.particle[static_cast<std::size_t>(d.part_b[k])] += costs.background[k];
  for (std::size_t e = 0; e < d.part_e.size(); ++e)
    c.element[static_cast<std::size_t>(d.part_e[e])] += costs.element[e];
  return c;
}

std::vector<double>
part_costs(const Decomposition& d, const EntityCosts& costs, std::span<const int> neighbours_p,
           std::span<const unsigned char> live_p, std::span<const unsigned char> live_e,
           std::span<const unsigned char> yielding_p, std::span<const unsigned char> yielding_e) {
  PhaseCosts c =
      phase_costs(d, current_costs(costs, neighbours_p, live_p, live_e, yielding_p, yielding_e));
  for (std::size_t q = 0; q < c.particle.size(); ++q)
    c.particle[q] += c.element[q];
  return c.particle;
}

double phase_imbalance(const Decomposition& d, const EntityCosts& costs) {
  return phase_imbalance(phase_costs(d, costs));
}

namespace {

// A phase's largest part cost and the parts' total, s (0 and 0 without parts).
struct PhaseSpread {
  double largest = 0, total = 0;
  double parts = 0;
  explicit PhaseSpread(const std::vector<double>& cost) : parts(static_cast<double>(cost.size())) {
    if (cost.empty())
      return;
    largest = *std::max_element(cost.begin(), cost.end());
    total = std::accumulate(cost.begin(), cost.end(), 0.0);
  }
};

} // namespace

double phase_imbalance(const PhaseCosts& c) {
  // Each phase waits for its slowest part: the worse of the two phases' imbalances.
  const auto imbalance = [](const PhaseSpread& s) {
    return s.total > 0 ? s.largest * s.parts / s.total : 1.0;
  };
  return std::max(imbalance(PhaseSpread(c.particle)), imbalance(PhaseSpread(c.element)));
}

double wait_beyond_even(const PhaseCosts& c) {
  const auto beyond = [](const PhaseSpread& s) {
    return s.parts > 0 ? s.largest - s.total / s.parts : 0.0;
  };
  return beyond(PhaseSpread(c.particle)) + beyond(PhaseSpread(c.element));
}

bool new_cut_pays(const PhaseCosts& c, long long steps_served, std::size_t entities) {
  return wait_beyond_even(c) * static_cast<double>(steps_served) >
         StepCost::new_cut * static_cast<double>(entities);
}

} // namespace sphfem
