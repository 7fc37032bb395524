#include "solver/io/frame_writer.hpp"

#include "solver/core/error.hpp"
#include "solver/fem/nodal_stress.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/material/material_point.hpp"
#include "solver/parallel/ranks.hpp"

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

#include <algorithm>
#include <cstdio>
#include <exception>
#include <iostream>
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
// strain, damage, temperature (K), a failure flag (killed particles, eroded elements) and
// whether the point yields now (material/material_point.hpp: yielding).
struct FrameWriter::History {
  vtkSmartPointer<vtkDoubleArray> plastic_strain, damage, temperature;
  vtkSmartPointer<vtkIntArray> failed, yielding;

  History(const char* flag, vtkDataSetAttributes* into)
      : plastic_strain(double_array("plastic_strain", 1, 0)), damage(double_array("damage", 1, 0)),
        temperature(double_array("temperature", 1, 0)), failed(int_array(flag, {})),
        yielding(int_array("yielding", {})) {
    for (auto& a : {plastic_strain, damage, temperature})
      into->AddArray(a);
    into->AddArray(failed);
    into->AddArray(yielding);
  }
  void set(vtkIdType k, const Material& m, const Mat3& S, const MaterialPoint& point, int flag) {
    plastic_strain->SetValue(k, point.plastic_strain);
    damage->SetValue(k, point.damage);
    temperature->SetValue(k, point.temperature);
    failed->SetValue(k, flag);
    yielding->SetValue(k, sphfem::yielding(m, S, point));
  }
};

struct FrameWriter::Grid {
  vtkSmartPointer<vtkUnstructuredGrid> grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkSmartPointer<vtkPoints> points = vtkSmartPointer<vtkPoints>::New();
  vtkSmartPointer<vtkDoubleArray> displacement, velocity, stress, von_mises, pressure, density;
  vtkSmartPointer<vtkIntArray> body_n, id_n, body_e, id_e;
  std::unique_ptr<History> history;
  vtkSmartPointer<vtkUnsignedCharArray> ghost; // eroded elements hidden in ParaView
  std::vector<Index> elements, nodes;          // written, by index in the model
  bool shaped = false;
};

struct FrameWriter::Cloud {
  vtkSmartPointer<vtkUnstructuredGrid> grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkSmartPointer<vtkPoints> points = vtkSmartPointer<vtkPoints>::New();
  vtkSmartPointer<vtkDoubleArray> displacement, velocity, stress, von_mises, pressure, density, h,
      internal_energy, mass;
  vtkSmartPointer<vtkIntArray> neighbours, body_id, id;
  std::unique_ptr<History> history;
  vtkIdType count = -1; // particles the grid is shaped for
};

