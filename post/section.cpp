#include "post/section.hpp"

#include "post/frames.hpp"

#include "post/line_chart.hpp"
#include "post/particle_outline.hpp"
#include "post/post.hpp"
#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/model_h5.hpp"

#include <nlohmann/json.hpp>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCutter.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

namespace sphfem::post {

namespace fs = std::filesystem;

namespace {

// The plane's frame: unit normal n, in-plane axes û = ŵ × n and ŵ (the deflection axis).
struct Plane {
  Vec3 point, n, u, w;
  Vec3 at(double u_m, double w_m) const { return point + u_m * u + w_m * w; }
  double distance(const Vec3& x) const { return (x - point).dot(n); }
};

std::string vec_text(const Vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "%g,%g,%g", v.x(), v.y(), v.z());
  return buffer;
}

Plane make_plane(const SectionOptions& o) {
  const std::string plane = "--plane " + vec_text(o.point) + "," + vec_text(o.normal);
  SPHFEM_CHECK(o.point.allFinite() && o.normal.allFinite(), plane, ": expected finite numbers");
  SPHFEM_CHECK(o.normal.norm() > 0, plane, ": the normal NX,NY,NZ is zero");
  Plane p{o.point, o.normal.normalized(), Vec3::Zero(), Vec3::Zero()};
  if (o.axis) {
    const Vec3& a = *o.axis;
    SPHFEM_CHECK(a.allFinite() && a.norm() > 0, "--axis ", vec_text(a),
                 ": expected a non-zero direction");
    p.w = a - a.dot(p.n) * p.n;
    SPHFEM_CHECK(p.w.norm() > 1e-6 * a.norm(), "--axis ", vec_text(a),
                 " is along the plane's normal: expected a direction in the plane");
  } else { // the in-plane direction closest to z; for a plane normal to z, the one closest to y
    p.w = Vec3::UnitZ() - p.n.z() * p.n;
    if (p.w.norm() < 1e-6)
      p.w = Vec3::UnitY() - p.n.y() * p.n;
  }
  p.w.normalize();
  p.u = p.w.cross(p.n);
  return p;
}

vtkDataArray* array(vtkDataSetAttributes* data, const char* name, const fs::path& file,
                    int components) {
  vtkDataArray* a = data->GetArray(name);
  SPHFEM_CHECK(a && a->GetNumberOfComponents() == components, file.string(), ": no ", name,
               " array with ", components, " component(s)");
  return a;
}

struct Frame {
  double time;
  vtkSmartPointer<vtkUnstructuredGrid> fe, sph; // null if the run has none
  fs::path fe_file, sph_file;
};

// The frame nearest to `time` (the last without one): its FE and particle files.
Frame read_frame(const fs::path& run, std::optional<double> time) {
  const fs::path pvd = run / "results.pvd";
  SPHFEM_CHECK(fs::is_regular_file(pvd), pvd.string(),
               ": no such file (not a run folder; run `sphfem solve` first)");
  SPHFEM_CHECK(!time || std::isfinite(*time), "--time ", *time, ": expected seconds");
  const auto frames = frame_files(pvd);
  const FrameFiles& files = frames[nearest_frame(frames, time)];
  Frame f{files.time, nullptr, nullptr, files.elements, files.particles};
  if (!files.elements.empty())
    f.fe = read_vtu(files.elements);
  if (!files.particles.empty())
    f.sph = read_vtu(files.particles);
  return f;
}

struct Bodies {
  std::vector<std::string> names;
  std::vector<double> spacing; // m, 0 if unknown (FE bodies)
};

// From OUT/model.h5; without it, bodies named body0, body1, … up to the largest body id.
Bodies read_bodies(const fs::path& run, const Frame& frame) {
  const fs::path file = run / "model.h5";
  if (fs::exists(file)) {
    Model m = read_model_h5(file);
    m.spacing_b.resize(m.body_names.size(), 0.0);
    return {m.body_names, m.spacing_b};
  }
  auto largest_id = [](vtkDataArray* ids) { return ids ? int(ids->GetRange()[1]) : -1; };
  int largest = -1;
  if (frame.fe)
    largest = std::max(largest, largest_id(frame.fe->GetCellData()->GetArray("body_id")));
  if (frame.sph)
    largest = std::max(largest, largest_id(frame.sph->GetPointData()->GetArray("body_id")));
  Bodies b;
  for (int i = 0; i <= largest; ++i)
    b.names.push_back("body" + std::to_string(i));
  b.spacing.assign(b.names.size(), 0.0);
  return b;
}

std::string list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names)
    s += (s.empty() ? "" : ", ") + n;
  return s;
}

