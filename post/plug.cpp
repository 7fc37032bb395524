#include "post/plug.hpp"

#include "post/frames.hpp"

#include "post/line_chart.hpp"
#include "post/post.hpp"
#include "solver/core/error.hpp"
#include "solver/fem/hex8.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/model_h5.hpp"

#include <nlohmann/json.hpp>

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

namespace sphfem::post {

namespace fs = std::filesystem;

namespace {

// Everything of one frame the fragment search needs, for all bodies.
struct Frame {
  std::vector<Vec3> x_p, v_p;
  std::vector<double> m_p;
  std::vector<int> body_p;
  std::vector<char> killed_p;
  std::vector<Vec3> x_n, v_n;
  std::vector<Hex> hex_e;
  std::vector<double> m_e;
  std::vector<int> body_e;
  std::vector<char> eroded_e;
};

Vec3 tuple3(vtkDataArray* a, vtkIdType i) {
  const double* t = a->GetTuple3(i);
  return {t[0], t[1], t[2]};
}

Frame read_frame(const FrameFiles& files) {
  Frame f;
  if (!files.particles.empty()) {
    const auto grid = read_vtu(files.particles);
    const vtkIdType n = grid->GetNumberOfPoints();
    auto* pd = grid->GetPointData();
    auto* v = frame_array(pd, "velocity", 3, n, files.particles);
    auto* m = frame_array(pd, "mass", 1, n, files.particles);
    auto* body = frame_array(pd, "body_id", 1, n, files.particles);
    auto* killed = frame_array(pd, "killed", 1, n, files.particles, false);
    for (vtkIdType i = 0; i < n; ++i) {
      double x[3];
      grid->GetPoint(i, x);
      f.x_p.emplace_back(x[0], x[1], x[2]);
      f.v_p.push_back(tuple3(v, i));
      f.m_p.push_back(m->GetComponent(i, 0));
      f.body_p.push_back(int(body->GetComponent(i, 0)));
      f.killed_p.push_back(killed && killed->GetComponent(i, 0) != 0);
    }
  }
  if (!files.elements.empty()) {
    const auto grid = read_vtu(files.elements);
    const vtkIdType n = grid->GetNumberOfPoints(), ne = grid->GetNumberOfCells();
    auto* v = frame_array(grid->GetPointData(), "velocity", 3, n, files.elements);
    auto* cd = grid->GetCellData();
    auto* density = frame_array(cd, "density", 1, ne, files.elements);
    auto* body = frame_array(cd, "body_id", 1, ne, files.elements);
    auto* eroded = frame_array(cd, "eroded", 1, ne, files.elements, false);
    for (vtkIdType i = 0; i < n; ++i) {
      double x[3];
      grid->GetPoint(i, x);
      f.x_n.emplace_back(x[0], x[1], x[2]);
      f.v_n.push_back(tuple3(v, i));
    }
    vtkNew<vtkIdList> ids;
    for (vtkIdType k = 0; k < ne; ++k) {
      SPHFEM_CHECK(grid->GetCellType(k) == VTK_HEXAHEDRON, files.elements.string(), ": cell ", k,
                   " is not a hexahedron");
      grid->GetCellPoints(k, ids);
      Hex hex;
      HexPoints x;
      for (int a = 0; a < 8; ++a) {
        hex[a] = Index(ids->GetId(a));
        x[a] = f.x_n[hex[a]];
      }
      f.hex_e.push_back(hex);
      f.m_e.push_back(density->GetComponent(k, 0) * hex8_gradient(x).volume);
      f.body_e.push_back(int(body->GetComponent(k, 0)));
      f.eroded_e.push_back(eroded && eroded->GetComponent(k, 0) != 0);
    }
  }
  return f;
}

// The target body's part of a frame (all nodes kept: elements index them).
FragmentSource select_body(const Frame& f, int body) {
  FragmentSource s;
  for (std::size_t i = 0; i < f.x_p.size(); ++i)
    if (f.body_p[i] == body) {
      s.x_p.push_back(f.x_p[i]);
      s.v_p.push_back(f.v_p[i]);
      s.m_p.push_back(f.m_p[i]);
      s.killed_p.push_back(f.killed_p[i]);
    }
  s.x_n = f.x_n;
  s.v_n = f.v_n;
  for (std::size_t k = 0; k < f.hex_e.size(); ++k)
    if (f.body_e[k] == body) {
      s.hex_e.push_back(f.hex_e[k]);
      s.m_e.push_back(f.m_e[k]);
      s.eroded_e.push_back(f.eroded_e[k]);
    }
  return s;
}

// Each fragment's travel along `axis`: Σ m (x − x0) / Σ m over its particles and elements,
// `start` being the same body in the first frame (same particles, elements and nodes).
void set_travel(const FragmentSource& start, const FragmentSource& now, FragmentSet& set,
                const Vec3& axis) {
  std::vector<double> moved(set.fragments.size(), 0.0), mass(set.fragments.size(), 0.0);
  for (std::size_t i = 0; i < now.x_p.size(); ++i)
    if (const int f = set.fragment_p[i]; f >= 0) {
      moved[f] += now.m_p[i] * (now.x_p[i] - start.x_p[i]).dot(axis);
      mass[f] += now.m_p[i];
    }
  for (std::size_t k = 0; k < now.hex_e.size(); ++k)
    if (const int f = set.fragment_e[k]; f >= 0) {
      Vec3 shift = Vec3::Zero();
      for (Index n : now.hex_e[k])
        shift += (now.x_n[n] - start.x_n[n]) / 8.0;
      moved[f] += now.m_e[k] * shift.dot(axis);
      mass[f] += now.m_e[k];
    }
  for (std::size_t f = 0; f < set.fragments.size(); ++f)
    set.fragments[f].travel = mass[f] > 0 ? moved[f] / mass[f] : 0.0;
}

// The frame-wide masks of the target's pieces outside its main fragment (PlugResult::detached_*).
void detached(const Frame& f, int body, const FragmentSet& set, PlugResult& r) {
  r.detached_p.assign(f.x_p.size(), 0);
  r.detached_e.assign(f.hex_e.size(), 0);
  std::size_t j = 0;
  for (std::size_t i = 0; i < f.x_p.size(); ++i)
    if (f.body_p[i] == body)
      r.detached_p[i] = set.fragment_p[j++] != 0;
  j = 0;
  for (std::size_t k = 0; k < f.hex_e.size(); ++k)
    if (f.body_e[k] == body)
      r.detached_e[k] = set.fragment_e[j++] != 0;
}

// Momentum of each body (element momentum = ρ V × mean node velocity), kg m/s.
std::map<int, Vec3> momentum_by_body(const Frame& f) {
  std::map<int, Vec3> p;
  for (std::size_t i = 0; i < f.x_p.size(); ++i)
    p.try_emplace(f.body_p[i], Vec3::Zero()).first->second += f.m_p[i] * f.v_p[i];
  for (std::size_t k = 0; k < f.hex_e.size(); ++k)
    for (Index n : f.hex_e[k])
      p.try_emplace(f.body_e[k], Vec3::Zero()).first->second += f.m_e[k] / 8 * f.v_n[n];
  return p;
}

// Total momentum of every body but `body`, kg m/s.
Vec3 momentum_of_others(const Frame& f, int body) {
  Vec3 total = Vec3::Zero();
  for (const auto& [b, p] : momentum_by_body(f))
    if (b != body)
      total += p;
  return total;
}

// The other body with the largest momentum along the axis in the first frame (the projectile),
// -1 if none moves along it.
int leading_body(const Frame& first, int target, const Vec3& axis) {
  int leader = -1;
  double largest = 0;
  for (const auto& [b, p] : momentum_by_body(first))
    if (b != target && p.dot(axis) > largest) {
      largest = p.dot(axis);
      leader = b;
    }
  return leader;
}

// A body's particles and element nodes in a frame.
std::vector<Vec3> points_of(const Frame& f, int body) {
  std::vector<Vec3> points;
  for (std::size_t i = 0; i < f.x_p.size(); ++i)
    if (f.body_p[i] == body)
      points.push_back(f.x_p[i]);
  for (std::size_t k = 0; k < f.hex_e.size(); ++k)
    if (f.body_e[k] == body)
      for (Index n : f.hex_e[k])
        points.push_back(f.x_n[n]);
  return points;
}

// Whether the leading other body has passed through the target (path_open, fragments.hpp), the
// rear face being the target's in the first frame.
bool passed_through(const Frame& first, const Frame& now, int target, const Vec3& axis,
                    const FragmentSource& source, const FragmentSet& set) {
  const int leader = leading_body(first, target, axis);
  const std::vector<Vec3> target_points = points_of(first, target);
  if (leader < 0 || target_points.empty())
    return false;
  double rear = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : target_points)
    rear = std::max(rear, x.dot(axis));
  return path_open(points_of(now, leader), source, set, rear, axis);
}

int target_body(const Model& model, const std::string& name, const fs::path& file) {
  std::string names;
  for (const auto& b : model.body_names)
    names += (names.empty() ? "" : ", ") + b;
  if (!name.empty()) {
    for (std::size_t b = 0; b < model.body_names.size(); ++b)
      if (model.body_names[b] == name)
        return int(b);
    throw Error("--body " + name + ": no such body in " + file.string() + " (bodies: " + names +
                ")");
  }
  std::vector<char> has(model.body_names.size(), 0);
  for (int b : model.body_p)
    has[b] = 1;
  std::vector<int> with;
  std::string with_names;
  for (std::size_t b = 0; b < has.size(); ++b)
    if (has[b]) {
      with.push_back(int(b));
      with_names += (with_names.empty() ? "" : ", ") + model.body_names[b];
    }
  SPHFEM_CHECK(!with.empty(), file.string(),
               ": no body has particles; choose the target with --body (bodies: ", names, ")");
  SPHFEM_CHECK(with.size() == 1, file.string(), ": several bodies have particles (", with_names,
               "); choose the target with --body");
  return with[0];
}

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

std::string three_digits(double v) { // for labels: 6.69, 0.0785, 12.1
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

// "x", "-z", … for a global axis, else "".
std::string axis_name(const Vec3& a) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(a[k]) - 1) < 1e-12)
      return std::string(a[k] < 0 ? "-" : "") + "xyz"[k];
  return "";
}

