// Result frames for ParaView: per frame one VTU (XML, appended raw binary, LZ4) with the FE
// mesh in its current configuration (frames/fe_*.vtu, part 0) and one with the particles as
// vertices (frames/sph_*.vtu, part 1), each only if the model has them; results.pvd lists the
// complete frames with their times. VTK 9.1 has no .pvd writer: the small XML collection is
// written here, atomically.
// FE point data: displacement (m), velocity (m/s), body_id; cell data: stress (symmetric
// tensor XX YY ZZ XY YZ XZ, Pa), von_mises (Pa), pressure (Pa), density (kg/m³), body_id.
// Particle point data: displacement, velocity, stress, von_mises, pressure, density, h (m),
// internal_energy (specific, J/kg), mass (kg), neighbours (count within 2h), body_id, id (index in
// model.h5).
// With a Johnson–Cook material, also plastic_strain, damage and temperature (K) on particles
// and cells, killed (particles, 0/1) and eroded (cells, 0/1); eroded cells are marked hidden
// in the vtkGhostType array, so ParaView does not draw them.
// Verified by tests/e2e/run_test.cpp (frames re-read with VTK's reader).
#pragma once

#include "solver/io/state_archive.hpp"

#include "solver/state/hex_elements.hpp"
#include "solver/state/nodes.hpp"
#include "solver/state/particles.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

class vtkUnstructuredGrid;

namespace sphfem {

class FrameWriter {
public:
  FrameWriter(const std::filesystem::path& out_dir, const Nodes& nodes, const HexElements& e,
              const Particles& particles);
  ~FrameWriter();

  void write(double time, const Nodes& nodes, const HexElements& e, const Particles& particles);
  int frame_count() const { return frame_count_; }
  // Checkpoint: the frames listed so far. Reading them back makes the next write continue the
  // numbering and the collection (a restart overwrites the frames written after the checkpoint).
  void persist(StateArchive& a);

private:
  void write_collection() const;

  std::filesystem::path out_dir_;
  struct History;
  struct Grid;
  struct Cloud;
  std::unique_ptr<Grid> grid_;   // null without elements
  std::unique_ptr<Cloud> cloud_; // null without particles
  struct Entry {
    double time;
    int part;
    std::string file; // relative to out_dir
  };
  std::vector<Entry> entries_;
  int frame_count_ = 0;
};

} // namespace sphfem
