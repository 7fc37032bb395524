// The case as parsed and validated: everything a run needs, in SI units. Built only by
// read_case() (solver/io/case_reader.hpp), so every instance has passed validation.
#pragma once

#include "solver/core/time_function.hpp"
#include "solver/core/types.hpp"
#include "solver/material/adiabatic_heating.hpp"
#include "solver/material/ductile_damage.hpp"
#include "solver/material/johnson_cook.hpp"
#include "solver/material/mie_gruneisen.hpp"

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sphfem {

struct MaterialSpec {
  std::string name;
  std::string model;         // "elastic" or "johnson_cook"
  double density = 0;        // kg/m³
  double youngs_modulus = 0; // Pa
  double poisson_ratio = 0;
  std::optional<JohnsonCook> johnson_cook{}; // model johnson_cook: the flow stress
  std::optional<DuctileDamage> damage{};     // johnson_cook only
  std::optional<AdiabaticHeating> heating{}; // johnson_cook only
  std::optional<MieGruneisen> eos{};         // replaces p = K (ρ/ρ0 − 1)
  bool erosion = false;                      // failed hexahedra are removed
};

struct BoxGeometry {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();
};

// The whole of a round body, its half y ≥ y_axis (FE only; a cylinder's axis in the x–z plane)
// for half models with a symmetry plane on its cut face ymin, or its quarter x ≥ x_axis,
// y ≥ y_axis (axis along +z only) for quarter models with symmetry planes on xmin and ymin.
enum class Sector { Full, Half, Quarter };

// A projectile's nose at a cylinder's base (FE only; mesher/nose.cpp): flat (the plain
// cylinder), or a solid of revolution ending in a point on the axis at `base`, tangent to the
// cylinder where it meets it except the cone: hemispherical (its length is the radius), conical
// (`length` from tip to shoulder), ogival (a tangent ogive of calibre-radius-head `crh`, its arc
// radius crh × the diameter, its length R √(4 crh − 1)).
struct NoseGeometry {
  enum class Shape { Flat, Hemispherical, Conical, Ogival };
  Shape shape = Shape::Flat;
  double length = 0; // m, conical
  double crh = 0;    // ogival, ≥ 0.5 (0.5 is the hemisphere)

  // The nose's length along the axis, m (0 when flat).
  double nose_length(double radius) const;
  // Its radius at `z` above the tip, m, for z in [0, nose_length] (the cylinder's radius when
  // flat).
  double radius_at(double z, double radius) const;
};

// A circular cylinder: base centre, axis vector (its length is the cylinder's length, the nose
// included), radius.
struct CylinderGeometry {
  Vec3 base = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  double radius = 0;
  Sector sector = Sector::Full; // Quarter: FE bodies only
  NoseGeometry nose{};          // flat unless given (FE only)
};

// A plate ring (FE only): the plate z ∈ [base.z, base.z + thickness] between the square hole
// |x − base.x|, |y − base.y| ≤ half_width and the circle of `radius` about the vertical axis
// through `base` — the O-grid around a square SPH core. Hexahedra are element_size at the hole
// (matching a lattice of that spacing there) and grow geometrically to rim_element_size at the
// rim (0: the circumferential size there, for square elements in plan).
// Faces: inner (the hole), rim, bottom, top; a half also ymin, a quarter xmin and ymin.
struct RingGeometry {
  Vec3 base = Vec3::Zero();
  double half_width = 0, radius = 0, thickness = 0;
  double rim_element_size = 0;
  Sector sector = Sector::Full;
};

struct GeometrySpec {
  enum class Kind { Box, Cylinder, File, Ring };
  Kind kind = Kind::Box;
  BoxGeometry box;
  CylinderGeometry cylinder;
  RingGeometry ring;
  std::filesystem::path file; // File: a gmsh .geo/.step/.brep closed volume (SPH bodies only)
};

enum class Method { Fem, Sph };

// Named faces: a box has xmin, xmax, ymin, ymax, zmin, zmax; a cylinder has base, top, side
// (a half also ymin, a quarter xmin, ymin); a ring inner, rim, bottom, top (the same cuts).
// FE bodies are meshed with element_size; SPH bodies are filled with a cubic lattice of
// the given spacing Δp, smoothing length h = h_factor · Δp. An SPH box's lattice puts the
// particles at cell centres (Centred) or on the nodes of the matching hex grid (Nodes, box only).
// SPH smoothing length h = h_factor · Δp. The default 1.2 is the usual 3-D choice: the cubic
// B-spline's support 2h = 2.4 Δp then holds 57 particles of a full cubic lattice (itself
// included). Below 1.0 (27 particles) the sums are too coarse; above 2.0 (257) too costly.
inline constexpr double sph_h_factor_low = 1.0, sph_h_factor_high = 2.0;

struct BodySpec {
  enum class Lattice { Centred, Nodes };

  std::string name;
  Method method = Method::Fem;
  GeometrySpec geometry;
  double element_size = 0;            // m (fem)
  double spacing = 0;                 // m (sph)
  double h_factor = 1.2;              // sph: h/Δp; fem: background particles' h/element_size
  Lattice lattice = Lattice::Centred; // (sph)
  std::string material;
  Vec3 velocity = Vec3::Zero(); // initial velocity, m/s
};

enum class BoundaryType { Fixed, Velocity, Symmetry };

struct BoundaryConditionSpec {
  BoundaryType type = BoundaryType::Fixed;
  std::string body;
  std::string face;
  // Velocity only: prescribed components (m/s), scaled by `function`; empty = free.
  std::array<std::optional<double>, 3> velocity;
  TimeFunction function;
};

// Uniform pressure (Pa, positive pushes into the body) on a named face, scaled by `function`.
struct PressureLoadSpec {
  std::string body;
  std::string face;
  double pressure = 0;
  TimeFunction function;
};

struct TimeSpec {
  double end = 0;              // s
  double cfl = 0.9;            // fraction of the critical step
  double output_interval = 0;  // s between frames
  double history_interval = 0; // s between history rows; 0 = every step
  double energy_limit = 0.5;   // balance error (fraction) that stops the run as unstable
};

// Recorded at the body's node (FE) or particle (SPH) nearest to `point`.
struct ProbeSpec {
  std::string name;
  std::string body;
  Vec3 point = Vec3::Zero();
};

enum class HourglassForm { Viscous, Stiffness };

struct FemSpec {
  HourglassForm hourglass_form = HourglassForm::Viscous;
  double hourglass_coefficient = 0.1;
  double bulk_viscosity_linear = 0.06;   // C1
  double bulk_viscosity_quadratic = 1.5; // C0
};

// SPH options (METHOD.md §2). A term that is off is not computed at all.
struct SphSpec {
  bool artificial_viscosity = true;
  double alpha = 1.0;   // linear (bulk) coefficient
  double beta = 2.0;    // quadratic coefficient
  bool balsara = false; // scale Π_ij by the pair's mean Balsara factor (less viscosity in shear)
  bool artificial_stress = true;
  double epsilon = 0.3;       // artificial stress factor
  double stress_exponent = 4; // n in f_ij^n, a positive integer
  bool xsph = true;
  double xsph_epsilon = 0.5;
  bool variable_h = true;          // dh/dt = −(h/3ρ) dρ/dt
  bool gradient_correction = true; // L = G M⁻¹/ρ exact for linear fields; M⁻¹ in momentum too
  double cfl = 0.3;                // Δt_SPH = cfl · min h/(c + |v|)
  double skin = 0.1;               // neighbour-list skin as a fraction of the largest 2h
};

// An SPH body glued to an FE body (METHOD.md §4.2): the particles' sums include the FE
// nodes' background particles, as if the two were one body.
struct AttachSpec {
  std::string fem_body;
  std::string sph_body;
};

// How two bodies in contact meet (docs/contact.md). Surface: a penalty on the overlap of their
// physical surfaces — hexahedron faces, particles as spheres of radius Δp/2 — with optional
// Coulomb friction. Kernel: the paper's potential (METHOD.md §4.3), acting within 2h_ij.
enum class ContactModel { Surface, Kernel };

// Penalty contact between two bodies.
struct ContactSpec {
  std::array<std::string, 2> bodies;
  ContactModel model = ContactModel::Surface;
  // Pa. Kernel: the penalty pressure K. Surface: the contact modulus, the pressure per unit
  // penetration strain (penetration / the entity's size); the reader's default is the smaller
  // P-wave modulus K + 4G/3 of the two bodies' materials.
  double penalty = 0;
  double exponent = 2; // kernel: n
  double friction = 0; // surface: Coulomb coefficient μ
};

// The plane of the report's deformed section (post/section.hpp): a point on it and its normal.
struct SectionPlane {
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitY();
  std::optional<std::array<double, 2>> u_range; // the picture's window along u, m; none: all
};

// When OUT/checkpoint.h5 is written besides the run's end (and a SIGINT/SIGTERM): every
// `steps` steps (0: not by steps) and every `wall_s` seconds of wall time (0: not by time).
struct CheckpointSpec {
  long long steps = 0;
  double wall_s = 600;
};

struct OutputSpec {
  bool frames = true;
  std::optional<SectionPlane> section; // none: through the model's centre, normal y
  CheckpointSpec checkpoint;
};

// What a scene template was given (solver/scenes/plate_impact.hpp), for the run's summary.json
// ("scene"), where reports and sweeps read the impact velocity and the resolution back.
struct SceneSpec {
  std::string name;              // plate_impact
  std::string preset;            // coarse, standard, fine
  std::string symmetry = "none"; // quarter, half, none
  double obliquity = 0;          // degrees from the plate's normal, in the x–z plane
  double spacing = 0;            // the core's Δp, m
  double core_half_width = 0;    // m, given or the scene's
  double velocity = 0;           // projectile.velocity, m/s towards the plate
};

struct Case {
  std::string name;
  std::filesystem::path file; // the case file it was read from
  TimeSpec time;
  std::vector<MaterialSpec> materials;
  std::vector<BodySpec> bodies;
  std::vector<BoundaryConditionSpec> boundary_conditions;
  std::vector<PressureLoadSpec> loads;
  std::vector<ProbeSpec> probes;
  std::vector<AttachSpec> attachments;
  std::vector<ContactSpec> contacts;
  FemSpec fem;
  SphSpec sph;
  OutputSpec output;
  std::optional<SceneSpec> scene;
  // Every value of the file after overrides and material libraries, by key path ("time.cfl" →
  // "0.5"; list entries by index): the case as parsed, which a checkpoint records and a restart
  // compares.
  std::map<std::string, std::string> keys;

  const MaterialSpec& material(const std::string& name) const;
  int body_index(const std::string& name) const; // -1 if absent
  // Group of each body: its own index, or for an SPH body attached to an FE body, the FE
  // body's (the entities of one group share their SPH sums).
  std::vector<int> body_groups() const;
};

} // namespace sphfem
