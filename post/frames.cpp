#include "post/frames.hpp"

#include "post/post.hpp"
#include "solver/core/error.hpp"

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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

namespace {

// `in` with its points and cells in the order of `point_from` and `cell_from` (new index → old),
// the cells' point ids taken through `point_to` (old → new).
vtkSmartPointer<vtkUnstructuredGrid> reordered(vtkUnstructuredGrid* in,
                                               const std::vector<vtkIdType>& point_from,
                                               const std::vector<vtkIdType>& point_to,
                                               const std::vector<vtkIdType>& cell_from) {
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const auto np = static_cast<vtkIdType>(point_from.size());
  points->SetNumberOfPoints(np);
  out->GetPointData()->CopyAllocate(in->GetPointData(), np);
  for (vtkIdType a = 0; a < np; ++a) {
    points->SetPoint(a, in->GetPoint(point_from[static_cast<std::size_t>(a)]));
    out->GetPointData()->CopyData(in->GetPointData(), point_from[static_cast<std::size_t>(a)], a);
  }
  out->SetPoints(points);
  const auto nc = static_cast<vtkIdType>(cell_from.size());
  out->AllocateExact(nc, 8 * nc);
  out->GetCellData()->CopyAllocate(in->GetCellData(), nc);
  std::vector<vtkIdType> mapped;
  for (vtkIdType k = 0; k < nc; ++k) {
    const vtkIdType from = cell_from[static_cast<std::size_t>(k)];
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    in->GetCellPoints(from, n, ids);
    mapped.assign(ids, ids + n);
    for (auto& id : mapped)
      id = point_to[static_cast<std::size_t>(id)];
    out->InsertNextCell(in->GetCellType(from), n, mapped.data());
    out->GetCellData()->CopyData(in->GetCellData(), from, k);
  }
  return out;
}

// Each value of `ids` (an `id` array: an index in model.h5) as a position 0, 1, … in its order;
// with `shared`, a value may come several times (a node of two ranks' pieces) and its first
// place is kept; else twice is an Error. Every index from 0 to the largest must be there.
std::vector<vtkIdType> places_by_id(vtkDataArray* ids, bool shared, const char* what,
                                    const fs::path& file) {
  const vtkIdType n = ids->GetNumberOfTuples();
  vtkIdType largest = -1;
  for (vtkIdType k = 0; k < n; ++k)
    largest = std::max(largest, static_cast<vtkIdType>(ids->GetComponent(k, 0)));
  std::vector<vtkIdType> from(static_cast<std::size_t>(largest + 1), -1);
  for (vtkIdType k = 0; k < n; ++k) {
    const auto id = static_cast<vtkIdType>(ids->GetComponent(k, 0));
    SPHFEM_CHECK(id >= 0, file.string(), ": ", what, " ", k, " has id ", id, ", expected ≥ 0");
    auto& place = from[static_cast<std::size_t>(id)];
    SPHFEM_CHECK(place < 0 || shared, file.string(), ": ", what, " id ", id, " comes twice");
    if (place < 0)
      place = k;
  }
  for (std::size_t id = 0; id < from.size(); ++id)
    SPHFEM_CHECK(from[id] >= 0, file.string(), ": no ", what, " of id ", id, " (ids up to ",
                 largest, "): a piece of the frame is missing");
  return from;
}

bool identity(const std::vector<vtkIdType>& from, vtkIdType count) {
  if (static_cast<vtkIdType>(from.size()) != count)
    return false;
  for (std::size_t k = 0; k < from.size(); ++k)
    if (from[k] != static_cast<vtkIdType>(k))
      return false;
  return true;
}

// A frame in the model's order, whoever wrote it: particles by their `id`, an FE mesh's nodes by
// their point `id` (a node in two ranks' pieces taken once) and its hexahedra by their cell
// `id`. A frame of one process or of several ranks then reads the same, point for point.
// Frames without the arrays (written before they were) are read as written.
vtkSmartPointer<vtkUnstructuredGrid> in_model_order(vtkSmartPointer<vtkUnstructuredGrid> grid,
                                                    const fs::path& file) {
  vtkDataArray* point_ids = grid->GetPointData()->GetArray("id");
  if (!point_ids)
    return grid;
  const vtkIdType np = grid->GetNumberOfPoints(), nc = grid->GetNumberOfCells();
  vtkDataArray* cell_ids = grid->GetCellData()->GetArray("id");
  const bool mesh = cell_ids != nullptr;
  const std::vector<vtkIdType> point_from =
      places_by_id(point_ids, mesh, mesh ? "node" : "particle", file);
  std::vector<vtkIdType> cell_from;
  if (mesh) {
    cell_from = places_by_id(cell_ids, false, "element", file);
  } else {
    // Particles are vertices, one each: the cell of a particle follows it.
    for (vtkIdType k = 0; k < nc; ++k)
      SPHFEM_CHECK(grid->GetCellType(k) == VTK_VERTEX, file.string(), ": cell ", k,
                   " of a particle frame is not a vertex");
    cell_from = point_from;
  }
  if (identity(point_from, np) && identity(cell_from, nc))
    return grid;
  std::vector<vtkIdType> point_to(static_cast<std::size_t>(np));
  for (vtkIdType k = 0; k < np; ++k)
    point_to[static_cast<std::size_t>(k)] = static_cast<vtkIdType>(point_ids->GetComponent(k, 0));
  return reordered(grid, point_from, point_to, cell_from);
}

} // namespace

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& file) {
  SPHFEM_CHECK(fs::is_regular_file(file), file.string(), ": no such frame file");
  // A distributed run's frame: a .pvtu naming one piece per rank, read as one grid.
  vtkSmartPointer<vtkXMLReader> reader;
  if (file.extension() == ".pvtu")
    reader = vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New();
  else
    reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  vtkNew<FirstError> error;
  for (const unsigned long event : {vtkCommand::ErrorEvent, vtkCommand::WarningEvent}) {
    reader->AddObserver(event, error);
    reader->GetExecutive()->AddObserver(event, error);
  }
  reader->SetParserErrorObserver(error);
  reader->SetReaderErrorObserver(error);
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkSmartPointer<vtkUnstructuredGrid> grid =
      vtkUnstructuredGrid::SafeDownCast(reader->GetOutputDataObject(0));
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
  return in_model_order(grid, file);
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
