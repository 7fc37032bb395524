#include "post/frames.hpp"

#include "post/post.hpp"
#include "solver/core/error.hpp"

#include <vtkNew.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>

namespace sphfem::post {

namespace fs = std::filesystem;

std::vector<FrameFiles> frame_files(const fs::path& pvd) {
  std::vector<FrameFiles> frames;
  for (const auto& [time, file] : read_pvd(pvd)) {
    if (frames.empty() || frames.back().time != time)
      frames.push_back({time, {}, {}});
    const fs::path path = pvd.parent_path() / file;
    // frame_writer names the parts fe_NNNNNN.vtu and sph_NNNNNN.vtu.
    (path.filename().string().rfind("sph_", 0) == 0 ? frames.back().particles
                                                    : frames.back().elements) = path;
  }
  SPHFEM_CHECK(!frames.empty(), pvd.string(), ": lists no frames");
  return frames;
}

std::size_t nearest_frame(const std::vector<FrameFiles>& frames, std::optional<double> time) {
  std::size_t chosen = frames.size() - 1;
  if (time)
    for (std::size_t i = 0; i < frames.size(); ++i)
      if (std::abs(frames[i].time - *time) < std::abs(frames[chosen].time - *time))
        chosen = i;
  return chosen;
}

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& file) {
  SPHFEM_CHECK(fs::is_regular_file(file), file.string(), ": no such frame file");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  SPHFEM_CHECK(reader->GetErrorCode() == 0 && grid && grid->GetNumberOfPoints() > 0, file.string(),
               ": cannot read the frame");
  return grid;
}

} // namespace sphfem::post
