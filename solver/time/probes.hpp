// Probes: named points whose histories are recorded, each on the node (FE body) or particle
// (SPH body) of its body nearest to the requested point in the reference configuration (ties:
// the lowest index). Stress at a node is the volume-weighted mean of its elements', at a
// particle its own. Columns <probe>.ux|uy|uz (m),
// vx|vy|vz (m/s), sxx|syy|szz|sxy|syz|szx, pressure, von_mises (Pa).
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"
#include "solver/time/simulation.hpp"

#include <string>
#include <vector>

namespace sphfem {

struct Probe {
  std::string name;
  bool on_particle = false;
  Index node = -1;               // node index, or particle id (model.h5 order) when on_particle
  Vec3 requested = Vec3::Zero(); // the case's point, m
  Vec3 position = Vec3::Zero();  // the node's reference position, m
};

std::vector<Probe> locate_probes(const Case& c, const Model& model);

// Column names in the order probe_values() fills them.
std::vector<std::string> probe_columns(const std::vector<Probe>& probes);
// Appends each probe's values, taken by the rank that keeps its node or particle current.
// Collective in a distributed run.
void probe_values(const std::vector<Probe>& probes, const Simulation& sim,
                  std::vector<double>& row);

} // namespace sphfem
