#include "solver/time/probes.hpp"

#include "solver/core/error.hpp"
#include "solver/fem/nodal_stress.hpp"
#include "solver/parallel/ranks.hpp"

#include <limits>

namespace sphfem {

namespace {

// Index of the point of `body` nearest to `target`, or -1 if the body has none.
Index nearest(const std::vector<Vec3>& points, const std::vector<int>& body_of, int body,
              const Vec3& target) {
  Index best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (Index i = 0; i < static_cast<Index>(points.size()); ++i) {
    const double d = (points[i] - target).squaredNorm();
    if (body_of[i] == body && d < best_distance) {
      best_distance = d;
      best = i;
    }
  }
  return best;
}

} // namespace

std::vector<Probe> locate_probes(const Case& c, const Model& model) {
  std::vector<Probe> out;
  for (const auto& spec : c.probes) {
    const int body = c.body_index(spec.body);
    Probe probe{spec.name, c.bodies[body].method == Method::Sph, -1, spec.point, Vec3::Zero()};
    const auto& points = probe.on_particle ? model.x_p : model.x_n;
    probe.node = nearest(points, probe.on_particle ? model.body_p : model.body_n, body, spec.point);
    SPHFEM_CHECK(probe.node >= 0, "probes.", spec.name, ": body ", spec.body, " is empty");
    probe.position = points[probe.node];
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
  const auto& part = sim.particle_system().particles();
  // Each probe's values from the rank keeping its entity current (every rank on one process):
  // a flag saying so, then its 14 values.
  constexpr std::size_t width = 15;
  std::vector<double> mine;
  for (const auto& p : probes) {
    Vec3 u, v;
    Mat3 s;
    bool owner = false;
    if (p.on_particle) {
      const Index i = sim.particle_system().index_of(p.node);
      owner = i >= 0 && sim.owns_row(i); // a distributed rank may not hold it
      u = v = Vec3::Zero();
      s = Mat3::Zero();
      if (owner) {
        u = part.x_p[i] - part.x0_p[i];
        v = part.v_p[i];
        s = part.S_p[i] - part.p_p[i] * Mat3::Identity();
      }
    } else {
      owner = sim.owns_node(p.node);
      u = nodes.x_n[p.node] - nodes.x0_n[p.node];
      v = nodes.v_n[p.node];
      s = nodal_stress(sim.elements(), sim.node_gather(), p.node);
    }
    mine.insert(mine.end(),
                {owner ? 1.0 : 0.0, u.x(), u.y(), u.z(), v.x(), v.y(), v.z(), s(0, 0), s(1, 1),
                 s(2, 2), s(0, 1), s(1, 2), s(2, 0), -s.trace() / 3.0, von_mises(s)});
  }
  const std::vector<double> all = ranks::gather_all(mine);
  for (std::size_t k = 0; k < probes.size(); ++k) {
    std::size_t at = k * width;
    while (at < all.size() && all[at] == 0)
      at += mine.size(); // the next rank's block
    SPHFEM_CHECK(at < all.size(), "probe ", probes[k].name, ": no rank keeps its entity");
    row.insert(row.end(), all.begin() + static_cast<std::ptrdiff_t>(at + 1),
               all.begin() + static_cast<std::ptrdiff_t>(at + width));
  }
}

} // namespace sphfem
