// Expands `scene: plate_impact` into bodies, couplings and boundary conditions (see the header).
#include "solver/io/plate_impact.hpp"

#include "solver/core/error.hpp"

#include <cmath>
#include <numbers>

namespace sphfem {
namespace {

BodySpec fem_body(const std::string& name, const std::string& material, double element_size) {
  BodySpec b;
  b.name = name;
  b.method = Method::Fem;
  b.element_size = element_size;
  b.material = material;
  return b;
}

BoundaryConditionSpec condition(BoundaryType type, const std::string& body,
                                const std::string& face) {
  BoundaryConditionSpec bc;
  bc.type = type;
  bc.body = body;
  bc.face = face;
  return bc;
}

} // namespace

double preset_spacing(const std::string& preset) {
  for (const ResolutionPreset& p : resolution_presets)
    if (preset == p.name)
      return p.spacing;
  throw Error("preset: unknown preset '" + preset + "' (expected coarse, standard or fine)");
}

void expand_plate_impact(const PlateImpactSpec& s, Case& c) {
  const double dp = s.spacing.value_or(preset_spacing(s.preset));
  const double element = s.element_size.value_or(preset_spacing(s.preset));
  const double a = s.core_half_width, t = s.thickness, radius = 0.5 * s.diameter;
  SPHFEM_CHECK(a > radius, "core.half_width: must exceed the projectile's radius ", radius,
               " m (the projectile meets only the SPH core), got ", a, " m");
  SPHFEM_CHECK(0.5 * s.clamped_diameter > std::numbers::sqrt2 * a,
               "plate.clamped_diameter: the clamped circle must enclose the SPH core's corners (",
               2 * std::numbers::sqrt2 * a, " m across), got ", s.clamped_diameter, " m");
  SPHFEM_CHECK(dp <= a && dp <= t, "core.spacing: ", dp,
               " m is coarser than the core's half-width or the plate's thickness");
  // The lattice has round(2a/Δp) cells across the whole core, the ring round(a/Δp) per half side.
  SPHFEM_CHECK(std::lround(2 * a / dp) == 2 * std::lround(a / dp),
               "core.half_width / core.spacing = ", a / dp,
               " ends in .5: the core's lattice and the ring's nodes would not meet");
  // The surface contact starts where the projectile's face meets the spheres of the core's top
  // layer (radius Δp/2, the layer itself on z = 0); the kernel contact within h_core +
  // h_projectile (METHOD.md §4.3). The projectile starts just beyond.
  const bool kernel = s.contact.model == ContactModel::Kernel;
  const double reach = kernel ? s.core_h_factor * dp + s.projectile_h_factor * element : 0.5 * dp;
  const double gap = s.gap.value_or(reach + 0.25 * std::min(dp, element));
  SPHFEM_CHECK(gap > reach, "projectile.gap: ", gap, " m starts the projectile inside the ",
               kernel ? "kernel contact's reach h_core + h_projectile = "
                      : "core's contact spheres, whose top is Δp/2 = ",
               reach, " m at this resolution");

  const double low = s.quarter ? 0.0 : -a;
  BodySpec core;
  core.name = "plate_core";
  core.method = Method::Sph;
  core.geometry.kind = GeometrySpec::Kind::Box;
  core.geometry.box = {Vec3(low, low, -t), Vec3(a, a, 0)};
  core.spacing = dp;
  core.h_factor = s.core_h_factor;
  core.lattice = BodySpec::Lattice::Nodes;
  core.material = s.plate_material;

  const Sector sector = s.quarter ? Sector::Quarter : Sector::Full;
  BodySpec ring = fem_body("plate_ring", s.plate_material, dp);
  ring.geometry.kind = GeometrySpec::Kind::Ring;
  ring.geometry.ring = {Vec3(0, 0, -t), a, 0.5 * s.clamped_diameter, t, s.rim_element_size, sector};

  BodySpec projectile = fem_body("projectile", s.projectile_material, element);
  projectile.geometry.kind = GeometrySpec::Kind::Cylinder;
  projectile.geometry.cylinder = {Vec3(0, 0, gap), Vec3(0, 0, s.length), radius, sector};
  projectile.h_factor = s.projectile_h_factor;
  projectile.velocity = Vec3(0, 0, -s.velocity);

  c.bodies = {core, ring, projectile};
  c.attachments = {{ring.name, core.name}};
  ContactSpec contact = s.contact;
  contact.bodies = {core.name, projectile.name};
  c.contacts = {contact};
  c.boundary_conditions = {condition(BoundaryType::Fixed, ring.name, "rim")};
  if (s.quarter)
    for (const BodySpec* body : {&core, &ring, &projectile})
      for (const char* face : {"xmin", "ymin"})
        c.boundary_conditions.push_back(condition(BoundaryType::Symmetry, body->name, face));
  c.scene = SceneSpec{"plate_impact", s.preset, s.quarter, dp, s.velocity};
  // The section through the impact axis, a quarter spacing off the plane y = 0 so that it cuts
  // elements and particle layers rather than running along them. Its normal is −y so that the
  // section's in-plane axis u = z × n is +x: a quarter model (x ≥ 0) is drawn at u ≥ 0. The
  // picture shows the core and as much ring again (|x| ≤ 2 half_width), where the plate bulges.
  if (!c.output.section)
    c.output.section = SectionPlane{Vec3(0, 0.25 * dp, -0.5 * t), -Vec3::UnitY(),
                                    std::array<double, 2>{s.quarter ? 0.0 : -2 * a, 2 * a}};
}

} // namespace sphfem