namespace {

vtkSmartPointer<vtkDoubleArray> stress_array() {
  auto a = double_array("stress", 6, 0);
  const char* components[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (int c = 0; c < 6; ++c)
    a->SetComponentName(c, components[c]);
  return a;
}

void set_stress(vtkDoubleArray* stress, vtkIdType k, const Mat3& s) {
  const double tensor[6] = {s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(0, 2)};
  stress->SetTuple(k, tensor);
}

// Every array of `data` sized for `count` tuples.
void size_arrays(vtkDataSetAttributes* data, vtkIdType count) {
  for (int a = 0; a < data->GetNumberOfArrays(); ++a)
    data->GetAbstractArray(a)->SetNumberOfTuples(count);
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

// The XML type name of an array's values.
const char* xml_type(vtkAbstractArray* a) {
  switch (a->GetDataType()) {
  case VTK_DOUBLE:
    return "Float64";
  case VTK_INT:
    return "Int32";
  case VTK_UNSIGNED_CHAR:
    return "UInt8";
  default:
    throw Error(detail::concat("frame array ", a->GetName(), ": no XML type for VTK type ",
                               a->GetDataType()));
  }
}

void declare_arrays(std::ostringstream& xml, const char* tag, vtkDataSetAttributes* data) {
  xml << "    <" << tag << ">\n";
  for (int k = 0; k < data->GetNumberOfArrays(); ++k) {
    vtkAbstractArray* a = data->GetAbstractArray(k);
    xml << "      <PDataArray type=\"" << xml_type(a) << "\" Name=\"" << a->GetName()
        << "\" NumberOfComponents=\"" << a->GetNumberOfComponents() << '"';
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
      if (a->HasAComponentName() && a->GetComponentName(c))
        xml << " ComponentName" << c << "=\"" << a->GetComponentName(c) << '"';
    xml << "/>\n";
  }
  xml << "    </" << tag << ">\n";
}

// The parallel file of a frame's part: the arrays every piece has (those of `grid`, this
// rank's piece) and the pieces `stem`_0.vtu … `stem`_{ranks−1}.vtu beside it.
std::string pvtu_text(vtkUnstructuredGrid* grid, const std::string& stem, int ranks) {
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
      << "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  declare_arrays(xml, "PPointData", grid->GetPointData());
  declare_arrays(xml, "PCellData", grid->GetCellData());
  xml << "    <PPoints>\n"
      << "      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
      << "    </PPoints>\n";
  for (int r = 0; r < ranks; ++r)
    xml << "    <Piece Source=\"" << stem << '_' << r << ".vtu\"/>\n";
  xml << "  </PUnstructuredGrid>\n</VTKFile>\n";
  return xml.str();
}

} // namespace

FrameWriter::FrameWriter(const std::filesystem::path& out_dir, const HexElements& e,
                         const Particles& particles, std::vector<Material> materials)
    : out_dir_(out_dir), materials_(std::move(materials)) {
  std::filesystem::create_directories(out_dir_ / "frames");
  if (particles.size() > 0 || particles.model_real > 0) { // a distributed rank may hold none
    cloud_ = std::make_unique<Cloud>();
    auto& c = *cloud_;
    c.points->SetDataTypeToDouble();
    c.grid->SetPoints(c.points);
    c.displacement = double_array("displacement", 3, 0);
    c.velocity = double_array("velocity", 3, 0);
    c.stress = stress_array();
    c.von_mises = double_array("von_mises", 1, 0);
    c.pressure = double_array("pressure", 1, 0);
    c.density = double_array("density", 1, 0);
    c.h = double_array("h", 1, 0);
    c.internal_energy = double_array("internal_energy", 1, 0);
    c.mass = double_array("mass", 1, 0);
    c.neighbours = int_array("neighbours", {});
    c.body_id = int_array("body_id", {});
    c.id = int_array("id", {});
    auto* pd = c.grid->GetPointData();
    for (auto& a : {c.displacement, c.velocity, c.stress, c.von_mises, c.pressure, c.density, c.h,
                    c.internal_energy, c.mass})
      pd->AddArray(a);
    for (auto& a : {c.neighbours, c.body_id, c.id})
      pd->AddArray(a);
    if (particles.inelastic)
      c.history = std::make_unique<History>("killed", pd);
  }
  if (e.size() == 0)
    return;
  grid_ = std::make_unique<Grid>();
  auto& g = *grid_;
  g.points->SetDataTypeToDouble();
  g.grid->SetPoints(g.points);
  g.displacement = double_array("displacement", 3, 0);
  g.velocity = double_array("velocity", 3, 0);
  g.body_n = int_array("body_id", {});
  g.id_n = int_array("id", {});
  g.stress = stress_array();
  g.von_mises = double_array("von_mises", 1, 0);
  g.pressure = double_array("pressure", 1, 0);
  g.density = double_array("density", 1, 0);
  g.body_e = int_array("body_id", {});
  g.id_e = int_array("id", {});
  auto* pd = g.grid->GetPointData();
  for (auto& a : {g.displacement, g.velocity})
    pd->AddArray(a);
  for (auto& a : {g.body_n, g.id_n})
    pd->AddArray(a);
  auto* cd = g.grid->GetCellData();
  for (auto& a : {g.stress, g.von_mises, g.pressure, g.density})
    cd->AddArray(a);
  for (auto& a : {g.body_e, g.id_e})
    cd->AddArray(a);
  if (e.inelastic) {
    g.history = std::make_unique<History>("eroded", cd);
    g.ghost = vtkSmartPointer<vtkUnsignedCharArray>::New();
    g.ghost->SetName(vtkDataSetAttributes::GhostArrayName());
    cd->AddArray(g.ghost);
  }
}

FrameWriter::~FrameWriter() = default;

void FrameWriter::write(double time, const Nodes& nodes, const HexElements& e,
                        const Particles& particles, const FramePiece* piece) {
  if (!piece) {
    write_parts(nodes, e, particles, nullptr);
  } else {
    // Every rank learns whether all pieces were written before the parallel files name them.
    std::exception_ptr failed;
    try {
      write_parts(nodes, e, particles, piece);
    } catch (const Error& error) {
      failed = std::current_exception();
      // Rank 0 alone speaks for the run (app/commands.cpp): another rank says its own error, in
      // one write so that the ranks' lines do not interleave.
      if (piece->rank != 0)
        std::cerr << detail::concat("sphfem: error on MPI rank ", piece->rank, ": ", error.what(),
                                    "\n");
    }
    if (ranks::max(failed ? 1 : 0) != 0) {
      if (failed)
        std::rethrow_exception(failed);
      throw Error(detail::concat("frame ", frame_count_, ": another MPI rank could not write its ",
                                 "piece (its message names the file); the frame is not listed"));
    }
  }
  // Each part's file in the collection: its .vtu, or the .pvtu naming the ranks' pieces.
  const auto list = [&](int part, const char* prefix, vtkUnstructuredGrid* grid) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "%s_%06d", prefix, frame_count_);
    const std::string file = std::string(stem) + (piece ? ".pvtu" : ".vtu");
    if (piece && piece->rank == 0)
      write_text_atomically(out_dir_ / "frames" / file, pvtu_text(grid, stem, piece->ranks));
    entries_.push_back({time, part, "frames/" + file});
  };
  if (grid_)
    list(0, "fe", grid_->grid);
  if (cloud_)
    list(1, "sph", cloud_->grid);
  ++frame_count_;
  if (!piece || piece->rank == 0)
    write_collection();
}