void write_chart(const PlugResult& r, const FragmentSource& source, const FragmentSet& set,
                 double spacing, const PlugOptions& o) {
  // The drawing plane contains the impact axis; "up" is the axis turned towards its dominant
  // global direction, so a projectile along −z still comes from the top.
  Eigen::Index k = 0;
  r.impact_axis.cwiseAbs().maxCoeff(&k);
  const Vec3 up = r.impact_axis[k] < 0 ? Vec3(-r.impact_axis) : r.impact_axis;
  const Vec3 lateral = lateral_direction(up);
  const auto outlines = fragment_outlines(source, set, lateral, up, spacing);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Series {
    std::string label;
    LineStyle style;
    std::vector<double> x, y;
  };
  std::vector<Series> series(3);
  const int others = int(outlines.size()) - 1 - (r.plug >= 0);
  series[0] = {"main fragment, " +
                   three_digits(r.fragments.empty() ? 0 : r.fragments[0].mass * 1e3) + " g",
               {LineChart::palette(0), 2.0, false},
               {},
               {}};
  series[1] = {r.plug < 0 ? ""
                          : "plug, " + three_digits(r.fragments[r.plug].mass * 1e3) + " g, " +
                                three_digits(r.fragments[r.plug].diameter * 1e3) + " mm across",
               {LineChart::palette(1), 3.0, false},
               {},
               {}};
  series[2] = {std::to_string(others) + " other fragment" + (others == 1 ? "" : "s"),
               {{110, 110, 110}, 1.2, false},
               {},
               {}};
  const double inf = std::numeric_limits<double>::infinity();
  double lo_x = inf, hi_x = -inf, lo_y = inf, hi_y = -inf;
  for (std::size_t f = 0; f < outlines.size(); ++f) {
    Series& s = series[f == 0 ? 0 : int(f) == r.plug ? 1 : 2];
    const auto& hull = outlines[f];
    for (std::size_t i = 0; i <= hull.size(); ++i) { // closed
      const Point2 p = hull[i % hull.size()] * 1e3;
      s.x.push_back(p.x());
      s.y.push_back(p.y());
      lo_x = std::min(lo_x, p.x()), hi_x = std::max(hi_x, p.x());
      lo_y = std::min(lo_y, p.y()), hi_y = std::max(hi_y, p.y());
    }
    s.x.push_back(nan); // a break before the next outline
    s.y.push_back(nan);
  }
  if (!outlines.empty()) {
    // Equal scales on both axes: two isolated points (drawn as nothing) widen the short side.
    const auto area = LineChart::plot_area(o.width, o.height);
    const double w = area.right - area.left, h = area.bottom - area.top;
    const double mm_per_px = std::max((hi_x - lo_x) / w, (hi_y - lo_y) / h) * 1.05;
    const double cx = (lo_x + hi_x) / 2, cy = (lo_y + hi_y) / 2;
    series[0].x.insert(series[0].x.end(), {cx - mm_per_px * w / 2, nan, cx + mm_per_px * w / 2});
    series[0].y.insert(series[0].y.end(), {cy - mm_per_px * h / 2, nan, cy + mm_per_px * h / 2});
  }

  LineChart chart(o.width, o.height);
  char title[160];
  if (r.plug >= 0)
    std::snprintf(title, sizeof title, "t = %.1f \u00b5s: plug at %.0f m/s along the impact axis",
                  r.time * 1e6, r.fragments[r.plug].velocity.dot(r.impact_axis));
  else
    std::snprintf(title, sizeof title, "t = %.1f \u00b5s: no plug", r.time * 1e6);
  chart.set_title(title);
  const std::string x_name = axis_name(lateral), y_name = axis_name(up);
  chart.set_x_label((x_name.empty() ? "lateral" : x_name) + " (mm)");
  chart.set_y_label((y_name.empty() ? "along the impact axis" : y_name) + " (mm)");
  // Others first, so the main fragment and the plug are drawn over them.
  for (int s : {2, 0, 1})
    if (!series[s].x.empty())
      chart.add_series(series[s].label, series[s].x, series[s].y, series[s].style);
  chart.write_png(r.png);
}

} // namespace

