// `sphfem post section` on inputs with known answers: frames written here with VTK's writer
// (an undeformed FE box, a disk of particles, a plate bent into a paraboloid) and a real tiny
// run through the command. Checks the section's shape (shoelace area, equivalent radius), the
// deflection profile, the files and the one-line errors, for bad options and for bad run files
// (results.pvd and the frames it lists).
#include "png_pixels.hpp"
#include "tests/support/command.hpp"

#include "post/section.hpp"
#include "solver/core/error.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
using sphfem::Vec3;
using sphfem::post::SectionOptions;
using sphfem::post::write_section;
using sphfem::test::Result;
using sphfem::test::run_sphfem;
using sphfem::test::Scratch;
using sphfem::test::slurp;

namespace {

void write_grid(const fs::path& file, vtkUnstructuredGrid* grid) {
  fs::create_directories(file.parent_path());
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputData(grid);
  ASSERT_EQ(writer->Write(), 1) << file;
}

vtkNew<vtkDoubleArray> vectors(const char* name, const std::vector<Vec3>& v) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(3);
  for (const auto& x : v)
    a->InsertNextTuple3(x.x(), x.y(), x.z());
  return a;
}

vtkNew<vtkDoubleArray> scalars(const char* name, std::size_t n, double value) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(vtkIdType(n));
  a->FillValue(value);
  return a;
}

vtkNew<vtkIntArray> zeros(const char* name, std::size_t n) {
  vtkNew<vtkIntArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(vtkIdType(n));
  a->FillValue(0);
  return a;
}

// results.pvd of one frame at t = 10 µs with the given parts.
void write_pvd(const fs::path& run, bool fe, bool sph) {
  std::ofstream out(run / "results.pvd");
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
      << "  <Collection>\n";
  if (fe)
    out << "    <DataSet timestep=\"1e-05\" group=\"\" part=\"0\" "
           "file=\"frames/fe_000000.vtu\"/>\n";
  if (sph)
    out << "    <DataSet timestep=\"1e-05\" group=\"\" part=\"1\" "
           "file=\"frames/sph_000000.vtu\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
}

// The box [lo, hi] in n[0] × n[1] × n[2] hexahedra (one body, id 0), nodes moved by u(x0).
void write_fe_box(const fs::path& run, Vec3 lo, Vec3 hi, std::array<int, 3> n,
                  const std::function<Vec3(const Vec3&)>& u, std::vector<vtkIdType> eroded = {}) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble(); // as frames are written
  std::vector<Vec3> disp;
  auto id = [&](int i, int j, int k) { return vtkIdType((k * (n[1] + 1) + j) * (n[0] + 1) + i); };
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        const Vec3 x0 =
            lo + (hi - lo).cwiseProduct(Vec3(double(i) / n[0], double(j) / n[1], double(k) / n[2]));
        disp.push_back(u(x0));
        const Vec3 x = x0 + disp.back();
        points->InsertNextPoint(x.data());
      }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  vtkNew<vtkCellArray> cells;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const vtkIdType ids[8] = {
            id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
            id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        cells->InsertNextCell(8, ids);
      }
  grid->SetCells(VTK_HEXAHEDRON, cells);
  grid->GetPointData()->AddArray(vectors("displacement", disp));
  grid->GetPointData()->AddArray(zeros("body_id", disp.size()));
  grid->GetCellData()->AddArray(zeros("body_id", std::size_t(n[0]) * n[1] * n[2]));
  if (!eroded.empty()) { // marked as the frame writer does: hidden ghost cells
    vtkNew<vtkUnsignedCharArray> ghost;
    ghost->SetName(vtkDataSetAttributes::GhostArrayName());
    ghost->SetNumberOfTuples(grid->GetNumberOfCells());
    ghost->FillValue(0);
    for (vtkIdType k : eroded)
      ghost->SetValue(k, vtkDataSetAttributes::HIDDENCELL);
    grid->GetCellData()->AddArray(ghost);
  }
  write_grid(run / "frames" / "fe_000000.vtu", grid);
}

