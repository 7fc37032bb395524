#include "solver/time/particle_boundaries.hpp"

#include "solver/core/error.hpp"
#include "solver/sph/surface_traction.hpp"

#include <algorithm>
#include <cmath>

namespace sphfem {

namespace {

const ParticleFace& face(const Model& model, const std::string& body, const std::string& name) {
  const auto it = model.particle_faces.find(body + "/" + name);
  SPHFEM_CHECK(it != model.particle_faces.end(), "model has no particle face ", body, "/", name,
               " (re-mesh: the model does not match the case)");
  return it->second;
}

bool on_particles(const Case& c, const std::string& body) {
  return c.bodies[c.body_index(body)].method == Method::Sph;
}

} // namespace

ParticleBoundaries::ParticleBoundaries(const Case& c, const Model& model) {
  for (const auto& load : c.loads)
    if (on_particles(c, load.body)) {
      const ParticleFace& f = face(model, load.body, load.face);
      const int body =
          static_cast<int>(std::find(model.body_names.begin(), model.body_names.end(), load.body) -
                           model.body_names.begin());
      TractionWeights w = surface_traction_weights(model, body, f, c.sph.gradient_correction);
      loads_.push_back(
          {std::move(w.particles), std::move(w.area), f.normal, load.pressure, load.function});
    }
  for (const auto& bc : c.boundary_conditions)
    if (on_particles(c, bc.body)) {
      const ParticleFace& f = face(model, bc.body, bc.face);
      if (bc.type == BoundaryType::Symmetry) {
        // Mirror particles (solver/sph/mirror_particles.hpp) make the plane; a particle lying on
        // it (a lattice on nodes) is also held on it: it would repel its own image, which sits
        // where it does, as soon as it left the plane in compression.
        const BodySpec& body = c.bodies[c.body_index(bc.body)];
        Eigen::Index axis = 0;
        f.normal.cwiseAbs().maxCoeff(&axis);
        const double plane =
            (f.normal[axis] > 0 ? body.geometry.box.max : body.geometry.box.min)[axis];
        Constraint roller{{}, {}, TimeFunction()};
        roller.velocity[axis] = 0.0;
        for (const Index id : f.particles)
          if (std::abs(model.x_p[id][axis] - plane) < 1e-9 * body.spacing)
            roller.ids.push_back(id);
        if (!roller.ids.empty())
          constraints_.push_back(std::move(roller));
        continue;
      }
      const auto& ids = f.particles;
      if (bc.type == BoundaryType::Fixed)
        constraints_.push_back({ids, {0.0, 0.0, 0.0}, TimeFunction()});
      else
        constraints_.push_back({ids, bc.velocity, bc.function});
    }
}

ReactionTotals ParticleBoundaries::apply(double t, double t_half, double dt_v,
                                         ParticleSystem& system) const {
  Particles& p = system.particles();
  // A distributed run: each rank applies (and counts) its own particles' conditions.
  const std::span<const unsigned char> own = system.owned_rows();
  const auto mine = [&own](Index i) { return i >= 0 && (own.empty() || own[i]); };
  ReactionTotals totals;
  for (const auto& load : loads_) {
    const double pressure = load.pressure * load.function(t);
    for (std::size_t k = 0; k < load.ids.size(); ++k) {
      const Index i = system.index_of(load.ids[k]);
      if (!mine(i))
        continue;
      const Vec3 impulse = (-dt_v * pressure * load.area[k]) * load.normal;
      const Vec3 v_old = p.v_p[i] - (dt_v / p.m_p[i]) * p.f_p[i]; // v^{n−½}
      p.v_p[i] += impulse / p.m_p[i];
      totals.add(impulse.dot(0.5 * (v_old + p.v_p[i])), impulse);
    }
  }
  for (const auto& c : constraints_) {
    const double scale = c.function(t_half);
    for (Index id : c.ids) {
      const Index i = system.index_of(id);
      if (!mine(i))
        continue;
      const Vec3 v_free = p.v_p[i];
      for (int d = 0; d < 3; ++d)
        if (c.velocity[d]) {
          p.v_p[i][d] = *c.velocity[d] * scale;
          p.xsph_p[i][d] = 0; // a constrained particle moves with its prescribed velocity
        }
      const Vec3 impulse = p.m_p[i] * (p.v_p[i] - v_free);
      const Vec3 v_old = v_free - (dt_v / p.m_p[i]) * p.f_p[i];
      totals.add(impulse.dot(0.5 * (v_old + p.v_p[i])), impulse);
    }
  }
  return totals;
}

} // namespace sphfem