struct Polyline {
  std::string part; // fe or sph
  std::vector<Vec3> x;
};

// A piece of the cut coloured by the field: a cut hexahedron's polygon or a particle's square.
struct Patch {
  std::vector<Vec3> x; // on the plane, in order around it
  double value;
  double depth; // distance of a particle from the plane (paints nearest last), 0 for elements
};

struct BodySection {
  std::vector<Polyline> polylines;
  std::vector<Patch> patches;
  std::vector<Vec3> killed;                      // killed particles near the plane
  std::vector<std::array<double, 3>> profile;    // (|u| m, displacement·ŵ m, weight)
  double bin = 0;                                // bin width of the profile, m
  std::vector<std::array<double, 2>> deflection; // (radius, mean deflection) per bin, m
  double max_deflection = 0;                     // m
};

// The field's array, or null if the data has none (an elastic run) or no field is drawn.
vtkDataArray* field_array(vtkDataSetAttributes* data, const std::string& field,
                          const fs::path& file) {
  if (field == "none")
    return nullptr;
  vtkDataArray* a = data->GetArray(field.c_str());
  SPHFEM_CHECK(!a || a->GetNumberOfComponents() == 1, file.string(), ": array ", field, " has ",
               a->GetNumberOfComponents(), " components, expected 1");
  return a;
}

// The points where the plane crosses a cell's edges, ordered by angle about their mean in the
// plane (a plane cuts a convex cell in a convex polygon).
std::vector<Vec3> cut_polygon(std::vector<Vec3> points, const Plane& plane) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points)
    mean += p / double(points.size());
  auto angle = [&](const Vec3& p) {
    return std::atan2((p - mean).dot(plane.w), (p - mean).dot(plane.u));
  };
  std::sort(points.begin(), points.end(),
            [&](const Vec3& a, const Vec3& b) { return angle(a) < angle(b); });
  return points;
}

bool left_out(const std::vector<char>& mask, vtkIdType i) {
  return std::size_t(i) < mask.size() && mask[std::size_t(i)] != 0;
}

