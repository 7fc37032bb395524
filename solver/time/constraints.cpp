#include "solver/time/constraints.hpp"

#include "solver/core/error.hpp"

#include <algorithm>

namespace sphfem {

namespace {

const std::vector<Index>& node_set(const Model& model, const std::string& body,
                                   const std::string& face) {
  const auto it = model.node_sets.find(body + "/" + face);
  SPHFEM_CHECK(it != model.node_sets.end(), "model has no face ", body, "/", face,
               " (re-mesh: the model does not match the case)");
  return it->second;
}

// Unit normal of a planar face; a symmetry plane on a curved face is an input error.
Vec3 plane_normal(const Model& model, const std::string& body, const std::string& face) {
  const auto it = model.face_sets.find(body + "/" + face);
  SPHFEM_CHECK(it != model.face_sets.end() && !it->second.empty(), "model has no face ", body, "/",
               face);
  Vec3 sum = Vec3::Zero();
  std::vector<Vec3> normals;
  for (const Quad& q : it->second) {
    const Vec3 a = (model.x_n[q[2]] - model.x_n[q[0]]).cross(model.x_n[q[3]] - model.x_n[q[1]]);
    normals.push_back(a.normalized());
    sum += a;
  }
  const Vec3 n = sum.normalized();
  for (const Vec3& each : normals)
    SPHFEM_CHECK(each.dot(n) > 1 - 1e-6, "boundary_conditions: symmetry on ", body, "/", face,
                 ": the face is not planar (a symmetry plane needs a flat face)");
  return n;
}

} // namespace

Constraints::Constraints(const Case& c, const Model& model) {
  for (const auto& bc : c.boundary_conditions) {
    if (c.bodies[c.body_index(bc.body)].method == Method::Sph)
      continue; // particle faces: ParticleBoundaries
    const auto& nodes = node_set(model, bc.body, bc.face);
    switch (bc.type) {
    case BoundaryType::Fixed:
      fixed_.insert(fixed_.end(), nodes.begin(), nodes.end());
      break;
    case BoundaryType::Symmetry: {
      const Vec3 n = plane_normal(model, bc.body, bc.face);
      for (Index i : nodes)
        symmetry_.push_back({i, n});
      break;
    }
    case BoundaryType::Velocity:
      for (Index i : nodes)
        prescribed_.push_back({i, bc.velocity, bc.function});
      break;
    }
    nodes_.insert(nodes_.end(), nodes.begin(), nodes.end());
  }
  std::sort(nodes_.begin(), nodes_.end());
  nodes_.erase(std::unique(nodes_.begin(), nodes_.end()), nodes_.end());
  v_free_.resize(nodes_.size());
}

// Symmetry first, then prescribed components, then fixed: a fixed node stays fixed.
void Constraints::constrain(double t, std::vector<Vec3>& v) const {
  for (const auto& s : symmetry_)
    v[s.node] -= v[s.node].dot(s.normal) * s.normal;
  for (const auto& p : prescribed_) {
    const double scale = p.function(t);
    for (int k = 0; k < 3; ++k)
      if (p.velocity[k])
        v[p.node][k] = *p.velocity[k] * scale;
  }
  for (Index i : fixed_)
    v[i].setZero();
}

ReactionTotals Constraints::apply(double t_half, double dt, const std::vector<double>& m,
                                  const std::vector<Vec3>& f, std::vector<Vec3>& v_half,
                                  std::span<const unsigned char> counted) {
  for (std::size_t k = 0; k < nodes_.size(); ++k)
    v_free_[k] = v_half[nodes_[k]];
  constrain(t_half, v_half);
  ReactionTotals totals;
  // The reaction m Δv/Δt acts over Δt: its impulse is m Δv, its work m Δv · v̄.
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    const Index i = nodes_[k];
    if (!counted.empty() && !counted[i])
      continue;
    const Vec3 impulse = m[i] * (v_half[i] - v_free_[k]);
    const Vec3 v_old = v_free_[k] - dt * f[i] / m[i];
    totals.add(impulse.dot(0.5 * (v_old + v_half[i])), impulse);
  }
  return totals;
}

void Constraints::apply_initial(std::vector<Vec3>& v) const {
  constrain(0.0, v);
}

} // namespace sphfem
