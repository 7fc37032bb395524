// `sphfem post plug`: the fragments that have separated from the target and the plug, from one
// frame of a run (OUT/results.pvd, OUT/model.h5). Fragments are found by post/fragments.hpp on
// the target body's surviving particles (killed = 0) and elements (eroded = 0); element mass =
// cell density × volume of the trilinear hexahedron on its current nodes.
// Impact axis: the direction of the other bodies' total momentum in the first frame (element
// momentum = ρ V × mean node velocity), else +z if they have none; plug.json says which.
// A fragment's travel: its centre of mass's displacement along the impact axis since the first
// frame (the same particles and elements there; element positions at the mean of their nodes).
// Main = the most massive fragment; plug = the most massive other fragment moving along the
// impact axis (velocity · axis > 0), if any. Passed through: the nose of the other body with the
// largest momentum along the axis in the first frame (the projectile) lies beyond the target's
// rear face of the first frame, and no part of the main fragment lies ahead of it within half the
// projectile's radius of its axis (a projectile through a target that shattered without a plug,
// its tail perhaps still in the hole; a plug still hanging on the plate blocks the path).
// Writes DIR/plug.json (SI units), DIR/fragments.csv (one row per fragment) and DIR/plug.png:
// each fragment's outline, the convex hull of its points projected on a plane containing the
// impact axis (particles as squares of side Δp), in mm, the plug highlighted.
// Verified by tests/post/plug_test.cpp.
#pragma once

#include "post/fragments.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace sphfem::post {

struct PlugOptions {
  std::filesystem::path run;     // OUT, holding results.pvd and model.h5
  std::string body;              // target body; empty: the only body with particles
  std::optional<double> time;    // s; the frame nearest to it; empty: the last frame
  double connect = 1.5;          // connectivity distance / lattice spacing
  long long min_pieces = 27;     // particles and elements a plug holds at least
  std::filesystem::path out_dir; // empty: OUT/post
  int width = 900, height = 560;
};

struct PlugResult {
  std::string body; // the target's name
  double time = 0;  // s
  Vec3 impact_axis = Vec3::UnitZ();
  std::vector<Fragment> fragments; // most massive first
  int main = -1, plug = -1;        // indices into fragments, -1: none
  bool passed_through = false;     // the projectile's path through the target is open
  double debris_mass = 0;          // kg: killed particles and eroded elements
  // Per particle and per element of the frame (all bodies, in the frame's order): 1 for the
  // target's pieces that are not part of its main fragment (plug, other fragments, debris).
  std::vector<char> detached_p, detached_e;
  std::filesystem::path json, csv, png;
};

// Reads and checks everything before writing; bad input (no results.pvd or model.h5, unknown
// body, several particle bodies without `body`, a missing frame) throws sphfem::Error.
PlugResult write_plug(const PlugOptions& options);

} // namespace sphfem::post