// FE bodies: outline from the cut boundary faces, profile from the cut hexahedron edges.
void cut_fe(const Frame& frame, const Plane& plane, const std::vector<bool>& selected,
            const SectionOptions& o, std::map<int, BodySection>& sections) {
  vtkUnstructuredGrid* grid = frame.fe;
  const fs::path& file = frame.fe_file;
  vtkDataArray* u = array(grid->GetPointData(), "displacement", file, 3);
  vtkDataArray* value = field_array(grid->GetCellData(), o.field, file);
  vtkDataArray* body = array(grid->GetCellData(), "body_id", file, 1);
  vtkDataArray* ghost = grid->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
  const vtkIdType n_points = grid->GetNumberOfPoints();
  std::vector<Vec3> x(n_points), disp(n_points);
  std::vector<double> d(n_points);
  for (vtkIdType i = 0; i < n_points; ++i) {
    grid->GetPoint(i, x[i].data());
    u->GetTuple(i, disp[i].data());
    d[i] = plane.distance(x[i]);
  }
  static constexpr int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                      {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  static constexpr int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                       {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  // Per body: each face of a live hexahedron by its sorted node ids → (uses, the face).
  std::map<int, std::map<std::array<vtkIdType, 4>, std::pair<int, std::array<vtkIdType, 4>>>>
      boundary;
  std::map<int, std::set<std::pair<vtkIdType, vtkIdType>>> cut_edges;
  std::map<int, std::pair<double, int>> edge_length; // Σ longest edge of cut cells, count
  for (vtkIdType k = 0; k < grid->GetNumberOfCells(); ++k) {
    if (grid->GetCellType(k) != VTK_HEXAHEDRON ||
        (ghost && (int(ghost->GetComponent(k, 0)) & vtkDataSetAttributes::HIDDENCELL)))
      continue;
    const int b = int(body->GetComponent(k, 0));
    if (b < 0 || b >= int(selected.size()) || !selected[b])
      continue;
    vtkIdType n;
    const vtkIdType* ids;
    grid->GetCellPoints(k, n, ids);
    const auto [lo, hi] =
        std::minmax_element(ids, ids + n, [&](auto a, auto c) { return d[a] < d[c]; });
    if (d[*lo] > 0 || d[*hi] < 0)
      continue; // a cut face belongs only to cells the plane reaches
    for (const auto& f : faces) {
      std::array<vtkIdType, 4> face{ids[f[0]], ids[f[1]], ids[f[2]], ids[f[3]]}, key = face;
      std::sort(key.begin(), key.end());
      auto& slot = boundary[b][key];
      slot = {slot.first + 1, face};
    }
    bool cut = false;
    std::vector<Vec3> polygon;
    for (const auto& e : edges) {
      vtkIdType a = ids[e[0]], c = ids[e[1]];
      if ((d[a] < 0) == (d[c] < 0))
        continue;
      cut = true;
      if (a > c)
        std::swap(a, c);
      const double t = d[a] / (d[a] - d[c]);
      const Vec3 xi = x[a] + t * (x[c] - x[a]), ui = disp[a] + t * (disp[c] - disp[a]);
      polygon.push_back(xi);
      if (left_out(o.leave_out_e, k) || !cut_edges[b].insert({a, c}).second)
        continue;
      sections[b].profile.push_back(
          {std::abs((xi - plane.point).dot(plane.u)), ui.dot(plane.w), 1.0});
    }
    if (value && polygon.size() >= 3)
      sections[b].patches.push_back(
          {cut_polygon(std::move(polygon), plane), value->GetComponent(k, 0), 0.0});
    if (cut) { // the element size: its longest edge (a plate's in-plane size), reference
      double longest = 0;
      for (const auto& e : edges) {
        const auto a = ids[e[0]], c = ids[e[1]];
        longest = std::max(longest, ((x[a] - disp[a]) - (x[c] - disp[c])).norm());
      }
      auto& [sum, count] = edge_length[b];
      sum += longest;
      ++count;
    }
  }
  for (const auto& [b, length] : edge_length)
    sections[b].bin = length.first / length.second;

  vtkNew<vtkPlane> cut_plane;
  cut_plane->SetOrigin(plane.point.data());
  cut_plane->SetNormal(plane.n.data());
  for (const auto& [b, faces_b] : boundary) {
    vtkNew<vtkCellArray> quads;
    for (const auto& [key, slot] : faces_b)
      if (slot.first == 1) // used by one live hexahedron: on the body's surface
        quads->InsertNextCell(4, slot.second.data());
    vtkNew<vtkPolyData> surface;
    surface->SetPoints(grid->GetPoints());
    surface->SetPolys(quads);
    vtkNew<vtkCutter> cutter;
    cutter->SetInputData(surface);
    cutter->SetCutFunction(cut_plane);
    cutter->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
    cutter->Update();
    vtkPolyData* lines = cutter->GetOutput();
    for (const auto& ids : chain_segments(lines)) {
      Polyline line{"fe", {}};
      for (long long id : ids) {
        Vec3 p;
        lines->GetPoint(id, p.data());
        line.x.push_back(p);
      }
      sections[b].polylines.push_back(std::move(line));
    }
  }
}

// SPH bodies: outline of the particles near the plane, killed ones and the profile in the slab.
void cut_sph(const Frame& frame, const Plane& plane, const Bodies& bodies,
             const std::vector<bool>& selected, const SectionOptions& o,
             std::map<int, BodySection>& sections) {
  vtkUnstructuredGrid* grid = frame.sph;
  const fs::path& file = frame.sph_file;
  vtkPointData* pd = grid->GetPointData();
  vtkDataArray* value = field_array(pd, o.field, file);
  vtkDataArray* u = array(pd, "displacement", file, 3);
  vtkDataArray* h = array(pd, "h", file, 1);
  vtkDataArray* mass = array(pd, "mass", file, 1);
  vtkDataArray* density = array(pd, "density", file, 1);
  vtkDataArray* body = array(pd, "body_id", file, 1);
  vtkDataArray* killed = pd->GetArray("killed");
  struct Cloud {
    std::vector<Eigen::Vector2d> x;
    std::vector<double> area, spacing;
  };
  std::map<int, Cloud> clouds;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    const int b = int(body->GetComponent(i, 0));
    if (b < 0 || b >= int(selected.size()) || !selected[b])
      continue;
    Vec3 x, disp;
    grid->GetPoint(i, x.data());
    const double s = bodies.spacing[b] > 0 ? bodies.spacing[b] : h->GetComponent(i, 0) / 1.2;
    const double d = std::abs(plane.distance(x));
    if (!(d < s))
      continue;
    const double tent = 1 - d / s;
    if (killed && killed->GetComponent(i, 0) != 0) {
      if (tent > 0.25) // the nearest layer, or the two a plane between layers halves
        sections[b].killed.push_back(x);
      continue;
    }
    const Vec3 r = x - plane.point;
    if (value && d < 0.75 * s) { // the nearest lattice layer, or the two a plane between halves
      std::vector<Vec3> square;
      for (const auto& [su, sw] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
        square.push_back(x - plane.distance(x) * plane.n + 0.5 * s * (su * plane.u + sw * plane.w));
      sections[b].patches.push_back({std::move(square), value->GetComponent(i, 0), d});
    }
    Cloud& c = clouds[b];
    c.x.emplace_back(r.dot(plane.u), r.dot(plane.w));
    c.area.push_back(tent * mass->GetComponent(i, 0) / density->GetComponent(i, 0) / s);
    c.spacing.push_back(s);
    u->GetTuple(i, disp.data());
    if (!left_out(o.leave_out_p, i))
      sections[b].profile.push_back({std::abs(c.x.back().x()), disp.dot(plane.w), tent});
  }
  for (auto& [b, c] : clouds) {
    double spacing = 0;
    for (double s : c.spacing)
      spacing += s / c.spacing.size();
    BodySection& section = sections[b];
    if (section.bin == 0)
      section.bin = spacing;
    for (const auto& line : particle_outline(c.x, c.area, spacing)) {
      Polyline p{"sph", {}};
      for (const auto& q : line)
        p.x.push_back(plane.at(q.x(), q.y()));
      section.polylines.push_back(std::move(p));
    }
  }
}

// Mean deflection in bins of |u| one `bin` wide whose edges lie halfway between the rows of
// points (at the circular mean phase of |u|/bin, plus 1/2), so that rows of nodes or particles
// fall mid-bin rather than on edges; averages are weighted, a bin's radius is the mean |u| in it.
void bin_profile(BodySection& s) {
  if (s.profile.empty() || !(s.bin > 0))
    return;
  double c = 0, sn = 0;
  for (const auto& point : s.profile) { // (|u|, deflection, weight)
    c += point[2] * std::cos(2 * std::numbers::pi * point[0] / s.bin);
    sn += point[2] * std::sin(2 * std::numbers::pi * point[0] / s.bin);
  }
  const double phase = std::atan2(sn, c) / (2 * std::numbers::pi);
  std::map<long long, std::array<double, 3>> bins; // Σ weight·|u|, Σ weight·deflection, Σ weight
  for (const auto& [r, w, weight] : s.profile) {
    auto& slot = bins[std::llround(r / s.bin - phase)];
    slot[0] += weight * r;
    slot[1] += weight * w;
    slot[2] += weight;
  }
  for (const auto& [k, slot] : bins) {
    s.deflection.push_back({slot[0] / slot[2], slot[1] / slot[2]});
    s.max_deflection = std::max(s.max_deflection, std::abs(slot[1] / slot[2]));
  }
}

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

// Writes a text file's content, whole or not at all (a temporary, then renamed).
void finish(const std::ostringstream& out, const fs::path& file) {
  write_text_atomically(file, out.str());
}

// "Section y = 25 mm" for a plane normal to a coordinate axis, else "Section".
std::string plane_name(const Plane& plane) {
  for (int i = 0; i < 3; ++i)
    if (std::abs(plane.n[i]) > 1 - 1e-12) {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "Section %c = %g mm", "xyz"[i], plane.point[i] * 1e3);
      return buffer;
    }
  return "Section";
}

// The field's patches of every body, in mm, beneath the outlines: elements first, then particles
// farthest from the plane first; its colour scale from 0 (damage: to 1, else to the largest
// value drawn). Empty if no patch carries the field.
std::optional<ColourScale> draw_field(LineChart& chart, const std::map<int, BodySection>& sections,
                                      const Plane& plane, const SectionOptions& o) {
  std::vector<const Patch*> patches;
  for (const auto& [b, s] : sections)
    for (const Patch& p : s.patches) {
      Vec3 mean = Vec3::Zero();
      for (const Vec3& x : p.x)
        mean += x / double(p.x.size());
      const double u = (mean - plane.point).dot(plane.u);
      if (!o.u_range || (u >= (*o.u_range)[0] && u <= (*o.u_range)[1]))
        patches.push_back(&p);
    }
  if (patches.empty())
    return std::nullopt;
  std::stable_sort(patches.begin(), patches.end(),
                   [](const Patch* a, const Patch* b) { return a->depth > b->depth; });
  ColourScale scale{o.field == "damage" ? "damage D (-)" : "equivalent plastic strain (-)", 0, 1};
  if (o.field != "damage") {
    double largest = 0;
    for (const Patch* p : patches)
      largest = std::max(largest, p->value);
    scale.max = largest > 0 ? largest : 1;
  }
  chart.set_colour_scale(scale);
  for (const Patch* p : patches) {
    std::vector<double> u_mm, w_mm;
    for (const Vec3& x : p->x) {
      u_mm.push_back(1e3 * (x - plane.point).dot(plane.u));
      w_mm.push_back(1e3 * (x - plane.point).dot(plane.w));
    }
    chart.add_patch(std::move(u_mm), std::move(w_mm), p->value);
  }
  return scale;
}

} // namespace

