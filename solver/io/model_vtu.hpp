// model.vtu: the meshed Model as a VTK XML unstructured grid (hex cells, body ids and one
// 0/1 point array "set:<body>/<face>" per node set) to inspect in ParaView. Verified by
// tests/io/model_h5_test.cpp.
#pragma once

#include "solver/state/model.hpp"

#include <filesystem>

namespace sphfem {

// Appended raw binary, LZ4-compressed; written to `file` + ".tmp" and renamed. Throws
// sphfem::Error naming the file if it cannot be written.
void write_model_vtu(const Model& m, const std::filesystem::path& file);

} // namespace sphfem
