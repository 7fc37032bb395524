// Builds vtkUnstructuredGrids from the Model (hexahedra: gmsh hex order is VTK_HEXAHEDRON's
// order; particles: vertex cells) and writes them with vtkXMLUnstructuredGridWriter. Verified by
// tests/io/model_h5_test.cpp.
#include "solver/io/model_vtu.hpp"

#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <functional>
#include <system_error>

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

vtkNew<vtkDoubleArray> double_array(const std::string& name, const std::vector<double>& values) {
  vtkNew<vtkDoubleArray> array;
  array->SetName(name.c_str());
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    array->SetValue(static_cast<vtkIdType>(i), values[i]);
  return array;
}

vtkNew<vtkPoints> make_points(const std::vector<Vec3>& x) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), x[i].data());
  return points;
}

// Cells of `size` points each, the points in order: cell c holds points size·c … size·c + size−1
// of `connectivity`.
vtkNew<vtkCellArray> make_cells(vtkIdType cells, int size,
                                const std::function<vtkIdType(vtkIdType)>& connectivity) {
  vtkNew<vtkIdTypeArray> offsets, points;
  offsets->SetNumberOfValues(cells + 1);
  points->SetNumberOfValues(size * cells);
  for (vtkIdType c = 0; c <= cells; ++c)
    offsets->SetValue(c, size * c);
  for (vtkIdType i = 0; i < size * cells; ++i)
    points->SetValue(i, connectivity(i));
  vtkNew<vtkCellArray> array;
  array->SetData(offsets, points);
  return array;
}

vtkNew<vtkUnstructuredGrid> make_grid(const Model& m) {
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(make_points(m.x_n));
  grid->SetCells(VTK_HEXAHEDRON, make_cells(m.element_count(), 8, [&m](vtkIdType i) {
                   return static_cast<vtkIdType>(m.hex_e[i / 8][i % 8]);
                 }));
  grid->GetPointData()->AddArray(int_array("body_id", m.body_n));
  std::vector<int> background(m.x_n.size(), 0);
  for (const Index i : m.background_nodes)
    background.at(static_cast<std::size_t>(i)) = 1;
  grid->GetPointData()->AddArray(int_array("background", background));
  grid->GetCellData()->AddArray(int_array("body_id", m.body_e));
  for (const auto& [name, nodes] : m.node_sets) {
    std::vector<int> flag(m.x_n.size(), 0);
    for (const Index i : nodes)
      flag.at(static_cast<std::size_t>(i)) = 1;
    grid->GetPointData()->AddArray(int_array("set:" + name, flag));
  }
  return grid;
}

// The particle arrays must all have one entry per particle, the particle faces' indices in range.
vtkNew<vtkUnstructuredGrid> make_particle_grid(const Model& m) {
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(make_points(m.x_p));
  grid->SetCells(VTK_VERTEX, make_cells(m.particle_count(), 1, [](vtkIdType i) { return i; }));
  grid->GetPointData()->AddArray(int_array("body_id", m.body_p));
  grid->GetPointData()->AddArray(double_array("mass", m.m_p));
  grid->GetPointData()->AddArray(double_array("h", m.h_p));
  grid->GetPointData()->AddArray(double_array("density", m.rho_p));
  grid->GetPointData()->AddArray(int_array(
      "interface", m.interface_p.empty() ? std::vector<int>(m.x_p.size(), 0) : m.interface_p));
  for (const auto& [name, face] : m.particle_faces) {
    std::vector<int> flag(m.x_p.size(), 0);
    for (const Index i : face.particles)
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

// Appended raw binary, LZ4, via a temporary file; VTK's errors become one sphfem::Error.
void write_grid(vtkUnstructuredGrid* grid, const fs::path& file) {
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

void add_fields(vtkUnstructuredGrid* grid, const VtuIntFields& extra, const fs::path& file) {
  const auto add = [&](const auto& fields, vtkIdType count, vtkDataSetAttributes* to,
                       const char* what) {
    for (const auto& [name, values] : fields) {
      if (static_cast<vtkIdType>(values.size()) != count)
        throw Error(detail::concat("cannot write model file ", file, ": array '", name, "' has ",
                                   values.size(), " values for ", count, " ", what));
      to->AddArray(int_array(name, values));
    }
  };
  add(extra.cells, grid->GetNumberOfCells(), grid->GetCellData(), "cells");
  add(extra.points, grid->GetNumberOfPoints(), grid->GetPointData(), "points");
}

} // namespace

void write_model_vtu(const Model& m, const fs::path& file, const VtuIntFields& extra) {
  auto grid = make_grid(m);
  add_fields(grid, extra, file);
  write_grid(grid, file);
}

void write_particles_vtu(const Model& m, const fs::path& file, const VtuIntFields& extra) {
  if (m.particle_count() == 0) {
    std::error_code status;
    if (fs::remove(file, status); status)
      throw Error(
          detail::concat("cannot remove the stale particle file ", file, ": ", status.message()));
    return;
  }
  const std::size_t p = m.x_p.size();
  if (m.m_p.size() != p || m.rho_p.size() != p || m.h_p.size() != p || m.body_p.size() != p ||
      (!m.interface_p.empty() && m.interface_p.size() != p))
    throw Error(detail::concat("cannot write model file ", file,
                               ": particle arrays do not match the ", p, " particle positions"));
  for (const auto& [name, face] : m.particle_faces)
    for (const Index i : face.particles)
      if (i < 0 || static_cast<std::size_t>(i) >= p)
        throw Error(detail::concat("cannot write model file ", file, ": particle face '", name,
                                   "' holds index ", i, " outside [0, ", p, ")"));
  auto grid = make_particle_grid(m);
  add_fields(grid, extra, file);
  write_grid(grid, file);
}

} // namespace sphfem
