// Result frames for ParaView: per frame one VTU (XML, appended raw binary, LZ4) with the FE
// mesh in its current configuration (frames/fe_*.vtu, part 0) and one with the particles as
// vertices (frames/sph_*.vtu, part 1), each only if the model has them; results.pvd lists the
// complete frames with their times. VTK 9.1 has no .pvd writer: the small XML collection is
// written here, atomically.
// A distributed run (issue 28) writes each frame in parallel: every rank its piece — the
// elements it computes with the nodes they hold, the particles it steps — as
// frames/fe_NNNNNN_R.vtu and sph_NNNNNN_R.vtu; once every rank has written, rank 0 writes the
// parallel files fe_NNNNNN.pvtu and sph_NNNNNN.pvtu that name the pieces (one per rank), and
// results.pvd lists those: ParaView opens the run as before. A node shared by two ranks'
// elements is in both pieces; the `id` arrays give each point and cell its index in model.h5.
// FE point data: displacement (m), velocity (m/s), body_id, id; cell data: stress (symmetric
// tensor XX YY ZZ XY YZ XZ, Pa), von_mises (Pa), pressure (Pa), density (kg/m³), body_id, id.
// Particle point data: displacement, velocity, stress, von_mises, pressure, density, h (m),
// internal_energy (specific, J/kg), mass (kg), neighbours (count within 2h), body_id, id (index in
// model.h5).
// With a Johnson–Cook material, also plastic_strain, damage and temperature (K) on particles
// and cells, killed (particles, 0/1), eroded (cells, 0/1) and yielding (0/1: the point's
// equivalent stress has reached its static flow stress, its next update returns to the yield
// surface — the active plastic zone; material/material_point.hpp: yielding); eroded cells are
// marked hidden in the vtkGhostType array, so ParaView does not draw them.
// Verified by tests/e2e/run_test.cpp (frames re-read with VTK's reader) and, in pieces, by
// tests/e2e/mpi_launch_test.cpp (read back by the post tool as the single process's frames).
#pragma once

#include "solver/io/state_archive.hpp"
#include "solver/material/material.hpp"

#include "solver/state/hex_elements.hpp"
#include "solver/state/nodes.hpp"
#include "solver/state/particles.hpp"

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

class vtkUnstructuredGrid;

namespace sphfem {

// What one rank of a distributed run writes of a frame: its elements and its real particles'
// rows, each ascending.
struct FramePiece {
  int rank = 0, ranks = 1;
  std::span<const Index> elements;
  std::span<const Index> particle_rows;
};

class FrameWriter {
public:
  // Frames of a model with these elements and particles (the arrays each part has), of these
  // materials (indexed as material_e and material_p).
  FrameWriter(const std::filesystem::path& out_dir, const HexElements& e,
              const Particles& particles, std::vector<Material> materials);
  ~FrameWriter();

  // The whole model into one file per part; with `piece`, this rank's piece of each part.
  // Collective with a piece: a rank that cannot write its piece stops every rank, with the
  // frame left out of results.pvd.
  void write(double time, const Nodes& nodes, const HexElements& e, const Particles& particles,
             const FramePiece* piece = nullptr);
  int frame_count() const { return frame_count_; }
  // Checkpoint: the frames listed so far. Reading them back makes the next write continue the
  // numbering and the collection (a restart overwrites the frames written after the checkpoint).
  void persist(StateArchive& a);

private:
  void write_parts(const Nodes& nodes, const HexElements& e, const Particles& particles,
                   const FramePiece* piece);
  void write_collection() const;

  std::filesystem::path out_dir_;
  std::vector<Material> materials_;
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
