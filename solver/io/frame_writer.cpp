#include "solver/io/frame_writer.hpp"

#include "solver/core/error.hpp"
#include "solver/fem/nodal_stress.hpp"
#include "solver/io/atomic_file.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cstdio>
#include <sstream>

namespace sphfem {

namespace {

vtkSmartPointer<vtkDoubleArray> double_array(const char* name, int components, vtkIdType count) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(count);
  return a;
}

vtkSmartPointer<vtkIntArray> int_array(const char* name, const std::vector<int>& values) {
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    a->SetValue(static_cast<vtkIdType>(i), values[i]);
  return a;
}

} // namespace

struct FrameWriter::Grid {
  vtkSmartPointer<vtkUnstructuredGrid> grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkSmartPointer<vtkPoints> points = vtkSmartPointer<vtkPoints>::New();
  vtkSmartPointer<vtkDoubleArray> displacement, velocity, stress, von_mises, pressure, density;
};

FrameWriter::FrameWriter(const std::filesystem::path& out_dir, const Nodes& nodes,
                         const HexElements& e)
    : out_dir_(out_dir), grid_(std::make_unique<Grid>()) {
  std::filesystem::create_directories(out_dir_ / "frames");
  const vtkIdType n = nodes.size(), ne = e.size();
  auto& g = *grid_;
  g.points->SetDataTypeToDouble();
  g.points->SetNumberOfPoints(n);
  g.grid->SetPoints(g.points);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->AllocateExact(ne, 8 * ne);
  for (const Hex& hex : e.nodes_e) {
    const vtkIdType ids[8] = {hex[0], hex[1], hex[2], hex[3], hex[4], hex[5], hex[6], hex[7]};
    cells->InsertNextCell(8, ids);
  }
  g.grid->SetCells(VTK_HEXAHEDRON, cells);

  g.displacement = double_array("displacement", 3, n);
  g.velocity = double_array("velocity", 3, n);
  g.stress = double_array("stress", 6, ne);
  const char* components[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (int c = 0; c < 6; ++c)
    g.stress->SetComponentName(c, components[c]);
  g.von_mises = double_array("von_mises", 1, ne);
  g.pressure = double_array("pressure", 1, ne);
  g.density = double_array("density", 1, ne);
  auto* pd = g.grid->GetPointData();
  pd->AddArray(g.displacement);
  pd->AddArray(g.velocity);
  pd->AddArray(int_array("body_id", nodes.body_n));
  auto* cd = g.grid->GetCellData();
  for (auto& a : {g.stress, g.von_mises, g.pressure, g.density})
    cd->AddArray(a);
  cd->AddArray(int_array("body_id", e.body_e));
}

FrameWriter::~FrameWriter() = default;

void FrameWriter::write(double time, const Nodes& nodes, const HexElements& e) {
  auto& g = *grid_;
  for (Index i = 0; i < nodes.size(); ++i) {
    const Vec3& x = nodes.x_n[i];
    const Vec3 u = x - nodes.x0_n[i];
    g.points->SetPoint(i, x.x(), x.y(), x.z());
    g.displacement->SetTuple3(i, u.x(), u.y(), u.z());
    g.velocity->SetTuple3(i, nodes.v_n[i].x(), nodes.v_n[i].y(), nodes.v_n[i].z());
  }
  g.points->Modified();
  for (Index k = 0; k < e.size(); ++k) {
    const Mat3 s = e.S_e[k] - e.p_e[k] * Mat3::Identity();
    const double tensor[6] = {s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(0, 2)};
    g.stress->SetTuple(k, tensor);
    g.von_mises->SetValue(k, von_mises(s));
    g.pressure->SetValue(k, e.p_e[k]);
    g.density->SetValue(k, e.mass_e[k] / e.V_e[k]);
  }

  char name[32];
  std::snprintf(name, sizeof name, "fe_%06d.vtu", frame_count());
  const std::filesystem::path file = out_dir_ / "frames" / name;
  write_atomically(file, [&](const std::filesystem::path& temporary) {
    auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(g.grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToLZ4();
    SPHFEM_CHECK(writer->Write() == 1, file.string(), ": cannot write frame");
  });
  frames_.emplace_back(time, std::string("frames/") + name);
  write_collection();
}

void FrameWriter::write_collection() const {
  std::ostringstream xml;
  xml.precision(17);
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (const auto& [time, file] : frames_)
    xml << "    <DataSet timestep=\"" << time << "\" group=\"\" part=\"0\" file=\"" << file
        << "\"/>\n";
  xml << "  </Collection>\n</VTKFile>\n";
  write_text_atomically(out_dir_ / "results.pvd", xml.str());
}

} // namespace sphfem
