// Builds a vtkUnstructuredGrid from the Model (gmsh hex order is VTK_HEXAHEDRON's order) and
// writes it with vtkXMLUnstructuredGridWriter. Verified by tests/io/model_h5_test.cpp.
#include "solver/io/model_vtu.hpp"

#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkExecutive.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace sphfem {
namespace {

namespace fs = std::filesystem;

vtkNew<vtkIntArray> int_array(const std::string& name, const std::vector<int>& values) {
  vtkNew<vtkIntArray> array;
  array->SetName(name.c_str());
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    array->SetValue(static_cast<vtkIdType>(i), values[i]);
  return array;
}

vtkNew<vtkUnstructuredGrid> make_grid(const Model& m) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(m.node_count());
  for (Index i = 0; i < m.node_count(); ++i)
    points->SetPoint(i, m.x_n[i].data());

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(m.element_count() + 1);
  connectivity->SetNumberOfValues(8 * static_cast<vtkIdType>(m.element_count()));
  for (Index e = 0; e <= m.element_count(); ++e)
    offsets->SetValue(e, 8 * static_cast<vtkIdType>(e));
  for (Index e = 0; e < m.element_count(); ++e)
    for (int i = 0; i < 8; ++i)
      connectivity->SetValue(8 * static_cast<vtkIdType>(e) + i, m.hex_e[e][i]);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);

  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->SetCells(VTK_HEXAHEDRON, cells);
  grid->GetPointData()->AddArray(int_array("body_id", m.body_n));
  grid->GetCellData()->AddArray(int_array("body_id", m.body_e));
  for (const auto& [name, nodes] : m.node_sets) {
    std::vector<int> flag(m.x_n.size(), 0);
    for (const Index i : nodes)
      flag.at(static_cast<std::size_t>(i)) = 1;
    grid->GetPointData()->AddArray(int_array("set:" + name, flag));
  }
  return grid;
}

// Keeps the text of VTK's first error message ("ERROR: In <file>, line <n>\n<class> (<ptr>):
// <text>") instead of letting VTK print it.
void keep_error(vtkObject*, unsigned long, void* client_data, void* call_data) {
  auto& first = *static_cast<std::string*>(client_data);
  if (call_data == nullptr || !first.empty())
    return;
  const std::string message = static_cast<const char*>(call_data);
  const std::size_t start = message.find("): ");
  std::string text = start == std::string::npos ? message : message.substr(start + 3);
  text.erase(text.find_last_not_of(" \n") + 1);
  first = text;
}

} // namespace

void write_model_vtu(const Model& m, const fs::path& file) {
  const vtkNew<vtkUnstructuredGrid> grid = make_grid(m);
  std::string vtk_error;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetCallback(keep_error);
  on_error->SetClientData(&vtk_error);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->AddObserver(vtkCommand::ErrorEvent, on_error);
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, on_error);
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToLZ4();
  writer->SetHeaderTypeToUInt64(); // block sizes beyond 4 GiB
  try {
    write_atomically(file, [&](const fs::path& temporary) {
      writer->SetFileName(temporary.string().c_str());
      SPHFEM_CHECK(writer->Write() == 1 && writer->GetErrorCode() == 0,
                   vtk_error.empty() ? "the VTK writer failed" : vtk_error);
    });
  } catch (const Error& e) {
    throw Error(detail::concat("cannot write model file ", file, ": ", e.what()));
  }
}

} // namespace sphfem
