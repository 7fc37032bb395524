#include "post/frames.hpp"

#include "post/post.hpp"
#include "solver/core/error.hpp"

#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkNew.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <string>

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

namespace {

// Keeps the first error VTK reports and silences the rest: left alone, VTK prints each error
// of a bad file over several coloured lines of the terminal.
class FirstError : public vtkCommand {
public:
  static FirstError* New() { return new FirstError; }
  void Execute(vtkObject*, unsigned long event, void* data) override {
    if (event != vtkCommand::ErrorEvent || !text.empty() || !data)
      return;
    // "ERROR: In <source>, line <n>\n<class> (<address>): <what>\n\n": keep <what>.
    const std::string message = static_cast<const char*>(data);
    const std::size_t start = message.find("): ");
    const std::size_t from = start == std::string::npos ? 0 : start + 3;
    text = message.substr(from, message.find('\n', from) - from);
  }
  std::string text;
};

} // namespace

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& file) {
  SPHFEM_CHECK(fs::is_regular_file(file), file.string(), ": no such frame file");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkNew<FirstError> error;
  for (const unsigned long event : {vtkCommand::ErrorEvent, vtkCommand::WarningEvent}) {
    reader->AddObserver(event, error);
    reader->GetExecutive()->AddObserver(event, error);
  }
  reader->SetParserErrorObserver(error);
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  SPHFEM_CHECK(error->text.empty() && reader->GetErrorCode() == 0, file.string(),
               ": cannot read the frame (VTK: ",
               error->text.empty() ? "error code " + std::to_string(reader->GetErrorCode())
                                   : error->text,
               ")");
  SPHFEM_CHECK(grid && grid->GetNumberOfPoints() > 0, file.string(),
               ": cannot read the frame (it has no points)");
  // VTK's reader takes a cell's point ids as written; the users index point arrays with them.
  const vtkIdType points = grid->GetNumberOfPoints();
  for (vtkIdType k = 0; k < grid->GetNumberOfCells(); ++k) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(k, n, ids);
    SPHFEM_CHECK(grid->GetCellType(k) != VTK_HEXAHEDRON || n == 8, file.string(), ": cell ", k,
                 " is a hexahedron of ", n, " points, expected 8");
    for (vtkIdType a = 0; a < n; ++a)
      SPHFEM_CHECK(ids[a] >= 0 && ids[a] < points, file.string(), ": cell ", k, " refers to point ",
                   ids[a], ", expected 0 to ", points - 1);
  }
  return grid;
}

vtkDataArray* frame_array(vtkDataSetAttributes* data, const char* name, int components,
                          vtkIdType count, const fs::path& file, bool required) {
  vtkDataArray* a = data->GetArray(name);
  SPHFEM_CHECK(a || !required, file.string(), ": no ", name, " array");
  if (a)
    SPHFEM_CHECK(a->GetNumberOfComponents() == components && a->GetNumberOfTuples() == count,
                 file.string(), ": array ", name, " has ", a->GetNumberOfTuples(), "×",
                 a->GetNumberOfComponents(), " values, expected ", count, "×", components);
  return a;
}

} // namespace sphfem::post
