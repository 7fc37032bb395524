// Reads `scene: plate_impact` and expands it into bodies, couplings and boundary conditions
// (see the header).
#include "solver/scenes/plate_impact.hpp"

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

constexpr bool positive(double v) {
  return v > 0;
}
constexpr bool non_negative(double v) {
  return v >= 0;
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

double core_half_width_for(const PlateImpactSpec& s, double spacing) {
  const double beta = s.obliquity * std::numbers::pi / 180;
  const double swept = 0.5 * s.diameter / std::cos(beta) + s.thickness * std::tan(beta);
  return spacing * std::ceil((swept + core_margin * s.thickness) / spacing - 1e-9);
}

void expand_plate_impact(const PlateImpactSpec& s, Case& c) {
  const double dp = s.spacing.value_or(preset_spacing(s.preset));
  const double element = s.element_size.value_or(preset_spacing(s.preset));
  const double a = s.core_half_width.value_or(core_half_width_for(s, dp));
  const double t = s.thickness, radius = 0.5 * s.diameter;
  const double beta = s.obliquity * std::numbers::pi / 180;
  SPHFEM_CHECK(s.symmetry != Sector::Quarter || s.obliquity == 0,
               "symmetry: quarter needs a normal impact; a shot at obliquity ", s.obliquity,
               "° is symmetric about y = 0 only (symmetry: half)");
  // An oblique cylinder cuts an ellipse of semi-axis R / cos β along x out of the plate.
  SPHFEM_CHECK(a > radius / std::cos(beta), "core.half_width: must exceed the projectile's ",
               s.obliquity > 0 ? "footprint's half-length R / cos β = " : "radius ",
               radius / std::cos(beta), " m (the projectile meets only the SPH core), got ", a,
               " m");
  SPHFEM_CHECK(0.5 * s.clamped_diameter > std::numbers::sqrt2 * a,
               "plate.clamped_diameter: the clamped circle must enclose the SPH core's corners (",
               2 * std::numbers::sqrt2 * a, " m across), got ", s.clamped_diameter, " m");
  SPHFEM_CHECK(s.nose.nose_length(radius) < s.length, "projectile.length: ", s.length,
               " m must exceed the nose's length ", s.nose.nose_length(radius), " m");
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

  const double low = s.symmetry == Sector::Full ? -a : 0.0;
  BodySpec core;
  core.name = "plate_core";
  core.method = Method::Sph;
  core.geometry.kind = GeometrySpec::Kind::Box;
  core.geometry.box = {Vec3(s.symmetry == Sector::Quarter ? 0.0 : -a, low, -t), Vec3(a, a, 0)};
  core.spacing = dp;
  core.h_factor = s.core_h_factor;
  core.lattice = BodySpec::Lattice::Nodes;
  core.material = s.plate_material;

  BodySpec ring = fem_body("plate_ring", s.plate_material, dp);
  ring.geometry.kind = GeometrySpec::Kind::Ring;
  ring.geometry.ring = {Vec3(0, 0, -t),     a,         0.5 * s.clamped_diameter, t,
                        s.rim_element_size, s.symmetry};

  // The projectile's base (its nose's tip) B on the line through the plate's centre along â,
  // so high that its lowest point, min over its surface of z − B_z = min_z (z cos β − r(z) sin β)
  // (z along the axis from the tip; r(z) the nose's radius, R on the shank), is `gap` above.
  const Vec3 along(std::sin(beta), 0, std::cos(beta));
  const double nose = s.nose.nose_length(radius);
  double lowest = nose * std::cos(beta) - radius * std::sin(beta); // the shank's lowest edge
  for (int i = 0; i < 1000; ++i) {
    const double z = nose * i / 1000;
    lowest = std::min(lowest, z * std::cos(beta) - s.nose.radius_at(z, radius) * std::sin(beta));
  }
  const Vec3 base = (gap - lowest) / std::cos(beta) * along;
  BodySpec projectile = fem_body("projectile", s.projectile_material, element);
  projectile.geometry.kind = GeometrySpec::Kind::Cylinder;
  projectile.geometry.cylinder = {base, s.length * along, radius, s.symmetry, s.nose};
  projectile.h_factor = s.projectile_h_factor;
  projectile.velocity = -s.velocity * along;

  c.bodies = {core, ring, projectile};
  c.attachments = {{ring.name, core.name}};
  ContactSpec contact = s.contact;
  contact.bodies = {core.name, projectile.name};
  c.contacts = {contact};
  c.boundary_conditions = {condition(BoundaryType::Fixed, ring.name, "rim")};
  for (const BodySpec* body : {&core, &ring, &projectile}) {
    if (s.symmetry == Sector::Quarter)
      c.boundary_conditions.push_back(condition(BoundaryType::Symmetry, body->name, "xmin"));
    if (s.symmetry != Sector::Full)
      c.boundary_conditions.push_back(condition(BoundaryType::Symmetry, body->name, "ymin"));
  }
  const char* symmetry = s.symmetry == Sector::Quarter ? "quarter"
                         : s.symmetry == Sector::Half  ? "half"
                                                       : "none";
  c.scene = SceneSpec{"plate_impact", s.preset, symmetry, s.obliquity, dp, a, s.velocity};
  // The section through the impact axis, a quarter spacing off the plane y = 0 so that it cuts
  // elements and particle layers rather than running along them. Its normal is −y so that the
  // section's in-plane axis u = z × n is +x: a quarter model (x ≥ 0) is drawn at u ≥ 0. The
  // picture shows the core and as much ring again (|x| ≤ 2 half_width), where the plate bulges.
  if (!c.output.section)
    c.output.section =
        SectionPlane{Vec3(0, 0.25 * dp, -0.5 * t), -Vec3::UnitY(),
                     std::array<double, 2>{s.symmetry == Sector::Quarter ? 0.0 : -2 * a, 2 * a}};
}

void read_plate_impact(const CaseNode& root, Case& c) {
  CaseNode::Names material_names;
  for (const MaterialSpec& material : c.materials)
    material_names.push_back(material.name);
  PlateImpactSpec s;
  if (const CaseNode preset = root.child("preset"); preset.defined())
    s.preset = preset.one_of({"coarse", "standard", "fine"}, "preset");
  if (const CaseNode symmetry = root.child("symmetry"); symmetry.defined()) {
    const std::string name = symmetry.one_of({"quarter", "half", "none"}, "symmetry");
    s.symmetry = name == "quarter" ? Sector::Quarter : name == "half" ? Sector::Half : Sector::Full;
  }

  const CaseNode plate = root.required("plate", "thickness, clamped_diameter, material");
  plate.check_keys({"thickness", "clamped_diameter", "rim_element_size", "material"});
  s.thickness = plate.required("thickness", "plate thickness, m").number("> 0 m", positive);
  s.clamped_diameter = plate.required("clamped_diameter", "diameter of the clamped rim, m")
                           .number("> 0 m", positive);
  s.rim_element_size =
      plate.number_or("rim_element_size", 0.0, ">= 0 m (0: square elements)", non_negative);
  s.plate_material =
      plate.required("material", "name of a material").one_of(material_names, "material");

  // The core's keys are each optional, and so is the block: the scene sizes the core.
  if (const CaseNode core = root.child("core"); core.defined()) {
    core.check_keys({"half_width", "spacing", "h_factor"});
    if (const CaseNode half_width = core.child("half_width"); half_width.defined())
      s.core_half_width = half_width.number("> 0 m", positive);
    if (const CaseNode spacing = core.child("spacing"); spacing.defined())
      s.spacing = spacing.number("> 0 m", positive);
    s.core_h_factor = core.number_or("h_factor", s.core_h_factor, "in [1.0, 2.0]", [](double v) {
      return v >= sph_h_factor_low && v <= sph_h_factor_high;
    });
  }

  const CaseNode projectile = root.required("projectile", "diameter, length, material, velocity");
  projectile.check_keys({"diameter", "length", "nose", "nose_length", "crh", "material", "velocity",
                         "obliquity", "gap", "element_size", "h_factor", "contact"});
  s.diameter = projectile.required("diameter", "m").number("> 0 m", positive);
  s.length = projectile.required("length", "m").number("> 0 m", positive);
  using Shape = NoseGeometry::Shape;
  if (const CaseNode nose = projectile.child("nose"); nose.defined()) {
    const std::string shape = nose.one_of({"blunt", "hemispherical", "conical", "ogival"}, "nose");
    s.nose.shape = shape == "hemispherical" ? Shape::Hemispherical
                   : shape == "conical"     ? Shape::Conical
                   : shape == "ogival"      ? Shape::Ogival
                                            : Shape::Flat;
  }
  const CaseNode nose_length = projectile.child("nose_length"), crh = projectile.child("crh");
  if (s.nose.shape == Shape::Conical)
    s.nose.length = projectile.required("nose_length", "the cone's length, tip to shoulder, m")
                        .number("> 0 m", positive);
  else if (nose_length.defined())
    nose_length.fail(nose_length.path(), "only for nose: conical");
  if (s.nose.shape == Shape::Ogival)
    s.nose.crh = projectile.required("crh", "the ogive's calibre-radius-head")
                     .number(">= 0.5 (0.5 is a hemisphere)", [](double v) { return v >= 0.5; });
  else if (crh.defined())
    crh.fail(crh.path(), "only for nose: ogival");
  s.projectile_material =
      projectile.required("material", "name of a material").one_of(material_names, "material");
  s.velocity = projectile.required("velocity", "impact speed towards the plate, m/s")
                   .number(">= 0 m/s (positive towards the plate)", non_negative);
  s.obliquity = projectile.number_or("obliquity", 0.0, "in [0, 90) degrees from the plate's normal",
                                     [](double v) { return v >= 0 && v < 90; });
  if (const CaseNode gap = projectile.child("gap"); gap.defined())
    s.gap = gap.number("> 0 m", positive);
  if (const CaseNode size = projectile.child("element_size"); size.defined())
    s.element_size = size.number("> 0 m", positive);
  s.projectile_h_factor = projectile.number_or("h_factor", s.projectile_h_factor, "> 0", positive);
  // The projectile–plate contact: a surface contact with the default penalty unless given.
  s.contact = projectile.child("contact").contact_law(c.material(s.plate_material),
                                                      c.material(s.projectile_material));
  try {
    expand_plate_impact(s, c);
  } catch (const Error& e) {
    root.fail("scene plate_impact", e.what());
  }
}

} // namespace sphfem
