// Result frames for ParaView: one VTU per frame (XML, appended raw binary, LZ4) with the FE
// mesh in its current configuration, and results.pvd listing the complete frames with their
// times. VTK 9.1 has no .pvd writer: the small XML collection is written here, atomically.
// Point data: displacement (m), velocity (m/s), body_id; cell data: stress (symmetric tensor
// XX YY ZZ XY YZ XZ, Pa), von_mises (Pa), pressure (Pa), density (kg/m³), body_id.
// Verified by tests/e2e/run_test.cpp (frames re-read with VTK's reader).
#pragma once

#include "solver/state/hex_elements.hpp"
#include "solver/state/nodes.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

class vtkUnstructuredGrid;

namespace sphfem {

class FrameWriter {
public:
  FrameWriter(const std::filesystem::path& out_dir, const Nodes& nodes, const HexElements& e);
  ~FrameWriter();

  void write(double time, const Nodes& nodes, const HexElements& e);
  int frame_count() const { return static_cast<int>(frames_.size()); }

private:
  void write_collection() const;

  std::filesystem::path out_dir_;
  struct Grid;
  std::unique_ptr<Grid> grid_;
  std::vector<std::pair<double, std::string>> frames_; // time, relative file name
};

} // namespace sphfem