struct Row {
  std::string body, part;
  int polyline;
  double u, w;
};

std::vector<Row> read_section_csv(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Row> rows;
  std::string line;
  std::getline(in, line); // comment
  std::getline(in, line);
  EXPECT_EQ(line, "body,part,polyline,u_m,w_m,x_m,y_m,z_m");
  while (std::getline(in, line)) {
    std::stringstream s(line);
    Row r;
    std::string cell;
    std::getline(s, r.body, ',');
    std::getline(s, r.part, ',');
    std::getline(s, cell, ',');
    r.polyline = std::stoi(cell);
    std::getline(s, cell, ',');
    r.u = std::stod(cell);
    std::getline(s, cell, ',');
    r.w = std::stod(cell);
    rows.push_back(r);
  }
  return rows;
}

// Polylines by (part, number), each as (u, w) vertices.
std::map<std::pair<std::string, int>, std::vector<std::array<double, 2>>>
polylines(const std::vector<Row>& rows) {
  std::map<std::pair<std::string, int>, std::vector<std::array<double, 2>>> out;
  for (const auto& r : rows)
    out[{r.part, r.polyline}].push_back({r.u, r.w});
  return out;
}

double shoelace(const std::vector<std::array<double, 2>>& p) { // |area| of the closed polygon
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& q = p[i];
    const auto& r = p[(i + 1) % p.size()];
    a += q[0] * r[1] - r[0] * q[1];
  }
  return std::abs(a) / 2;
}

} // namespace

TEST(Section, UndeformedBoxGivesTheExactRectangle) {
  const Scratch scratch("section_box");
  const fs::path& run = scratch.dir;
  // 40 × 30 × 20 mm in 4 × 3 × 2 hexahedra; the mid plane y = 15 mm lies inside a layer, and
  // the plane x = 20 mm runs through a layer of nodes (the harder case for a cutter).
  write_fe_box(run, {0, 0, 0}, {0.04, 0.03, 0.02}, {4, 3, 2},
               [](const Vec3&) { return Vec3::Zero(); });
  write_pvd(run, true, false);
  for (const auto& [point, normal, area] :
       {std::tuple{Vec3(0.02, 0.015, 0.01), Vec3(0, 2, 0), 0.04 * 0.02},
        std::tuple{Vec3(0.02, 0.015, 0.01), Vec3(1, 0, 0), 0.03 * 0.02}}) {
    SectionOptions o;
    o.run = run;
    o.point = point;
    o.normal = normal;
    const auto r = write_section(o);
    EXPECT_NEAR(r.time, 1e-5, 1e-18);
    const auto lines = polylines(read_section_csv(r.csv));
    ASSERT_EQ(lines.size(), 1u) << "one closed outline";
    const auto& poly = lines.begin()->second;
    ASSERT_GE(poly.size(), 5u);
    EXPECT_NEAR(poly.front()[0], poly.back()[0], 1e-12); // closed: first vertex repeated
    EXPECT_NEAR(poly.front()[1], poly.back()[1], 1e-12);
    // An undeformed box: the cut is exact up to round-off; 0.5 % as the brief asks.
    std::printf("box section, normal %g,%g,%g: area %.9g m² (exact %g)\n", normal.x(), normal.y(),
                normal.z(), shoelace(poly), area);
    EXPECT_NEAR(shoelace(poly), area, 0.005 * area) << "normal " << normal.transpose();
    double w_lo = 1, w_hi = -1;
    for (const auto& p : poly)
      w_lo = std::min(w_lo, p[1]), w_hi = std::max(w_hi, p[1]);
    EXPECT_NEAR(w_lo, -0.01, 1e-12); // w is z, measured from the point's z = 10 mm
    EXPECT_NEAR(w_hi, 0.01, 1e-12);
    EXPECT_NEAR(r.max_deflection.at("body0"), 0, 1e-15);
  }
}

