// The frames of a run as the post tool reads them back: results.pvd's list grouped per time
// into its particle file (frames/sph_*.vtu, or .pvtu) and FE file (frames/fe_*.vtu, .pvtu), the
// frame nearest to a time, and one VTU file read with VTK's own reader. Used by post section and
// post plug.
#pragma once

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <filesystem>
#include <optional>
#include <vector>

namespace sphfem::post {

struct FrameFiles {
  double time;                               // s
  std::filesystem::path particles, elements; // empty if the model has none
};

// The frames results.pvd lists, in its order; an empty list is an Error.
std::vector<FrameFiles> frame_files(const std::filesystem::path& pvd);

// The index of the frame nearest to `time`; without one, the last.
std::size_t nearest_frame(const std::vector<FrameFiles>& frames, std::optional<double> time);

// One frame file, .vtu or a distributed run's .pvtu (its pieces read as one grid), in the
// model's order: particles by id, an FE mesh's nodes and hexahedra by their ids (a node shared
// by two pieces once), so that a frame reads the same whoever wrote it. A missing or unreadable
// one (VTK's reason in the message, VTK's own printing silenced), one whose cells refer to
// points it does not have, or one missing a piece is an Error naming it.
vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const std::filesystem::path& file);

// A frame file's named array with `count` tuples of `components` values; an Error naming the
// file if it has another shape, or if it is absent and `required` (else nullptr).
vtkDataArray* frame_array(vtkDataSetAttributes* data, const char* name, int components,
                          vtkIdType count, const std::filesystem::path& file, bool required = true);

} // namespace sphfem::post
