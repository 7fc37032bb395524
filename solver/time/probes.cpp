#include "solver/time/probes.hpp"

#include "solver/core/error.hpp"
#include "solver/fem/nodal_stress.hpp"

#include <limits>

namespace sphfem {

std::vector<Probe> locate_probes(const Case& c, const Model& model) {
  std::vector<Probe> out;
  for (const auto& spec : c.probes) {
    const int body = c.body_index(spec.body);
    Probe probe{spec.name, -1, spec.point, Vec3::Zero()};
    double best = std::numeric_limits<double>::infinity();
    for (Index i = 0; i < model.node_count(); ++i) {
      if (model.body_n[i] != body)
        continue;
      const double d = (model.x_n[i] - spec.point).squaredNorm();
      if (d < best) {
        best = d;
        probe.node = i;
      }
    }
    SPHFEM_CHECK(probe.node >= 0, "probes.", spec.name, ": body ", spec.body, " has no nodes");
    probe.position = model.x_n[probe.node];
    out.push_back(probe);
  }
  return out;
}

std::vector<std::string> probe_columns(const std::vector<Probe>& probes) {
  static const char* quantities[] = {"ux",  "uy",  "uz",  "vx",  "vy",  "vz",       "sxx",
                                     "syy", "szz", "sxy", "syz", "szx", "pressure", "von_mises"};
  std::vector<std::string> out;
  for (const auto& p : probes)
    for (const char* q : quantities)
      out.push_back(p.name + "." + q);
  return out;
}

void probe_values(const std::vector<Probe>& probes, const Simulation& sim,
                  std::vector<double>& row) {
  const auto& nodes = sim.nodes();
  for (const auto& p : probes) {
    const Vec3 u = nodes.x_n[p.node] - nodes.x0_n[p.node];
    const Vec3& v = nodes.v_n[p.node];
    const Mat3 s = nodal_stress(sim.elements(), sim.node_gather(), p.node);
    row.insert(row.end(), {u.x(), u.y(), u.z(), v.x(), v.y(), v.z(), s(0, 0), s(1, 1), s(2, 2),
                           s(0, 1), s(1, 2), s(2, 0), -s.trace() / 3.0, von_mises(s)});
  }
}

} // namespace sphfem
