#include "solver/io/frame_writer.hpp"

#include "solver/core/error.hpp"
#include "solver/fem/nodal_stress.hpp"
#include "solver/io/atomic_file.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
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

// The material history of inelastic materials (absent from runs without one): plastic
// strain, damage, temperature (K) and a failure flag (killed particles, eroded elements).
struct FrameWriter::History {
  vtkSmartPointer<vtkDoubleArray> plastic_strain, damage, temperature;
  vtkSmartPointer<vtkIntArray> failed;

  History(vtkIdType n, const char* flag, vtkDataSetAttributes* into)
      : plastic_strain(double_array("plastic_strain", 1, n)), damage(double_array("damage", 1, n)),
        temperature(double_array("temperature", 1, n)),
        failed(int_array(flag, std::vector<int>(static_cast<std::size_t>(n), 0))) {
    for (auto& a : {plastic_strain, damage, temperature})
      into->AddArray(a);
    into->AddArray(failed);
  }
  void set(vtkIdType k, const MaterialPoint& point, int flag) {
    plastic_strain->SetValue(k, point.plastic_strain);
    damage->SetValue(k, point.damage);
    temperature->SetValue(k, point.temperature);
    failed->SetValue(k, flag);
  }
};

struct FrameWriter::Grid {
  vtkSmartPointer<vtkUnstructuredGrid> grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkSmartPointer<vtkPoints> points = vtkSmartPointer<vtkPoints>::New();
  vtkSmartPointer<vtkDoubleArray> displacement, velocity, stress, von_mises, pressure, density;
  std::unique_ptr<History> history;
  vtkSmartPointer<vtkUnsignedCharArray> ghost; // eroded elements hidden in ParaView
};

struct FrameWriter::Cloud {
  vtkSmartPointer<vtkUnstructuredGrid> grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkSmartPointer<vtkPoints> points = vtkSmartPointer<vtkPoints>::New();
  vtkSmartPointer<vtkDoubleArray> displacement, velocity, stress, von_mises, pressure, density, h,
      internal_energy, mass;
  vtkSmartPointer<vtkIntArray> neighbours, body_id, id;
  std::unique_ptr<History> history;
};