TEST(Section, ErodedHexahedraAreLeftOut) {
  const Scratch scratch("section_eroded");
  const fs::path& run = scratch.dir;
  // The box above with the corner cell (i, j, k) = (0, 1, 0) of the middle layer eroded: the
  // section at y = 15 mm loses its 10 × 10 mm square and becomes an L.
  write_fe_box(run, {0, 0, 0}, {0.04, 0.03, 0.02}, {4, 3, 2},
               [](const Vec3&) { return Vec3::Zero(); }, {(0 * 3 + 1) * 4 + 0});
  write_pvd(run, true, false);
  SectionOptions o;
  o.run = run;
  o.point = {0.02, 0.015, 0.01};
  const auto r = write_section(o);
  const auto lines = polylines(read_section_csv(r.csv));
  ASSERT_EQ(lines.size(), 1u);
  const double area = 0.04 * 0.02 - 0.01 * 0.01;
  EXPECT_NEAR(shoelace(lines.begin()->second), area, 0.005 * area); // exact up to round-off
}

TEST(Section, ParticleDiskIsOutlinedAsTheDisk) {
  const Scratch scratch("section_disk");
  const fs::path& run = scratch.dir;
  // Particles of spacing 1 mm on the lattice points inside a disk of R = 10 mm, two layers at
  // y = ±0.5 mm: the plane y = 0 falls between them, as it does through the middle of a plate
  // with an even number of layers. Spacing from h/1.2 (no model.h5). A killed particle pair at
  // x = −20 mm must not be outlined but listed.
  const double s = 1e-3, R = 10e-3, rho = 7800;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> cells;
  std::vector<Vec3> zero;
  vtkNew<vtkIntArray> killed;
  killed->SetName("killed");
  for (const double y : {-s / 2, s / 2}) {
    for (int i = -12; i <= 12; ++i)
      for (int k = -12; k <= 12; ++k)
        if (std::hypot(i * s, k * s) <= R) {
          const vtkIdType id = points->InsertNextPoint(i * s, y, k * s);
          cells->InsertNextCell(1, &id);
          zero.push_back(Vec3::Zero());
          killed->InsertNextValue(0);
        }
    const vtkIdType id = points->InsertNextPoint(-0.02, y, 0);
    cells->InsertNextCell(1, &id);
    zero.push_back(Vec3::Zero());
    killed->InsertNextValue(1);
  }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->SetCells(VTK_VERTEX, cells);
  auto* pd = grid->GetPointData();
  pd->AddArray(vectors("displacement", zero));
  pd->AddArray(scalars("h", zero.size(), 1.2 * s));
  pd->AddArray(scalars("mass", zero.size(), rho * s * s * s));
  pd->AddArray(scalars("density", zero.size(), rho));
  pd->AddArray(zeros("body_id", zero.size()));
  pd->AddArray(killed);
  write_grid(run / "frames" / "sph_000000.vtu", grid);
  write_pvd(run, false, true);

  SectionOptions o;
  o.run = run;
  o.normal = {0, -3, 0};
  const auto r = write_section(o);
  auto lines = polylines(read_section_csv(r.csv));
  ASSERT_EQ(lines.size(), 2u) << "one outline, no holes between lattice sites; killed points";
  const auto& dead = lines[{"killed", -1}];
  ASSERT_EQ(dead.size(), 2u);
  EXPECT_NEAR(dead[0][0], -0.02, 1e-12); // u = w × n = z × (−y) = x
  const auto& poly = lines[{"sph", 0}];
  const double equivalent = std::sqrt(shoelace(poly) / std::numbers::pi);
  double mean = 0, lo = 1, hi = 0;
  for (const auto& p : poly) {
    const double radius = std::hypot(p[0], p[1]);
    mean += radius / poly.size();
    lo = std::min(lo, radius);
    hi = std::max(hi, radius);
  }
  std::printf("disk R = %g mm: equivalent radius %.4f mm, mean %.4f mm, min %.4f, max %.4f mm\n",
              R * 1e3, equivalent * 1e3, mean * 1e3, lo * 1e3, hi * 1e3);
  // The particles stand for ~πR² of material; a lattice's staircase edge is within a spacing.
  EXPECT_NEAR(equivalent, R, s);
  EXPECT_NEAR(mean, R, s);
  EXPECT_GT(lo, R - 1.5 * s);
  EXPECT_LT(hi, R + 1.5 * s);
}

