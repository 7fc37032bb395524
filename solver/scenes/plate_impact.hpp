// The plate perforation scene (`scene: plate_impact`, DESIGN.md "Case file"; solver/scenes/
// scene.hpp): a cylindrical projectile — blunt, or with a hemispherical, conical or ogival nose
// (mesher/nose.cpp) — strikes the centre of a circular plate clamped at its rim. The case states a
// few physical parameters in its `preset`, `symmetry`, `plate`, `core` and `projectile` blocks;
// read_plate_impact() reads them into a PlateImpactSpec and expand_plate_impact() turns that into
// ordinary bodies, couplings and boundary conditions (METHOD.md §4):
//   plate_core  SPH box |x|, |y| ≤ a through the thickness, lattice on nodes (spacing Δp);
//   plate_ring  FE ring around it (RingGeometry), Δp at the core, graded to the clamped rim;
//               attached to plate_core (its interface nodes coincide with the lattice's);
//   projectile  FE cylinder along â = (sin β, 0, cos β), β the obliquity, velocity −v â, its
//               axis through the plate's centre and its lowest point `gap` above the plate; in
//               contact with plate_core (a surface contact unless the case names the kernel
//               one); by default the gap is a quarter element beyond where the contact starts:
//               the core's spheres (Δp/2 above its top layer) or the kernel's reach h_core +
//               h_projectile;
//   plate_ring/rim fixed; symmetry quarter (normal impact only): the three bodies cut at x = 0
//               and y = 0, half: at y = 0, with symmetry conditions there (mirror particles for
//               SPH, rollers for FE).
// The plate's impact face is z = 0, its back face z = −thickness; the normal impact's axis is −z,
// an oblique one's leans towards +x above the plate (the projectile travels towards −x).
// Resolution presets set Δp (the core spacing, the ring's size at the core and the projectile's
// element size): coarse 1.5 mm, standard 1 mm, fine 0.75 mm (8, 12 and 16 particles through
// Børvik's 12 mm; at 2 mm, 6, no plug separates at 303.5 m/s); an explicit core.spacing or
// projectile.element_size wins. Verified by tests/scenes/plate_impact_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/io/case_node.hpp"

#include <optional>
#include <string>

namespace sphfem {

struct PlateImpactSpec {
  std::string preset = "standard"; // coarse, standard or fine
  Sector symmetry = Sector::Full;  // quarter, half (y ≥ 0) or the whole (none)
  double obliquity = 0;            // degrees from the plate's normal, in the x–z plane
  // plate
  double thickness = 0, clamped_diameter = 0; // m
  double rim_element_size = 0;                // m, 0: square elements at the rim
  std::string plate_material;
  // SPH core
  std::optional<double> core_half_width; // m, else the scene's (core_half_width_for)
  std::optional<double> spacing;         // m, else the preset's
  double core_h_factor = 1.2;            // h/Δp
  // projectile
  double diameter = 0, length = 0;    // m
  double velocity = 0;                // m/s towards the plate
  std::optional<double> gap;          // m, else just beyond the contact's reach
  std::optional<double> element_size; // m, else the preset's
  double projectile_h_factor = 1.2;   // its contact face's background particles
  NoseGeometry nose;                  // blunt (flat) unless given; its tip `gap` above the plate
  std::string projectile_material;
  ContactSpec contact; // its law (model, penalty, exponent, friction); the bodies are set here
};

// The presets' names and spacings, m.
struct ResolutionPreset {
  const char* name;
  double spacing;
};
inline constexpr ResolutionPreset resolution_presets[] = {
    {"coarse", 0.0015}, {"standard", 0.001}, {"fine", 0.00075}};

// The SPH core's half-width when the case does not give one: the projectile's footprint swept
// through the plate — R / cos β at the impact face, shifted by t tan β at the back — plus a
// margin of core_margin × t where the plate still deforms plastically, rounded up to whole
// spacings Δp (so that the lattice and the ring meet).
inline constexpr double core_margin = 0.75;
double core_half_width_for(const PlateImpactSpec& s, double spacing);

// The spacing of a preset; throws for an unknown name.
double preset_spacing(const std::string& preset);

// Appends the scene's bodies, attachment, contact pair, boundary conditions and report section
// and its SceneSpec to `c` (whose materials are read). Throws sphfem::Error for an inconsistent
// scene, naming the key (e.g. "core.half_width: must exceed the projectile's radius 0.01 m").
void expand_plate_impact(const PlateImpactSpec& s, Case& c);

// Reads the scene's blocks at the case's top level (`root`) into a PlateImpactSpec, located
// errors for every value, and expands it into `c` (whose materials are read); the scene's own
// checks are reported at the top of the file under "scene plate_impact".
void read_plate_impact(const CaseNode& root, Case& c);

} // namespace sphfem
