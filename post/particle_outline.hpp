// The outline of particles projected onto a plane, for sections (post/section.hpp).
//
// Method: the smoothed indicator (the SPH colour function) of the material the particles stand
// for, f(x) = Σ_i A_i G(x − x_i), with A_i the in-plane area particle i represents and G the
// normalised 2-D Gaussian of σ = Δp/2, is sampled on a grid of Δp/6 cells and its f = 1/2 level
// is traced by marching squares (vtkMarchingSquares), then chained into polylines
// (vtkStripper). Why this and not disks or alpha shapes: inside a lattice f = 1 to within 3 %
// (lattice ripple 4·exp(−2π²σ²/Δp²)), and at a straight free surface the 1/2 level is the
// material's edge, half a spacing outside the outer particles, as the convolution of a step
// with a symmetric kernel is 1/2 at the step; disks small enough to stay inside that edge
// (r < 0.707 Δp) leave holes between the lattice sites, and an alpha shape needs a radius
// tuned to the deformation. Corners round off over about σ; a lone particle of area Δp² keeps
// a small loop (radius 0.35 Δp), so fragments stay visible. The grid reaches 3 Δp beyond the
// particles, so every outline is closed.
// Verified by tests/post/section_test.cpp (a disk of particles outlines the disk).
#pragma once

#include <Eigen/Core>

#include <vector>

class vtkPolyData;

namespace sphfem::post {

using Polyline2 = std::vector<Eigen::Vector2d>;

// Closed outlines (first point repeated at the end) of the particles at `x` (plane coordinates,
// m), each standing for the in-plane area `area` (m²; Δp² for an undeformed lattice), with the
// lattice spacing `spacing` (m, > 0). No particles: no outlines.
std::vector<Polyline2> particle_outline(const std::vector<Eigen::Vector2d>& x,
                                        const std::vector<double>& area, double spacing);

// The line cells of `lines` chained into polylines (vtkStripper) as lists of point ids; a closed
// loop repeats its first id at the end.
std::vector<std::vector<long long>> chain_segments(vtkPolyData* lines);

} // namespace sphfem::post