TEST(Section, BentPlateGivesTheDeflectionProfile) {
  const Scratch scratch("section_plate");
  const fs::path& run = scratch.dir;
  // A plate [−R, R]² × [0, 4 mm], 21 × 21 × 1 hexahedra, bent to w = −a(1 − r²/R²) (r < R).
  const double R = 0.05, a = 0.004;
  auto w = [&](double r) { return r < R ? -a * (1 - r * r / (R * R)) : 0.0; };
  write_fe_box(run, {-R, -R, 0}, {R, R, 0.004}, {21, 21, 1},
               [&](const Vec3& x) { return Vec3(0, 0, w(std::hypot(x.x(), x.y()))); });
  write_pvd(run, true, false);
  SectionOptions o;
  o.run = run;
  o.normal = {0, 1, 0};
  o.out_dir = run / "out";
  const auto r = write_section(o);
  // The plane y = 0 crosses element middles: edge interpolation of the quadratic field between
  // y = ±e/2 (e = 2R/21) lowers it by a·(e/2)²/R² = 0.2 % of a, and the first bin holds |u| = e/2
  // (another 0.2 %): 1 % bounds both.
  std::printf("bent plate: max |deflection| %.5f mm (exact %.5f mm)\n",
              r.max_deflection.at("body0") * 1e3, a * 1e3);
  EXPECT_NEAR(r.max_deflection.at("body0"), a, 0.01 * a);
  std::ifstream in(r.deflection_csv);
  std::string line;
  std::getline(in, line);
  std::getline(in, line);
  EXPECT_EQ(line, "body,radius_m,deflection_m");
  int bins = 0;
  while (std::getline(in, line)) {
    double radius, deflection;
    ASSERT_EQ(std::sscanf(line.c_str(), "body0,%lf,%lf", &radius, &deflection), 2) << line;
    EXPECT_NEAR(deflection, w(radius), 0.01 * a) << "radius " << radius;
    ++bins;
  }
  EXPECT_EQ(bins, 11); // |u| = e/2, 3e/2, …, R: bins one element wide
  const auto json = nlohmann::json::parse(slurp(r.json));
  EXPECT_NEAR(json["bodies"]["body0"]["max_deflection_m"].get<double>(), a, 0.01 * a);
  EXPECT_EQ(json["bodies"]["body0"]["polylines"].get<int>(), 1);
  EXPECT_NEAR(json["time_s"].get<double>(), 1e-5, 1e-18);

  // The cells of the cut row within R/2 of the centre (|i − 10| ≤ 5) left out, as the report
  // leaves out a plug: the profile starts at their outer edges |u| = 5.5 e, where the bend is
  // a (1 − (11/21)²); the outline keeps them.
  SectionOptions rim = o;
  rim.out_dir = run / "rim";
  rim.leave_out_e.assign(21 * 21, 0);
  for (int i = 5; i <= 15; ++i)
    rim.leave_out_e[10 * 21 + i] = 1;
  const auto kept = write_section(rim);
  EXPECT_NEAR(kept.max_deflection.at("body0"), a * (1 - 121.0 / 441), 0.01 * a);
  EXPECT_EQ(nlohmann::json::parse(slurp(kept.json))["bodies"]["body0"]["polylines"], 1);
  rim.leave_out_e.pop_back();
  EXPECT_THROW(write_section(rim), sphfem::Error);
}

