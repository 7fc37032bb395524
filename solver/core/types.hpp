// Basic numeric types shared by every module. Units are SI throughout (m, kg, s, Pa, J).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

namespace sphfem {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Index = std::int32_t;

// Hexahedron connectivity in gmsh order: nodes 0–3 bottom face counter-clockwise seen
// about +ζ (nodes 0,1,2,3 at ζ = −1), nodes 4–7 above them at ζ = +1 (METHOD.md §3).
using Hex = std::array<Index, 8>;
// Quadrilateral face, nodes ordered so that the right-hand normal points out of the body.
using Quad = std::array<Index, 4>;

} // namespace sphfem