void clip_polyline_u(std::vector<double>& u, std::vector<double>& w, double lo, double hi) {
  const double gap = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> cu, cw;
  const auto put = [&](double a, double b) {
    cu.push_back(a);
    cw.push_back(b);
  };
  const auto cut = [&] { // one break, never two in a row or at the start
    if (!cu.empty() && !std::isnan(cu.back()))
      put(gap, gap);
  };
  for (std::size_t k = 0; k < u.size(); ++k) {
    if (!std::isfinite(u[k])) {
      cut();
      continue;
    }
    if (k == 0 || !std::isfinite(u[k - 1])) {
      if (u[k] >= lo && u[k] <= hi)
        put(u[k], w[k]);
      continue;
    }
    // The segment k−1 → k inside lo ≤ u ≤ hi: parameters t0 ≤ t1 in [0, 1].
    const double a = u[k - 1], du = u[k] - a, b = w[k - 1], dw = w[k] - b;
    double t0 = 0, t1 = 1;
    if (du != 0) {
      const double ta = (lo - a) / du, tb = (hi - a) / du;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    } else if (a < lo || a > hi) {
      t0 = 1, t1 = 0;
    }
    if (t0 > t1) {
      cut();
      continue;
    }
    if (t0 > 0) { // enters through a bound (the start point was outside)
      cut();
      put(a + t0 * du, b + t0 * dw);
    }
    if (t1 < 1) { // leaves through a bound
      put(a + t1 * du, b + t1 * dw);
      cut();
    } else {
      put(u[k], w[k]);
    }
  }
  u = std::move(cu);
  w = std::move(cw);
}