// The cut coloured by a cell field: an FE box 4 × 3 × 2 whose cells carry plastic strain 0.1 ×
// (their index along x + 1); the plane y = 15 mm cuts the middle row, so each of the four values
// fills two 10 × 10 mm squares of the picture in its own colour of the scale 0 … 0.4.
TEST(Section, FieldColoursTheCut) {
  const Scratch scratch("section_field");
  const fs::path& run = scratch.dir;
  write_fe_box(run, {0, 0, 0}, {0.04, 0.03, 0.02}, {4, 3, 2},
               [](const Vec3&) { return Vec3::Zero(); });
  write_pvd(run, true, false);
  {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName((run / "frames" / "fe_000000.vtu").c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    vtkNew<vtkDoubleArray> strain;
    strain->SetName("plastic_strain");
    for (vtkIdType k = 0; k < grid->GetNumberOfCells(); ++k)
      strain->InsertNextValue(0.1 * double(k % 4 + 1));
    grid->GetCellData()->AddArray(strain);
    write_grid(run / "frames" / "fe_000000.vtu", grid);
  }
  SectionOptions o;
  o.run = run;
  o.point = {0.02, 0.015, 0.01};
  o.out_dir = run / "strain";
  const auto r = write_section(o);
  const auto json = nlohmann::json::parse(slurp(r.json));
  EXPECT_EQ(json["field"], "plastic_strain");
  EXPECT_NEAR(json["field_range"][1].get<double>(), 0.4, 1e-12);
  auto count = [](const sphfem_test::Pixels& png, sphfem::post::Rgb c) {
    long n = 0;
    for (int y = 0; y < png.height; ++y)
      for (int x = 0; x < png.width; ++x) {
        const auto p = png.at(x, y);
        n += p.r == c.r && p.g == c.g && p.b == c.b;
      }
    return n;
  };
  using sphfem::post::LineChart;
  const auto png = sphfem_test::read_png(r.png);
  std::vector<long> filled;
  for (int i = 1; i <= 4; ++i)
    filled.push_back(count(png, LineChart::viridis(i / 4.0)));
  std::printf("field pixels per value: %ld %ld %ld %ld\n", filled[0], filled[1], filled[2],
              filled[3]);
  for (long n : filled) // each value's two squares (the colour bar adds at most a few rows)
    EXPECT_GT(n, 0.9 * filled[0]) << "equal areas";
  EXPECT_GT(filled[0], 1000);

  o.out_dir = run / "none";
  o.field = "none";
  const auto plain = write_section(o);
  EXPECT_TRUE(nlohmann::json::parse(slurp(plain.json))["field"].is_null());
  EXPECT_EQ(count(sphfem_test::read_png(plain.png), LineChart::viridis(1.0)), 0);
}

TEST(Section, CommandOnATinyRunWritesTheFiles) {
  const Scratch scratch("section_command");
  const fs::path& dir = scratch.dir;
  const fs::path run = dir / "bar";
  const std::string bar_case = std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_impact/case.yaml";
  auto r = run_sphfem("run " + bar_case + " -o " + run.string() + " -q --set time.end=1e-5", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  // Through both bars' axis: bar_a in particles (a layer on the plane), bar_b in hexahedra.
  r = run_sphfem("post section " + run.string() + " --plane 0.025,0.025,0,1,0,0 --size 700x500",
                 dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"section.png", "section.csv", "deflection.csv", "section.json"}) {
    EXPECT_GT(fs::file_size(run / "post" / name), 60u) << name;
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
  }
  const auto png = sphfem_test::read_png(run / "post" / "section.png");
  EXPECT_EQ(png.width, 700);
  EXPECT_EQ(png.height, 500);
  EXPECT_GT(png.non_white_fraction(), 0.02);
  const auto json = nlohmann::json::parse(slurp(run / "post" / "section.json"));
  EXPECT_EQ(json["bodies"].size(), 2u);
  EXPECT_GE(json["bodies"]["bar_a"]["polylines"].get<int>(), 1);
  EXPECT_GE(json["bodies"]["bar_b"]["polylines"].get<int>(), 1);
  const auto rows = read_section_csv(run / "post" / "section.csv");
  std::map<std::string, int> parts;
  for (const auto& row : rows)
    ++parts[row.body + "/" + row.part];
  EXPECT_GT(parts["bar_a/sph"], 10);
  EXPECT_GT(parts["bar_b/fe"], 10);

  r = run_sphfem("post section " + run.string() +
                     " --plane 0.025,0.025,0,1,0,0 --bodies bar_b"
                     " --time 0 -o " +
                     (dir / "only_b").string(),
                 dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto only_b = nlohmann::json::parse(slurp(dir / "only_b" / "section.json"));
  EXPECT_EQ(only_b["bodies"].size(), 1u);
  EXPECT_NEAR(only_b["time_s"].get<double>(), 0, 1e-12);

  // A window along u: the picture shows less, the data files keep the whole section.
  r = run_sphfem("post section " + run.string() +
                     " --plane 0.025,0.025,0,1,0,0 --u-range -0.1,0 -o " + (dir / "half").string(),
                 dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto half = nlohmann::json::parse(slurp(dir / "half" / "section.json"));
  EXPECT_EQ(half["u_range_m"], nlohmann::json::array({-0.1, 0.0}));
  EXPECT_EQ(read_section_csv(dir / "half" / "section.csv").size(), rows.size());

  const std::string out = " -o " + (dir / "p").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"post section " + run.string() + " --plane 1,0,0,1,0,0", "the plane cuts no body"},
      {"post section " + run.string() + " --plane 0,0,0,0,0,0", "the normal NX,NY,NZ is zero"},
      {"post section " + run.string() + " --plane 0,0,0", "--plane 0,0,0: expected PX,PY,PZ"},
      {"post section " + run.string() + " --plane 0,0,0,1,0,0 --axis 1,0,0",
       "is along the plane's normal"},
      {"post section " + run.string() + " --plane 0.025,0,0,1,0,0 --bodies nope",
       "--bodies nope: no such body"},
      {"post section " + run.string() + " --plane 0.025,0,0,1,0,0 --u-range 1",
       "--u-range 1: expected U0,U1"},
      {"post section " + run.string() + " --plane 0.025,0,0,1,0,0 --u-range 0.1,0",
       "expected U0,U1 in m with U0 < U1"},
      {"post section " + dir.string() + " --plane 0,0,0,1,0,0", "results.pvd: no such file"},
  };
  for (const auto& [args, message] : cases) {
    const auto e = run_sphfem(args + out, dir);
    EXPECT_NE(e.code, 0) << args;
    EXPECT_NE(e.err.find("sphfem: error: " + std::string()), std::string::npos) << e.err;
    EXPECT_NE(e.err.find(message), std::string::npos) << args << "\n" << e.err;
    EXPECT_EQ(std::count(e.err.begin(), e.err.end(), '\n'), 1) << e.err;
    EXPECT_FALSE(fs::exists(dir / "p")) << args;
  }
}

// A run folder whose results.pvd or frame is wrong in one way: the command fails with one line
// naming the file and the fault (VTK's own messages, several lines each, are not printed) and
// writes nothing. The same folder with good files is cut, so each fault alone is the cause.
TEST(Section, BadRunFilesAreOneLineErrors) {
  const Scratch scratch("section_bad_files");
  const fs::path& dir = scratch.dir;
  const auto unit_hex = [](bool with_displacement,
                           std::vector<vtkIdType> ids = {0, 1, 2, 3, 4, 5, 6, 7}) {
    vtkNew<vtkPoints> points;
    std::vector<Vec3> zero;
    for (const auto& c : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                          Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)}) {
      points->InsertNextPoint(c.data());
      zero.push_back(Vec3::Zero());
    }
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(points);
    grid->InsertNextCell(VTK_HEXAHEDRON, vtkIdType(ids.size()), ids.data());
    if (with_displacement)
      grid->GetPointData()->AddArray(vectors("displacement", zero));
    grid->GetCellData()->AddArray(zeros("body_id", 1));
    return grid;
  };
  const auto particle_without_h = [] {
    vtkNew<vtkPoints> points;
    const vtkIdType id = points->InsertNextPoint(0, 0, 0);
    vtkNew<vtkCellArray> cells;
    cells->InsertNextCell(1, &id);
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(points);
    grid->SetCells(VTK_VERTEX, cells);
    auto* pd = grid->GetPointData();
    pd->AddArray(vectors("displacement", {Vec3::Zero()}));
    pd->AddArray(scalars("mass", 1, 1e-6));
    pd->AddArray(scalars("density", 1, 7800));
    pd->AddArray(zeros("body_id", 1));
    return grid;
  };
  const auto folder = [&](const std::string& name) {
    fs::create_directories(dir / name);
    return dir / name;
  };
  fs::path run = folder("good");
  write_grid(run / "frames" / "fe_000000.vtu", unit_hex(true));
  write_pvd(run, true, false);
  const std::string plane = " --plane 0.5,0.5,0.5,1,0,0";
  const Result good = run_sphfem("post section " + run.string() + plane, dir);
  ASSERT_EQ(good.code, 0) << good.err;

  std::vector<std::pair<fs::path, std::string>> cases;
  run = folder("timestep");
  fs::copy(dir / "good" / "frames", run / "frames");
  write_pvd(run, true, false);
  std::string pvd = slurp(run / "results.pvd");
  pvd.replace(pvd.find("1e-05"), 5, "soon");
  std::ofstream(run / "results.pvd") << pvd;
  cases.push_back({run, "results.pvd:4: DataSet timestep \"soon\": expected a time in s"});
  run = folder("no_frames");
  write_pvd(run, false, false);
  cases.push_back({run, "results.pvd: lists no frames"});
  run = folder("missing_frame");
  write_pvd(run, true, false);
  cases.push_back({run, "frames/fe_000000.vtu: no such frame file"});
  run = folder("garbage");
  write_pvd(run, true, false);
  fs::create_directories(run / "frames");
  std::ofstream(run / "frames" / "fe_000000.vtu") << "not a frame\n";
  cases.push_back({run, "fe_000000.vtu: cannot read the frame (VTK: Error parsing XML"});
  run = folder("truncated");
  write_pvd(run, true, false);
  fs::create_directories(run / "frames");
  const std::string frame = slurp(dir / "good" / "frames" / "fe_000000.vtu");
  std::ofstream(run / "frames" / "fe_000000.vtu") << frame.substr(0, frame.find("<Cells>"));
  cases.push_back({run, "fe_000000.vtu: cannot read the frame (VTK: "});
  run = folder("no_points");
  write_pvd(run, true, false);
  fs::create_directories(run / "frames");
  // A well-formed file of no points (VTK's writer leaves out the Points element, which its
  // reader then rejects).
  std::ofstream(run / "frames" / "fe_000000.vtu")
      << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n"
         "<UnstructuredGrid><Piece NumberOfPoints=\"0\" NumberOfCells=\"0\">\n"
         "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
         "</DataArray></Points>\n<Cells>"
         "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\"></DataArray>"
         "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\"></DataArray>"
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\"></DataArray></Cells>\n"
         "</Piece></UnstructuredGrid>\n</VTKFile>\n";
  cases.push_back({run, "fe_000000.vtu: cannot read the frame (it has no points)"});
  run = folder("no_displacement");
  write_pvd(run, true, false);
  write_grid(run / "frames" / "fe_000000.vtu", unit_hex(false));
  cases.push_back({run, "fe_000000.vtu: no displacement array with 3 component(s)"});
  run = folder("point_beyond");
  write_pvd(run, true, false);
  write_grid(run / "frames" / "fe_000000.vtu", unit_hex(true, {0, 1, 2, 3, 4, 5, 6, 99}));
  cases.push_back({run, "fe_000000.vtu: cell 0 refers to point 99, expected 0 to 7"});
  run = folder("seven_nodes");
  write_pvd(run, true, false);
  write_grid(run / "frames" / "fe_000000.vtu", unit_hex(true, {0, 1, 2, 3, 4, 5, 6}));
  cases.push_back({run, "fe_000000.vtu: cell 0 is a hexahedron of 7 points, expected 8"});
  run = folder("no_h");
  write_pvd(run, false, true);
  write_grid(run / "frames" / "sph_000000.vtu", particle_without_h());
  cases.push_back({run, "sph_000000.vtu: no h array with 1 component(s)"});
  for (const auto& [bad, message] : cases) {
    const Result r = run_sphfem("post section " + bad.string() + plane, dir);
    EXPECT_NE(r.code, 0) << bad;
    EXPECT_EQ(r.err.rfind("sphfem: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << bad << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(bad / "post")) << bad;
  }
}

// The picture's window along u: crossing segments end on the bounds, runs outside break the line.
TEST(Section, ClipKeepsThePartInsideTheWindow) {
  using sphfem::post::clip_polyline_u;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // A square from u = −1 to 3 (w 0 to 2), closed, clipped to 0 ≤ u ≤ 2: its top and bottom
  // edges are cut at both bounds, its left and right edges vanish.
  std::vector<double> u{-1, 3, 3, -1, -1}, w{0, 0, 2, 2, 0};
  clip_polyline_u(u, w, 0, 2);
  ASSERT_EQ(u.size(), 6u);
  EXPECT_EQ(u[0], 0);
  EXPECT_EQ(u[1], 2);
  EXPECT_EQ(w[0], 0);
  EXPECT_EQ(w[1], 0);
  EXPECT_TRUE(std::isnan(u[2]));
  EXPECT_EQ(u[3], 2);
  EXPECT_EQ(u[4], 0);
  EXPECT_EQ(w[3], 2);
  EXPECT_EQ(w[4], 2);
  EXPECT_TRUE(std::isnan(u[5])); // the line leaves the window at u = 0
  // A slanted segment is cut where it crosses (w interpolated); a break stays one break; a
  // line wholly outside leaves nothing.
  std::vector<double> a{1, 4, nan, 5, 6}, b{0, 3, nan, 1, 1};
  clip_polyline_u(a, b, 0, 2);
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a[0], 1);
  EXPECT_DOUBLE_EQ(a[1], 2);
  EXPECT_DOUBLE_EQ(b[1], 1);
  EXPECT_TRUE(std::isnan(a[2]));
}

