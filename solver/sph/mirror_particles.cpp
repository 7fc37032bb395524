#include "solver/sph/mirror_particles.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"

#include <cmath>
#include <optional>

namespace sphfem {

namespace {

// The flat face `face` of `body`, if it is a plane: a point on it and its outward normal. Box
// faces, and the cut faces xmin and ymin of a quarter cylinder or ring (through its axis).
std::optional<std::pair<Vec3, Vec3>> flat_face(const BodySpec& body, const std::string& face) {
  const GeometrySpec& g = body.geometry;
  if (g.kind == GeometrySpec::Kind::Box) {
    const char* names[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
    for (int k = 0; k < 6; ++k)
      if (face == names[k]) {
        const int axis = k / 2;
        const bool max = k % 2 == 1;
        Vec3 normal = Vec3::Zero();
        normal[axis] = max ? 1.0 : -1.0;
        return std::pair{max ? g.box.max : g.box.min, normal};
      }
  }
  const bool quarter_cylinder =
      g.kind == GeometrySpec::Kind::Cylinder && g.cylinder.sector == Sector::Quarter;
  const bool quarter_ring = g.kind == GeometrySpec::Kind::Ring && g.ring.sector == Sector::Quarter;
  if (quarter_cylinder || quarter_ring) {
    const Vec3& axis_point = quarter_cylinder ? g.cylinder.base : g.ring.base;
    if (face == "xmin")
      return std::pair{axis_point, Vec3(-Vec3::UnitX())};
    if (face == "ymin")
      return std::pair{axis_point, Vec3(-Vec3::UnitY())};
  }
  return std::nullopt;
}

} // namespace

MirrorParticles::MirrorParticles(const Case& c) {
  const std::vector<int> group = c.body_groups();
  // An FE body in a kernel contact pair carries background particles on its surface: its
  // symmetry planes mirror them too, so that the other body of the pair meets the whole surface
  // at the plane (else the contact near a quarter model's planes is one-sided). A surface
  // contact needs no such images: its faces reach the plane.
  const auto in_contact = [&c](const std::string& name) {
    for (const ContactSpec& pair : c.contacts)
      if (pair.model == ContactModel::Kernel && (pair.bodies[0] == name || pair.bodies[1] == name))
        return true;
    return false;
  };
  for (const auto& bc : c.boundary_conditions) {
    if (bc.type != BoundaryType::Symmetry)
      continue;
    const int body = c.body_index(bc.body);
    const BodySpec& spec = c.bodies[body];
    const auto plane = flat_face(spec, bc.face);
    if (spec.method == Method::Sph && !plane)
      throw Error("boundary_conditions: symmetry on " + spec.name + "/" + bc.face +
                  ": particles take symmetry planes only on box faces");
    if (plane && (spec.method == Method::Sph || in_contact(spec.name)))
      planes_.push_back({group[body], plane->first, plane->second});
  }
}

std::vector<MirrorParticles::Image> MirrorParticles::maps_of(const Vec3& x, int group,
                                                             double reach) const {
  // The planes of the group within reach; an image for every non-empty subset of them.
  std::vector<int> near;
  for (int k = 0; k < static_cast<int>(planes_.size()); ++k)
    if (planes_[k].group == group &&
        std::abs((x - planes_[k].point).dot(planes_[k].normal)) < reach)
      near.push_back(k);
  std::vector<Image> maps;
  for (unsigned subset = 1; subset < (1u << near.size()); ++subset) {
    Image image{Mat3::Identity(), Vec3::Zero()};
    for (std::size_t k = 0; k < near.size(); ++k)
      if (subset & (1u << k)) {
        const Plane& plane = planes_[near[k]];
        const Mat3 R = Mat3::Identity() - 2.0 * plane.normal * plane.normal.transpose();
        const Vec3 t = 2.0 * plane.point.dot(plane.normal) * plane.normal;
        image = {R * image.R, R * image.t + t};
      }
    maps.push_back(image);
  }
  return maps;
}

std::vector<Vec3> MirrorParticles::images_of(const Vec3& x, int group, double reach) const {
  std::vector<Vec3> images;
  for (const Image& image : maps_of(x, group, reach))
    images.push_back(image.R * x + image.t);
  return images;
}

void MirrorParticles::select(Particles& p, std::span<const Vec3> x, double reach,
                             std::span<const unsigned char> among) {
  SPHFEM_CHECK(x.size() >= static_cast<std::size_t>(p.rows()) &&
                   (among.empty() || among.size() >= static_cast<std::size_t>(p.rows())),
               "mirror images: positions of ", x.size(), " rows for ", p.rows(),
               " (internal error)");
  source_.clear();
  image_.clear();
  // Real particles first, then background particles (the FE side of an interface near the
  // plane needs its images as much as the SPH side).
  for (Index i = 0; i < p.rows(); ++i) {
    if (i == p.size())
      p.mirrored_real = size();
    if (!among.empty() && !among[i])
      continue;
    for (const Image& image : maps_of(x[i], p.group_p[i], reach)) {
      source_.push_back(i);
      image_.push_back(image);
    }
  }
  if (p.background == 0)
    p.mirrored_real = size();
}

void MirrorParticles::refresh_motion(Particles& p, Index first,
                                     const std::vector<Index>* only) const {
  const IndexRange slots = IndexRange::of(only, first, first + size());
  for (Index m = 0; m < slots.count; ++m) {
    const Index g = slots[m], k = g - first, i = source_[k];
    const Mat3& R = image_[k].R;
    p.x_p[g] = image_of(k, p.x_p[i]);
    p.x0_p[g] = R * p.x0_p[i] + image_[k].t;
    p.v_p[g] = R * p.v_p[i];
    p.u_p[g] = R * p.u_p[i];
    p.m_p[g] = p.m_p[i];
    p.rho0_p[g] = p.rho0_p[i];
    p.rho_p[g] = p.rho_p[i];
    p.h_p[g] = p.h_p[i];
    p.h0_p[g] = p.h0_p[i];
    p.dp_p[g] = p.dp_p[i];
    p.body_p[g] = p.body_p[i];
    p.group_p[g] = p.group_p[i];
    p.material_p[g] = p.material_p[i];
    p.id_p[g] = -1;
  }
}

void MirrorParticles::refresh_stress(Particles& p, Index first,
                                     const std::vector<Index>* only) const {
  const IndexRange slots = IndexRange::of(only, first, first + size());
  for (Index m = 0; m < slots.count; ++m) {
    const Index g = slots[m], k = g - first, i = source_[k];
    const Mat3& R = image_[k].R;
    p.rho_p[g] = p.rho_p[i]; // the material update has just changed density and h
    p.h_p[g] = p.h_p[i];
    p.S_p[g] = R * p.S_p[i] * R.transpose();
    p.p_p[g] = p.p_p[i];
    p.kill_p[g] = p.kill_p[i];
    p.C_p[g] = R * p.C_p[i] * R.transpose();
    p.R_p[g] = R * p.R_p[i] * R.transpose();
    p.shear_p[g] = p.shear_p[i]; // |∇·v| and |∇×v| are invariant under reflections
    p.f_p[g] = R * p.f_p[i];
  }
}

} // namespace sphfem
