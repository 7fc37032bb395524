// model.h5: the meshed Model in a self-describing HDF5 file. Verified by
// tests/io/model_h5_test.cpp.
//
// Layout (format "sphfem-model", format_version 3, sealed: sealed_h5.hpp; indices 0-based
// int32, coordinates float64; strings fixed-length UTF-8, null-padded — version 1's
// variable-length strings are refused):
//   /                 attributes format, format_version (int), generator, units, signature
//   /bodies/names     B strings; body ids index this list
//   /bodies/spacing   B lattice spacings Δp (0 for FE bodies), attribute units = "m"
//   /nodes/x          N×3 reference positions, attribute units = "m"
//   /nodes/body_id    N
//   /elements/hex     E×8 connectivity, attribute node_order = "gmsh hexahedron"
//   /elements/body_id E
//   /node_sets/<body>/<face>  sorted node indices of set "<body>/<face>"
//   /face_sets/<body>/<face>  F×4 quads, right-hand normal out of the body
//   /particles/x       P×3 SPH particle positions, units "m"
//   /particles/mass    P, units "kg"
//   /particles/density P, units "kg/m^3"
//   /particles/h       P smoothing lengths, units "m"
//   /particles/body_id P
//   /particles/interface P, 1 if a background particle lies within h_i + h_b, else 0
//   /particle_faces/<body>/<face>/index  particle indices of face "<body>/<face>"
//   /particle_faces/<body>/<face>/area   their tributary areas, units "m^2"
//   /particle_faces/<body>/<face>        attribute normal = outward unit normal (3 float64)
//   /coupling/background_nodes  B ascending node indices carrying background particles
//   /coupling/h                 B their smoothing lengths, units "m"
//   /coupling/spacing           B their lattice spacings Δp, units "m"
// /particles, /bodies/spacing, /particle_faces, /coupling and /particles/interface were added
// without a version change: the writer always writes them (P and B may be 0, /particle_faces may
// be empty), and a file without them (written before SPH bodies, particle faces or coupling
// existed) reads as a model with no particles, spacing 0 for every body, no particle faces, no
// background particles and interface 0 for every particle. That is what such a file's case
// makes: a case with attach or contact pairs has a different signature (mesher/mesher.hpp), so
// its older model is stale and re-meshed.
// A set's name maps to an HDF5 path below /node_sets or /face_sets ("bar/zmin" is dataset
// zmin in group bar), a particle face's to a group below /particle_faces (group zmin in group
// bar). Large datasets are chunked and compressed (shuffle + deflate). Reading checks every
// dataset's claimed size against its element size and the bytes the file stores before it
// allocates anything (a corrupt header may claim any extent; fuzz/regressions/model_h5/).
#pragma once

#include "solver/state/model.hpp"

#include <filesystem>

namespace sphfem {

// Writes `file` + ".tmp" and renames it over `file`, so a crash never leaves a torn file.
// An empty Model::spacing_b is written as 0 for every body. Throws sphfem::Error naming the
// file if it cannot be written or the model's arrays do not match (including a particle face
// whose areas do not match its particles or whose indices are out of range, or coupling arrays
// that do not match). An empty Model::interface_p is written as 0 for every particle.
void write_model_h5(const Model& m, const std::filesystem::path& file);

// Reads and checks a model file (its seal before anything else, format, version, shapes, index
// ranges; particles: positive finite mass, density and h, finite positions, bodies with a positive
// spacing; particle faces: particle indices in range, one positive finite area each, a unit normal;
// coupling: ascending node indices in range with one positive finite h and spacing each, interface
// 0 or 1 per particle); any problem is a sphfem::Error naming the file and what is wrong or
// missing.
Model read_model_h5(const std::filesystem::path& file);

} // namespace sphfem
