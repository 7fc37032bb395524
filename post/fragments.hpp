// Fragments: the connected pieces of a body's surviving particles and elements, and what an
// engineer measures on each (mass, centre of mass, velocity, thickness and diameter).
// Pure functions over arrays, so they are testable without files; post/plug.hpp reads the
// arrays from a run's frames.
// Connectivity: two surviving particles connect when closer than `reach`; surviving elements
// connect through shared nodes; a particle connects to an element when it is closer than
// `reach` to one of the element's nodes. Neighbours come from a cell list of cell size `reach`
// (O(N log N)), components from union–find. Killed particles and eroded elements are debris.
// Sizes: a particle stands for a cube of side Δp (the lattice spacing) aligned with the
// measuring axes, so a lattice block measures its physical size; element nodes are taken as
// they are. thickness = extent along the impact axis; diameter = largest extent perpendicular
// to it (the diameter of the convex hull of the projection on the plane normal to the axis).
// An element's mass and velocity sit at the mean of its nodes. Units: SI.
// Verified by tests/post/plug_test.cpp.
#pragma once

#include "solver/core/types.hpp"

#include <vector>

namespace sphfem::post {

struct Fragment {
  double mass = 0;                                  // kg
  Vec3 com = Vec3::Zero(), velocity = Vec3::Zero(); // m, m/s
  long long particles = 0, elements = 0;
  double diameter = 0, thickness = 0; // m
  double travel = 0; // m: its centre of mass's displacement along the axis since the first frame
};

// One body's particles and elements at one time. Node arrays may hold nodes no element uses.
struct FragmentSource {
  std::vector<Vec3> x_p, v_p; // particle positions (m), velocities (m/s)
  std::vector<double> m_p;    // kg
  std::vector<char> killed_p; // 1: debris; empty: none killed
  std::vector<Vec3> x_n, v_n; // node positions (m), velocities (m/s)
  std::vector<Hex> hex_e;     // element connectivity into x_n
  std::vector<double> m_e;    // element mass, kg
  std::vector<char> eroded_e; // 1: debris; empty: none eroded
};

struct FragmentSet {
  std::vector<Fragment> fragments;         // most massive first (ties: order of first particle)
  std::vector<int> fragment_p, fragment_e; // index into fragments per particle/element, -1: debris
  long long debris_particles = 0, debris_elements = 0;
  double debris_mass = 0; // kg
};

// The fragments of `source`; `reach` = connectivity distance (m), `spacing` = Δp (m, 0 without
// particles), `axis` = unit impact axis. Throws sphfem::Error on mismatched arrays.
FragmentSet find_fragments(const FragmentSource& source, double reach, double spacing,
                           const Vec3& axis);

// The largest fragment after fragments[0] (the main one) whose velocity along `axis` is positive
// and which holds at least `min_pieces` particles and elements (default 27, a 3 × 3 × 3 block:
// smaller moving pieces — a spalled particle, a few torn from a crack — are not a plug); -1 if
// none.
int find_plug(const std::vector<Fragment>& fragments, const Vec3& axis, long long min_pieces = 27);

// Whether a projectile (its particles and element nodes) has passed through a target: its nose
// lies beyond `rear` (the target's rear face, along `axis`), and no part of the target's main
// fragment (fragments[0]) lies ahead of the nose within half the projectile's radius of its axis
// (the line along `axis` through the mean of its points). A plug still hanging on the plate
// belongs to the main fragment and lies ahead; a plug that has left, or debris, does not — so a
// projectile through a target that shattered without a plug has passed through while its tail is
// still in the hole.
bool path_open(const std::vector<Vec3>& projectile, const FragmentSource& target,
               const FragmentSet& set, double rear, const Vec3& axis);

// A unit vector perpendicular to `axis`: the global axis least aligned with it, made
// perpendicular (x for an axis along z).
Vec3 lateral_direction(const Vec3& axis);

using Point2 = Eigen::Vector2d;

// Convex hull, counter-clockwise, no collinear points (Andrew's monotone chain).
std::vector<Point2> convex_hull(std::vector<Point2> points);

// Largest distance between two points of a convex polygon (rotating calipers).
double hull_diameter(const std::vector<Point2>& hull);

// Per fragment, the convex hull of its points projected on the plane spanned by the unit
// vectors e_x, e_y (coordinates x·e_x, x·e_y, m); particles as squares of side `spacing`.
std::vector<std::vector<Point2>> fragment_outlines(const FragmentSource& source,
                                                   const FragmentSet& set, const Vec3& e_x,
                                                   const Vec3& e_y, double spacing);

} // namespace sphfem::post
