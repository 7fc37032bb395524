#include "solver/sph/particle_system.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/sph/sph_update.hpp"

#include <algorithm>
#include <limits>

namespace sphfem {

namespace {

template <class T> void permute(std::vector<T>& field, const std::vector<Index>& new_to_old) {
  std::vector<T> sorted(field.size());
  for (std::size_t k = 0; k < new_to_old.size(); ++k)
    sorted[k] = field[new_to_old[k]];
  field.swap(sorted);
}

} // namespace

ParticleSystem::ParticleSystem(const Case& c, const Model& model,
                               const std::vector<ElasticConstants>& materials)
    : spec_(c.sph), materials_(materials), dt_stable_(std::numeric_limits<double>::infinity()) {
  const Index n = model.particle_count();
  if (n == 0)
    return;
  auto& p = particles_;
  p.for_each_field([n](auto& field) { field.resize(n); });
  double largest_h = 0;
  for (Index i = 0; i < n; ++i) {
    const int body = model.body_p[i];
    SPHFEM_CHECK(body >= 0 && body < static_cast<int>(c.bodies.size()), "model.h5: particle ", i,
                 " has body id ", body);
    p.x0_p[i] = p.x_p[i] = model.x_p[i];
    p.v_p[i] = c.bodies[body].velocity;
    p.m_p[i] = model.m_p[i];
    p.rho0_p[i] = p.rho_p[i] = model.rho_p[i];
    p.h0_p[i] = p.h_p[i] = model.h_p[i];
    p.dp_p[i] = model.spacing_b[body];
    p.S_p[i].setZero();
    p.p_p[i] = p.e_p[i] = 0;
    p.body_p[i] = body;
    p.material_p[i] = body; // one material entry per body
    p.id_p[i] = i;
    p.R_p[i].setZero();
    p.u_p[i].setZero();
    p.f_p[i].setZero();
    largest_h = std::max(largest_h, p.h_p[i]);
  }
  skin_ = spec_.skin * 2.0 * largest_h;
  index_of_id_.resize(n);
  rebuild();
  sph_kinematics(p, search_.list(), spec_, 0.0);
  forces(0.0);
}

void ParticleSystem::rebuild() {
  auto& p = particles_;
  // Renumber in the cell order of the last build (the particles have moved little since; at
  // the start, of a first build) for locality, then list: lists filled in near-cell order take
  // the search's fast path (≈ 1.4× faster, bench/neighbour_search.cpp).
  if (rebuilds_ == 0)
    search_.build(p.x_p, p.h_p, skin_);
  const std::vector<Index> order = search_.build_order();
  p.for_each_field([&order](auto& field) { permute(field, order); });
  for (Index k = 0; k < p.size(); ++k)
    index_of_id_[p.id_p[k]] = k;
  search_.build(p.x_p, p.h_p, skin_);
  ++rebuilds_;
}

void ParticleSystem::forces(double dt) {
  dt_stable_ = sph_forces(particles_, search_.list(), materials_, spec_, dt);
}

void ParticleSystem::kick(double dt_v) {
  auto& p = particles_;
  const Index n = p.size();
#pragma omp parallel for schedule(static) if (n > parallel_min_items)
  for (Index i = 0; i < n; ++i) {
    p.v_p[i] += (dt_v / p.m_p[i]) * p.f_p[i];
    p.e_p[i] += dt_v * p.heat_p[i];
  }
}

void ParticleSystem::drift(double dt) {
  auto& p = particles_;
  const Index n = p.size();
#pragma omp parallel for schedule(static) if (n > parallel_min_items)
  for (Index i = 0; i < n; ++i) {
    p.u_p[i] = p.v_p[i] + p.xsph_p[i];
    p.x_p[i] += dt * p.u_p[i];
  }
}

void ParticleSystem::update(double dt) {
  if (empty())
    return;
  if (search_.needs_update(particles_.x_p, particles_.h_p))
    rebuild();
  sph_kinematics(particles_, search_.list(), spec_, dt);
  sph_material_update(particles_, materials_, spec_, dt);
  forces(dt);
}

} // namespace sphfem