// LineChart's options for sections: equal axis scales and point markers.
TEST(SectionChart, EqualAspectGivesOneScaleAndMarkersDrawDots) {
  using sphfem::post::LineChart;
  LineChart chart(700, 400);
  chart.set_equal_aspect(true);
  chart.add_series("box", {0, 40, 40, 0, 0}, {0, 0, 10, 10, 0}, {LineChart::palette(0), 2, false});
  sphfem::post::LineStyle dots{LineChart::palette(1), 0, false};
  dots.marker = 3;
  chart.add_series("dots", {10, 30}, {3.3, 3.3}, dots);
  double x0, y0, x1, y1;
  chart.pixel(0, 0, x0, y0);
  chart.pixel(40, 10, x1, y1);
  EXPECT_NEAR((x1 - x0) / 40, (y0 - y1) / 10, 1e-9); // pixels per unit on both axes
  const auto area = LineChart::plot_area(700, 400);
  EXPECT_GE(x0, area.left); // the data stay inside the frame
  EXPECT_LE(x1, area.right);
  EXPECT_GE(y1, area.top);
  EXPECT_LE(y0, area.bottom);

  const auto rgb = chart.render();
  auto at = [&](double x, double y) {
    const std::size_t k = (std::size_t(std::lround(y)) * 700 + std::size_t(std::lround(x))) * 3;
    return std::array<int, 3>{rgb[k], rgb[k + 1], rgb[k + 2]};
  };
  const auto c = LineChart::palette(1);
  double px, py;
  chart.pixel(10, 3.3, px, py);
  EXPECT_EQ(at(px, py), (std::array<int, 3>{c.r, c.g, c.b})); // a dot's centre
  chart.pixel(17, 3.3, px, py);                               // off the grid lines
  EXPECT_EQ(at(px, py), (std::array<int, 3>{255, 255, 255})); // no line between dots
}