SectionResult write_section(const SectionOptions& o) {
  // Everything is read and checked before anything is written.
  const Plane plane = make_plane(o);
  (void)LineChart(o.width, o.height); // checks the size
  SPHFEM_CHECK(o.field == "plastic_strain" || o.field == "damage" || o.field == "none", "--field ",
               o.field, ": expected plastic_strain, damage or none");
  if (const auto& r = o.u_range)
    SPHFEM_CHECK(std::isfinite((*r)[0]) && std::isfinite((*r)[1]) && (*r)[0] < (*r)[1],
                 "--u-range ", (*r)[0], ",", (*r)[1], ": expected U0,U1 in m with U0 < U1");
  const Frame frame = read_frame(o.run, o.time);
  const Bodies bodies = read_bodies(o.run, frame);
  std::vector<bool> selected(bodies.names.size(), o.bodies.empty());
  for (const auto& name : o.bodies) {
    const auto it = std::find(bodies.names.begin(), bodies.names.end(), name);
    SPHFEM_CHECK(it != bodies.names.end(), "--bodies ", name, ": no such body in ",
                 (o.run / "model.h5").string(), " (bodies: ", list(bodies.names), ")");
    selected[it - bodies.names.begin()] = true;
  }
  auto check_mask = [&](const std::vector<char>& mask, vtkUnstructuredGrid* grid, bool cells) {
    const vtkIdType n = !grid ? 0 : cells ? grid->GetNumberOfCells() : grid->GetNumberOfPoints();
    SPHFEM_CHECK(mask.empty() || vtkIdType(mask.size()) == n, "section: ", mask.size(),
                 " flags to leave out, the frame has ", n, cells ? " cells" : " particles");
  };
  check_mask(o.leave_out_p, frame.sph, false);
  check_mask(o.leave_out_e, frame.fe, true);
  std::map<int, BodySection> sections;
  if (frame.fe)
    cut_fe(frame, plane, selected, o, sections);
  if (frame.sph)
    cut_sph(frame, plane, bodies, selected, o, sections);
  std::erase_if(sections, [](const auto& s) { return s.second.polylines.empty(); });
  char when[64];
  std::snprintf(when, sizeof when, "%.4g", frame.time * 1e6);
  SPHFEM_CHECK(!sections.empty(), "--plane ", vec_text(o.point), ",", vec_text(o.normal),
               ": the plane cuts no ", o.bodies.empty() ? "body" : "chosen body",
               " in the frame at t = ", when, " us of ", (o.run / "results.pvd").string());
  for (auto& [b, s] : sections)
    bin_profile(s);

  const fs::path dir = o.out_dir.empty() ? o.run / "post" : o.out_dir;
  std::error_code failed;
  fs::create_directories(dir, failed);
  SPHFEM_CHECK(!failed, dir.string(), ": cannot create the folder: ", failed.message());
  SectionResult result{frame.time,
                       dir / "section.csv",
                       dir / "section.png",
                       dir / "deflection.csv",
                       dir / "section.json",
                       {},
                       {}};

  std::ostringstream csv;
  csv << "# section at t = " << number(frame.time) << " s through point " << vec_text(plane.point)
      << " m with unit normal n = " << vec_text(plane.n) << "; w along " << vec_text(plane.w)
      << " (deflection axis in the plane), u = w x n = " << vec_text(plane.u)
      << "; u and w in m from the point; killed particles: part killed, polyline -1\n"
      << "body,part,polyline,u_m,w_m,x_m,y_m,z_m\n";
  auto row = [&](const std::string& name, const std::string& part, int line, const Vec3& x) {
    const Vec3 r = x - plane.point;
    csv << name << "," << part << "," << line << "," << number(r.dot(plane.u)) << ","
        << number(r.dot(plane.w)) << "," << number(x.x()) << "," << number(x.y()) << ","
        << number(x.z()) << "\n";
  };
  LineChart chart(o.width, o.height);
  chart.set_title(plane_name(plane) + " at t = " + std::string(when) + " \u00b5s");
  chart.set_x_label("u (mm)");
  chart.set_y_label("w (mm)");
  chart.set_equal_aspect(true);
  const auto field = draw_field(chart, sections, plane, o);
  nlohmann::json json_bodies = nlohmann::json::object();
  std::size_t colour = 0;
  for (const auto& [b, s] : sections) {
    const std::string& name = bodies.names[b];
    std::vector<double> u_mm, w_mm;
    for (std::size_t k = 0; k < s.polylines.size(); ++k) {
      for (const Vec3& x : s.polylines[k].x) {
        row(name, s.polylines[k].part, int(k), x);
        u_mm.push_back(1e3 * (x - plane.point).dot(plane.u));
        w_mm.push_back(1e3 * (x - plane.point).dot(plane.w));
      }
      u_mm.push_back(std::numeric_limits<double>::quiet_NaN()); // breaks the line
      w_mm.push_back(std::numeric_limits<double>::quiet_NaN());
    }
    if (o.u_range)
      clip_polyline_u(u_mm, w_mm, 1e3 * (*o.u_range)[0], 1e3 * (*o.u_range)[1]);
    const Rgb rgb = LineChart::palette(colour++);
    chart.add_series(name, u_mm, w_mm, {rgb, 2.0, false});
    if (!s.killed.empty()) {
      std::vector<double> ku, kw;
      for (const Vec3& x : s.killed) {
        row(name, "killed", -1, x);
        const double u = (x - plane.point).dot(plane.u);
        if (o.u_range && (u < (*o.u_range)[0] || u > (*o.u_range)[1]))
          continue;
        ku.push_back(1e3 * u);
        kw.push_back(1e3 * (x - plane.point).dot(plane.w));
      }
      LineStyle dots{rgb, 0.0, false};
      dots.marker = 2.5;
      chart.add_series(name + " killed", ku, kw, dots);
    }
    result.max_deflection[name] = s.max_deflection;
    json_bodies[name] = {{"max_deflection_m", s.max_deflection}, {"polylines", s.polylines.size()}};
  }
  finish(csv, result.csv);
  chart.write_png(result.png);

  std::ostringstream deflection;
  deflection << "# displacement along w = " << vec_text(plane.w)
             << " averaged in bins of |u| (distance in m from the plane's point along u = "
             << vec_text(plane.u) << ")\nbody,radius_m,deflection_m\n";
  for (const auto& [b, s] : sections)
    for (const auto& [r, w] : s.deflection)
      deflection << bodies.names[b] << "," << number(r) << "," << number(w) << "\n";
  finish(deflection, result.deflection_csv);

  auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  nlohmann::json json = {{"time_s", frame.time},
                         {"plane", {{"point_m", vec(plane.point)}, {"normal", vec(plane.n)}}},
                         {"axis", vec(plane.w)},
                         {"u_axis", vec(plane.u)},
                         {"bodies", json_bodies}};
  if (o.u_range)
    json["u_range_m"] = {(*o.u_range)[0], (*o.u_range)[1]};
  json["field"] = field ? nlohmann::json(o.field) : nlohmann::json(nullptr);
  result.field = field ? o.field : "";
  if (field)
    json["field_range"] = {field->min, field->max};
  std::ostringstream json_out;
  json_out << json.dump(2) << "\n";
  finish(json_out, result.json);
  return result;
}

} // namespace sphfem::post