namespace {

vtkSmartPointer<vtkDoubleArray> stress_array(vtkIdType count) {
  auto a = double_array("stress", 6, count);
  const char* components[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (int c = 0; c < 6; ++c)
    a->SetComponentName(c, components[c]);
  return a;
}

void set_stress(vtkDoubleArray* stress, vtkIdType k, const Mat3& s) {
  const double tensor[6] = {s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(0, 2)};
  stress->SetTuple(k, tensor);
}

// The arrays were filled in place (SetValue, SetTuple): marked modified, so that the ranges the
// writer puts in the file's header are this frame's and not those cached at the first frame.
void write_vtu(const std::filesystem::path& file, vtkUnstructuredGrid* grid) {
  for (vtkDataSetAttributes* data : {static_cast<vtkDataSetAttributes*>(grid->GetPointData()),
                                     static_cast<vtkDataSetAttributes*>(grid->GetCellData())})
    for (int a = 0; a < data->GetNumberOfArrays(); ++a)
      data->GetAbstractArray(a)->Modified();
  write_atomically(file, [&](const std::filesystem::path& temporary) {
    auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToLZ4();
    SPHFEM_CHECK(writer->Write() == 1, file.string(), ": cannot write frame");
  });
}

} // namespace

FrameWriter::FrameWriter(const std::filesystem::path& out_dir, const Nodes& nodes,
                         const HexElements& e, const Particles& particles)
    : out_dir_(out_dir) {
  std::filesystem::create_directories(out_dir_ / "frames");
  if (particles.size() > 0) {
    cloud_ = std::make_unique<Cloud>();
    auto& c = *cloud_;
    const vtkIdType n = particles.size();
    c.points->SetDataTypeToDouble();
    c.points->SetNumberOfPoints(n);
    c.grid->SetPoints(c.points);
    auto cells = vtkSmartPointer<vtkCellArray>::New();
    cells->AllocateExact(n, n);
    for (vtkIdType i = 0; i < n; ++i)
      cells->InsertNextCell(1, &i);
    c.grid->SetCells(VTK_VERTEX, cells);
    c.displacement = double_array("displacement", 3, n);
    c.velocity = double_array("velocity", 3, n);
    c.stress = stress_array(n);
    c.von_mises = double_array("von_mises", 1, n);
    c.pressure = double_array("pressure", 1, n);
    c.density = double_array("density", 1, n);
    c.h = double_array("h", 1, n);
    c.internal_energy = double_array("internal_energy", 1, n);
    c.mass = double_array("mass", 1, n);
    c.neighbours = int_array("neighbours", particles.neighbours_p);
    c.body_id = int_array("body_id", particles.body_p);
    c.id = int_array("id", std::vector<int>(particles.id_p.begin(), particles.id_p.end()));
    auto* pd = c.grid->GetPointData();
    for (auto& a : {c.displacement, c.velocity, c.stress, c.von_mises, c.pressure, c.density, c.h,
                    c.internal_energy, c.mass})
      pd->AddArray(a);
    for (auto& a : {c.neighbours, c.body_id, c.id})
      pd->AddArray(a);
    if (particles.inelastic)
      c.history = std::make_unique<History>(n, "killed", pd);
  }
  if (e.size() == 0)
    return;
  grid_ = std::make_unique<Grid>();
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
  g.stress = stress_array(ne);
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
  if (e.inelastic) {
    g.history = std::make_unique<History>(ne, "eroded", cd);
    g.ghost = vtkSmartPointer<vtkUnsignedCharArray>::New();
    g.ghost->SetName(vtkDataSetAttributes::GhostArrayName());
    g.ghost->SetNumberOfTuples(ne);
    cd->AddArray(g.ghost);
  }
}

FrameWriter::~FrameWriter() = default;

void FrameWriter::write(double time, const Nodes& nodes, const HexElements& e,
                        const Particles& particles) {
  char name[32];
  if (grid_) {
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
      set_stress(g.stress, k, s);
      g.von_mises->SetValue(k, von_mises(s));
      g.pressure->SetValue(k, e.p_e[k]);
      g.density->SetValue(k, e.mass_e[k] / e.V_e[k]);
      if (g.history) {
        g.history->set(k, e.point_e[k], e.eroded_e[k]);
        g.ghost->SetValue(k, e.eroded_e[k] ? vtkDataSetAttributes::HIDDENCELL : 0);
      }
    }
    std::snprintf(name, sizeof name, "fe_%06d.vtu", frame_count_);
    write_vtu(out_dir_ / "frames" / name, g.grid);
    entries_.push_back({time, 0, std::string("frames/") + name});
  }
  if (cloud_) {
    auto& c = *cloud_;
    const auto& p = particles;
    for (Index i = 0; i < p.size(); ++i) {
      const Vec3& x = p.x_p[i];
      const Vec3 u = x - p.x0_p[i];
      c.points->SetPoint(i, x.x(), x.y(), x.z());
      c.displacement->SetTuple3(i, u.x(), u.y(), u.z());
      c.velocity->SetTuple3(i, p.v_p[i].x(), p.v_p[i].y(), p.v_p[i].z());
      const Mat3 s = p.S_p[i] - p.p_p[i] * Mat3::Identity();
      set_stress(c.stress, i, s);
      c.von_mises->SetValue(i, von_mises(s));
      c.pressure->SetValue(i, p.p_p[i]);
      c.density->SetValue(i, p.rho_p[i]);
      c.h->SetValue(i, p.h_p[i]);
      c.internal_energy->SetValue(i, p.e_p[i] / p.m_p[i]);
      c.mass->SetValue(i, p.m_p[i]);
      c.neighbours->SetValue(i, p.neighbours_p[i]);
      c.body_id->SetValue(i, p.body_p[i]);
      c.id->SetValue(i, p.id_p[i]);
      if (c.history)
        c.history->set(i, p.point_p[i], p.kill_p[i] != Kill::None);
    }
    c.points->Modified();
    std::snprintf(name, sizeof name, "sph_%06d.vtu", frame_count_);
    write_vtu(out_dir_ / "frames" / name, c.grid);
    entries_.push_back({time, 1, std::string("frames/") + name});
  }
  ++frame_count_;
  write_collection();
}

void FrameWriter::persist(StateArchive& a) {
  std::ostringstream listed; // one frame file per line: time, part, file
  listed.precision(17);
  for (const auto& entry : entries_)
    listed << entry.time << ' ' << entry.part << ' ' << entry.file << '\n';
  std::string text = listed.str();
  a.text("run/frames", text);
  a.value("run/frame_count", frame_count_);
  if (!a.reading())
    return;
  entries_.clear();
  std::istringstream in(text);
  for (Entry entry; in >> entry.time >> entry.part >> entry.file;)
    entries_.push_back(entry);
  SPHFEM_CHECK(in.eof(), "checkpoint: unreadable frame list");
}

void FrameWriter::write_collection() const {
  std::ostringstream xml;
  xml.precision(17);
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (const auto& entry : entries_)
    xml << "    <DataSet timestep=\"" << entry.time << "\" group=\"\" part=\"" << entry.part
        << "\" file=\"" << entry.file << "\"/>\n";
  xml << "  </Collection>\n</VTKFile>\n";
  write_text_atomically(out_dir_ / "results.pvd", xml.str());
}

} // namespace sphfem
