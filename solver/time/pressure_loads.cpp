#include "solver/time/pressure_loads.hpp"

#include "solver/core/error.hpp"

#include <algorithm>

namespace sphfem {

PressureLoads::PressureLoads(const Case& c, const Model& model) {
  for (const auto& load : c.loads) {
    if (c.bodies[c.body_index(load.body)].method == Method::Sph)
      continue; // particle faces: ParticleBoundaries
    const auto it = model.face_sets.find(load.body + "/" + load.face);
    SPHFEM_CHECK(it != model.face_sets.end(), "model has no face ", load.body, "/", load.face,
                 " (re-mesh: the model does not match the case)");
    loads_.push_back({it->second, load.pressure, load.function});
    for (const Quad& q : it->second)
      loaded_nodes_.insert(loaded_nodes_.end(), q.begin(), q.end());
  }
  std::sort(loaded_nodes_.begin(), loaded_nodes_.end());
  loaded_nodes_.erase(std::unique(loaded_nodes_.begin(), loaded_nodes_.end()), loaded_nodes_.end());
}

void PressureLoads::apply(double t, const std::vector<Vec3>& x, std::vector<Vec3>& f_ext) const {
  for (Index i : loaded_nodes_)
    f_ext[i].setZero();
  for (const auto& load : loads_) {
    const double p = load.pressure * load.function(t);
    if (p == 0.0)
      continue;
    for (const Quad& q : load.faces) {
      const Vec3 area = 0.5 * (x[q[2]] - x[q[0]]).cross(x[q[3]] - x[q[1]]);
      const Vec3 f = -0.25 * p * area;
      for (Index i : q)
        f_ext[i] += f;
    }
  }
}

} // namespace sphfem