void FrameWriter::write_parts(const Nodes& nodes, const HexElements& e, const Particles& particles,
                              const FramePiece* piece) {
  char name[40];
  const auto file_name = [&](const char* part) {
    if (piece)
      std::snprintf(name, sizeof name, "%s_%06d_%d.vtu", part, frame_count_, piece->rank);
    else
      std::snprintf(name, sizeof name, "%s_%06d.vtu", part, frame_count_);
    return out_dir_ / "frames" / name;
  };
  if (grid_) {
    auto& g = *grid_;
    std::vector<Index> elements;
    if (piece)
      elements.assign(piece->elements.begin(), piece->elements.end());
    else
      for (Index k = 0; k < e.size(); ++k)
        elements.push_back(k);
    if (!g.shaped || elements != g.elements) {
      // The cells and the nodes they hold, numbered in the file in model order.
      g.elements = std::move(elements);
      g.nodes.clear();
      if (piece) {
        for (Index k : g.elements)
          g.nodes.insert(g.nodes.end(), e.nodes_e[k].begin(), e.nodes_e[k].end());
        std::sort(g.nodes.begin(), g.nodes.end());
        g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
      } else {
        for (Index i = 0; i < nodes.size(); ++i)
          g.nodes.push_back(i);
      }
      std::vector<vtkIdType> local(static_cast<std::size_t>(nodes.size()), -1);
      for (std::size_t a = 0; a < g.nodes.size(); ++a)
        local[static_cast<std::size_t>(g.nodes[a])] = static_cast<vtkIdType>(a);
      const auto nn = static_cast<vtkIdType>(g.nodes.size());
      const auto ne = static_cast<vtkIdType>(g.elements.size());
      auto cells = vtkSmartPointer<vtkCellArray>::New();
      cells->AllocateExact(ne, 8 * ne);
      for (Index k : g.elements) {
        vtkIdType ids[8];
        for (int a = 0; a < 8; ++a)
          ids[a] = local[static_cast<std::size_t>(e.nodes_e[k][a])];
        cells->InsertNextCell(8, ids);
      }
      g.points->SetNumberOfPoints(nn);
      size_arrays(g.grid->GetPointData(), nn);
      size_arrays(g.grid->GetCellData(), ne);
      g.grid->SetCells(VTK_HEXAHEDRON, cells);
      for (vtkIdType a = 0; a < nn; ++a) {
        g.body_n->SetValue(a, nodes.body_n[g.nodes[a]]);
        g.id_n->SetValue(a, static_cast<int>(g.nodes[a]));
      }
      for (vtkIdType a = 0; a < ne; ++a) {
        g.body_e->SetValue(a, e.body_e[g.elements[a]]);
        g.id_e->SetValue(a, static_cast<int>(g.elements[a]));
      }
      g.shaped = true;
    }
    for (std::size_t a = 0; a < g.nodes.size(); ++a) {
      const Index i = g.nodes[a];
      const auto k = static_cast<vtkIdType>(a);
      const Vec3& x = nodes.x_n[i];
      const Vec3 u = x - nodes.x0_n[i];
      g.points->SetPoint(k, x.x(), x.y(), x.z());
      g.displacement->SetTuple3(k, u.x(), u.y(), u.z());
      g.velocity->SetTuple3(k, nodes.v_n[i].x(), nodes.v_n[i].y(), nodes.v_n[i].z());
    }
    g.points->Modified();
    for (std::size_t a = 0; a < g.elements.size(); ++a) {
      const Index j = g.elements[a], slot = e.slot(j);
      const auto k = static_cast<vtkIdType>(a);
      const Mat3 s = e.S_e[slot] - e.p_e[slot] * Mat3::Identity();
      set_stress(g.stress, k, s);
      g.von_mises->SetValue(k, von_mises(s));
      g.pressure->SetValue(k, e.p_e[slot]);
      g.density->SetValue(k, e.mass_e[j] / e.V_e[slot]);
      if (g.history) {
        g.history->set(k, materials_[e.material_e[j]], e.S_e[slot], e.point_e[slot], e.eroded_e[j]);
        g.ghost->SetValue(k, e.eroded_e[j] ? vtkDataSetAttributes::HIDDENCELL : 0);
      }
    }
    write_vtu(file_name("fe"), g.grid);
  }
  if (cloud_) {
    auto& c = *cloud_;
    const auto& p = particles;
    std::vector<Index> all;
    if (!piece)
      for (Index i = 0; i < p.size(); ++i)
        all.push_back(i);
    const std::span<const Index> rows = piece ? piece->particle_rows : std::span<const Index>(all);
    const auto n = static_cast<vtkIdType>(rows.size());
    if (n != c.count) {
      auto cells = vtkSmartPointer<vtkCellArray>::New();
      cells->AllocateExact(n, n);
      for (vtkIdType i = 0; i < n; ++i)
        cells->InsertNextCell(1, &i);
      c.points->SetNumberOfPoints(n);
      size_arrays(c.grid->GetPointData(), n);
      c.grid->SetCells(VTK_VERTEX, cells);
      c.count = n;
    }
    for (vtkIdType k = 0; k < n; ++k) {
      const Index i = rows[static_cast<std::size_t>(k)];
      const Vec3& x = p.x_p[i];
      const Vec3 u = x - p.x0_p[i];
      c.points->SetPoint(k, x.x(), x.y(), x.z());
      c.displacement->SetTuple3(k, u.x(), u.y(), u.z());
      c.velocity->SetTuple3(k, p.v_p[i].x(), p.v_p[i].y(), p.v_p[i].z());
      const Mat3 s = p.S_p[i] - p.p_p[i] * Mat3::Identity();
      set_stress(c.stress, k, s);
      c.von_mises->SetValue(k, von_mises(s));
      c.pressure->SetValue(k, p.p_p[i]);
      c.density->SetValue(k, p.rho_p[i]);
      c.h->SetValue(k, p.h_p[i]);
      c.internal_energy->SetValue(k, p.e_p[i] / p.m_p[i]);
      c.mass->SetValue(k, p.m_p[i]);
      c.neighbours->SetValue(k, p.neighbours_p[i]);
      c.body_id->SetValue(k, p.body_p[i]);
      c.id->SetValue(k, static_cast<int>(p.id_p[i]));
      if (c.history)
        c.history->set(k, materials_[p.material_p[i]], p.S_p[i], p.point_p[i],
                       p.kill_p[i] != Kill::None);
    }
    c.points->Modified();
    write_vtu(file_name("sph"), c.grid);
  }
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
