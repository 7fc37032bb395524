// `sphfem post section`: the deformed cross-section of the bodies at a plane, as a report draws
// the bulged or perforated plate, and its permanent deflection profile.
//
// Plane coordinates (m): w along the deflection axis projected into the plane (default: the
// plane's in-plane direction closest to z, else to y), u = w × n with n the unit normal, both
// measured from the plane's point. FE bodies: the boundary faces of the non-eroded hexahedra
// of the frame (current configuration) cut by the plane (vtkCutter, vtkPlane) and chained into
// polylines (vtkStripper). SPH bodies: the particles within |distance| < Δp of the plane, each
// weighted by the tent 1 − |distance|/Δp (which sums to 1 over lattice layers, so a plane that
// falls between two layers sees both at half weight instead of neither or both) and standing
// for the in-plane area tent·V/Δp (V = mass/density), outlined by post/particle_outline.hpp;
// killed particles are left out of the outline and listed as points if tent > 1/4 (the nearest
// layer, or both layers a plane between them halves). Δp is the body's lattice spacing from
// OUT/model.h5, or h/1.2 without it.
// Deflection: displacement·ŵ at the points of the section — FE: where the plane crosses the
// edges of non-eroded hexahedra (linear interpolation of the nodal displacement), SPH: the live
// particles within Δp of the plane, tent-weighted — averaged in bins of |u| one element size
// (the mean over the cut hexahedra of their longest edge, reference configuration: a plate's
// in-plane size) or one Δp wide, edges halfway between the rows of points (their mean phase); a
// bin's radius is the mean |u| of its points.
// Files in DIR (default OUT/post):
//   section.csv     body,part,polyline,u_m,w_m,x_m,y_m,z_m — one row per vertex, part fe|sph,
//                   polylines numbered per body from 0 (closed ones repeat their first vertex);
//                   killed particles as rows with part killed and polyline -1
//   section.png     the polylines with equal axis scales in mm, one colour per body, over the
//                   field (plastic strain by default, or damage) on the cut with its colour bar:
//                   each live hexahedron the plane cuts as its polygon (the plane's crossings of
//                   its edges), each live particle within 0.75 Δp of the plane as a square of
//                   side Δp (the nearest painted last); with a u range, only the part of the
//                   section inside it (the data files keep all). A run without the field (an
//                   elastic one) is drawn as outlines only.
//   deflection.csv  body,radius_m,deflection_m
//   section.json    {time_s, plane: {point_m, normal}, axis, u_axis, [u_range_m], field (null
//                    if none was drawn), [field_range],
//                    bodies: {name: {max_deflection_m, polylines}}}
// Verified by tests/post/section_test.cpp.
#pragma once

#include "solver/core/types.hpp"

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sphfem::post {

struct SectionOptions {
  std::filesystem::path run;       // OUT, holding results.pvd and model.h5
  Vec3 point = Vec3::Zero();       // a point of the plane, m
  Vec3 normal = Vec3::UnitY();     // its normal (any length > 0)
  std::optional<double> time;      // s; the frame nearest to it; empty: the last frame
  std::vector<std::string> bodies; // empty: all bodies
  std::optional<Vec3> axis;        // deflection axis; empty: the in-plane direction closest to z
  std::optional<std::array<double, 2>> u_range; // the picture's window along u, m; empty: all
  std::string field = "plastic_strain";         // colours the cut: plastic_strain, damage, none
  // Left out of the deflection profile (not of the outline), indexed as the frame's particles and
  // cells; empty: none. The report leaves out the pieces that left the target (PlugResult).
  std::vector<char> leave_out_p, leave_out_e;
  std::filesystem::path out_dir; // empty: OUT/post
  int width = 900, height = 560; // PNG pixels
};

struct SectionResult {
  double time = 0; // s, of the frame used
  std::filesystem::path csv, png, deflection_csv, json;
  std::map<std::string, double> max_deflection; // body name → m
  std::string field;                            // the field drawn on the cut; empty: none
};

// Writes the four files; bad input (no results.pvd, a zero normal or axis, an unknown body, a
// plane that cuts nothing) throws sphfem::Error naming the file or option before anything is
// written.
SectionResult write_section(const SectionOptions& options);

// The part of the polyline (u, w) with lo ≤ u ≤ hi, in place: a segment crossing a bound ends
// on it (linear interpolation), a run outside becomes one break (NaN) in the line, as does a
// break (NaN) already in it.
void clip_polyline_u(std::vector<double>& u, std::vector<double>& w, double lo, double hi);

} // namespace sphfem::post