PlugResult write_plug(const PlugOptions& o) {
  // Everything is read and checked before anything is written.
  const fs::path pvd = o.run / "results.pvd", model_file = o.run / "model.h5";
  SPHFEM_CHECK(fs::is_directory(o.run), o.run.string(), ": no such run folder");
  SPHFEM_CHECK(fs::is_regular_file(pvd), o.run.string(),
               ": not a run folder (no results.pvd; run `sphfem solve` first)");
  SPHFEM_CHECK(fs::is_regular_file(model_file), o.run.string(), ": no model.h5");
  SPHFEM_CHECK(std::isfinite(o.connect) && o.connect > 0, "--connect ", o.connect,
               ": expected a positive factor of the lattice spacing");
  (void)LineChart(o.width, o.height); // checks the size
  const Model model = read_model_h5(model_file);
  const int body = target_body(model, o.body, model_file);
  const bool has_particles = std::count(model.body_p.begin(), model.body_p.end(), body) > 0;
  const bool has_elements = std::count(model.body_e.begin(), model.body_e.end(), body) > 0;
  SPHFEM_CHECK(has_particles || has_elements, "--body ", model.body_names[body],
               ": has neither particles nor elements");
  const double spacing = has_particles ? model.spacing_b[body] : 0;

  const auto frames = frame_files(pvd);
  const std::size_t chosen = nearest_frame(frames, o.time);
  const Frame first = read_frame(frames[0]);
  const Frame frame = chosen == 0 ? first : read_frame(frames[chosen]);
  const FragmentSource source = select_body(frame, body);
  SPHFEM_CHECK(source.x_p.size() + source.hex_e.size() > 0, frames[chosen].particles.string(),
               ": no particles or elements of body ", model.body_names[body]);

  PlugResult r;
  r.body = model.body_names[body];
  r.time = frames[chosen].time;
  const Vec3 p0 = momentum_of_others(first, body);
  std::string axis_from = "+z: the other bodies have no momentum in the first frame";
  if (p0.norm() > 0) {
    r.impact_axis = p0.normalized();
    axis_from = "momentum of the other bodies at t = " + number(frames[0].time) + " s";
  }
  const double reach = o.connect * spacing;
  FragmentSet set = find_fragments(source, reach, spacing, r.impact_axis);
  r.main = set.fragments.empty() ? -1 : 0;
  r.plug = find_plug(set.fragments, r.impact_axis, o.min_pieces);
  r.passed_through = passed_through(first, frame, body, r.impact_axis, source, set);
  r.debris_mass = set.debris_mass;
  set_travel(select_body(first, body), source, set, r.impact_axis);
  r.fragments = set.fragments;
  detached(frame, body, set, r);

  const fs::path dir = o.out_dir.empty() ? o.run / "post" : o.out_dir;
  std::error_code failed;
  fs::create_directories(dir, failed);
  SPHFEM_CHECK(!failed, dir.string(), ": cannot create the folder: ", failed.message());
  r.json = dir / "plug.json";
  r.csv = dir / "fragments.csv";
  r.png = dir / "plug.png";

  auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  nlohmann::json j;
  j["time_s"] = r.time;
  j["body"] = model.body_names[body];
  j["impact_axis"] = vec(r.impact_axis);
  j["impact_axis_from"] = axis_from;
  j["spacing_m"] = spacing;
  j["connect_distance_m"] = reach;
  j["outline"] = "convex hull of the points projected on a plane containing the impact axis";
  j["debris"] = {{"particles", set.debris_particles},
                 {"elements", set.debris_elements},
                 {"mass_kg", set.debris_mass}};
  j["fragments"] = nlohmann::json::array();
  for (const Fragment& f : r.fragments)
    j["fragments"].push_back({{"mass_kg", f.mass},
                              {"com_m", vec(f.com)},
                              {"velocity_m_per_s", vec(f.velocity)},
                              {"axial_velocity_m_per_s", f.velocity.dot(r.impact_axis)},
                              {"particles", f.particles},
                              {"elements", f.elements},
                              {"diameter_m", f.diameter},
                              {"thickness_m", f.thickness},
                              {"travel_m", f.travel}});
  j["main"] = r.main < 0 ? nlohmann::json(nullptr) : nlohmann::json(r.main);
  j["plug"] = r.plug < 0 ? nlohmann::json(nullptr) : nlohmann::json(r.plug);
  j["projectile_passed_through"] = r.passed_through;
  write_text_atomically(r.json, j.dump(2) + "\n");

  std::ostringstream csv;
  csv << "fragment,role,mass [kg],com_x [m],com_y [m],com_z [m],vx [m/s],vy [m/s],vz [m/s],"
         "v_axial [m/s],particles,elements,diameter [m],thickness [m],travel [m]\n";
  for (std::size_t f = 0; f < r.fragments.size(); ++f) {
    const Fragment& x = r.fragments[f];
    csv << f << ","
        << (int(f) == r.main   ? "main"
            : int(f) == r.plug ? "plug"
                               : "")
        << "," << number(x.mass);
    for (const Vec3* v : {&x.com, &x.velocity})
      for (int c = 0; c < 3; ++c)
        csv << "," << number((*v)[c]);
    csv << "," << number(x.velocity.dot(r.impact_axis)) << "," << x.particles << "," << x.elements
        << "," << number(x.diameter) << "," << number(x.thickness) << "," << number(x.travel)
        << "\n";
  }
  write_text_atomically(r.csv, csv.str());

  write_chart(r, source, set, spacing, o);
  return r;
}

} // namespace sphfem::post
