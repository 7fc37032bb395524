// model.vtu: the meshed Model as a VTK XML unstructured grid (hex cells, body ids, a 0/1 point
// array "background" marking the nodes that carry background particles, and one 0/1 point array
// "set:<body>/<face>" per node set) to inspect in ParaView; and, only when the model has SPH
// particles, model_particles.vtu next to it: one VTK_VERTEX cell per particle, point data
// body_id, mass (kg), h (m), density (kg/m³), "interface" (0/1, Model::interface_p) and one 0/1
// array "set:<body>/<face>" per particle face. Verified by tests/io/model_h5_test.cpp.
#pragma once

#include "solver/state/model.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace sphfem {

// Further integer arrays by name (a decomposition's rank, say): one value per cell and per point.
struct VtuIntFields {
  std::map<std::string, std::vector<int>> cells, points;
};

// Appended raw binary, LZ4-compressed; written to `file` + ".tmp" and renamed. Throws
// sphfem::Error naming the file if it cannot be written or an extra array has the wrong size.
void write_model_vtu(const Model& m, const std::filesystem::path& file,
                     const VtuIntFields& extra = {});

// The particles, written the same way (their extra arrays are point arrays, one per particle).
// When the model has no particles nothing is written and an existing `file` is removed, so no
// particles of an earlier model are left behind.
void write_particles_vtu(const Model& m, const std::filesystem::path& file,
                         const VtuIntFields& extra = {});

} // namespace sphfem
