#include "post/report.hpp"

#include "post/history_plot.hpp"
#include "post/line_chart.hpp"
#include "post/plug.hpp"
#include "post/post.hpp"
#include "post/section.hpp"
#include "post/text.hpp"
#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/model_h5.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

namespace sphfem::post {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (char c : line) {
    if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted) {
      cells.push_back(cell);
      cell.clear();
    } else if (c != '\r')
      cell += c;
  }
  cells.push_back(cell);
  return cells;
}

// The value at a dotted path ("bodies.bar.com_velocity.2") of a JSON document.
const nlohmann::json* at_path(const nlohmann::json& doc, const std::string& path) {
  const nlohmann::json* node = &doc;
  std::istringstream keys(path);
  for (std::string key; std::getline(keys, key, '.');) {
    std::size_t index = 0; // an index too large for size_t is absent, as one past the end
    const char* end = key.data() + key.size();
    if (node->is_object() && node->contains(key))
      node = &(*node)[key];
    else if (const auto [stop, error] = std::from_chars(key.data(), end, index);
             node->is_array() && !key.empty() && error == std::errc{} && stop == end &&
             index < node->size())
      node = &(*node)[index];
    else
      return nullptr;
  }
  return node;
}

// summary.json as the report reads it: an object whose keys used here have the types `solve`
// writes (solver/time/run.cpp), else an Error naming the file and the key, before anything is
// written (JSON's own type errors would name neither).
void check_summary(const nlohmann::json& summary, const fs::path& file) {
  using Json = nlohmann::json;
  const auto fail = [&](const std::string& key, const std::string& expected, const Json* got) {
    throw Error(file.string() + ": " + key + ": expected " + expected + ", got " +
                (got ? std::string(got->type_name()) : "nothing (missing key)"));
  };
  // `in`'s `key` (at `path`) if `ok` holds for it; missing: nullptr, or an Error if `required`.
  const auto check = [&](const Json& in, const std::string& path, const std::string& key,
                         bool required, const std::string& expected,
                         const auto& ok) -> const Json* {
    const auto it = in.find(key);
    if (it == in.end() ? required : !ok(*it))
      fail(path + key, expected, it == in.end() ? nullptr : &*it);
    return it == in.end() ? nullptr : &*it;
  };
  const auto number = [](const Json& j) { return j.is_number(); };
  const auto string = [](const Json& j) { return j.is_string(); };
  const auto object = [](const Json& j) { return j.is_object(); };
  const auto numbers = [](std::size_t n) {
    return [n](const Json& j) {
      return j.is_array() && j.size() == n &&
             std::all_of(j.begin(), j.end(), [](const Json& v) { return v.is_number(); });
    };
  };
  if (!summary.is_object())
    fail("(top level)", "an object (the run's summary)", &summary);
  check(summary, "", "case", false, "a string", string);
  check(summary, "", "case_file", false, "a string", string);
  for (const char* key :
       {"time", "steps", "wall_s", "threads", "entity_steps_per_s", "momentum_drift"})
    check(summary, "", key, false, "a number", number);
  const Json* counts = check(summary, "", "counts", true, "an object", object);
  for (const char* key : {"particles", "nodes", "elements"})
    check(*counts, "counts.", key, false, "a number", number);
  const Json* energy = check(summary, "", "energy", true, "an object", object);
  check(*energy, "energy.", "balance_error", false, "a number", number);
  if (const Json* bodies = check(summary, "", "bodies", false, "an object", object))
    for (const auto& [name, body] : bodies->items()) {
      const std::string path = "bodies." + name;
      if (!body.is_object())
        fail(path, "an object", &body);
      check(body, path + ".", "com_velocity", true, "3 numbers [vx, vy, vz]", numbers(3));
      for (const char* key :
           {"mass", "kinetic_energy", "internal_energy", "killed_particles", "eroded_elements"})
        check(body, path + ".", key, false, "a number", number);
    }
  if (const Json* plane = check(summary, "", "section_plane", false, "an object", object)) {
    for (const char* key : {"point", "normal"})
      check(*plane, "section_plane.", key, true, "3 numbers [x, y, z]", numbers(3));
    check(*plane, "section_plane.", "u_range", false, "2 numbers [u0, u1]", numbers(2));
  }
}

// Whether a reference row's `when` (path=value) holds for this run's summary.
bool applies(const ReferenceRow& row, const nlohmann::json& summary) {
  if (row.when.empty())
    return true;
  const auto equals = row.when.find('=');
  const nlohmann::json* node = at_path(summary, row.when.substr(0, equals));
  const std::string wanted = row.when.substr(equals + 1);
  if (node && node->is_string())
    return node->get<std::string>() == wanted;
  if (!node || !node->is_number())
    return false;
  char* end = nullptr;
  const double v = std::strtod(wanted.c_str(), &end);
  return end != wanted.c_str() && *end == '\0' &&
         std::abs(node->get<double>() - v) <= 1e-9 * std::max(std::abs(v), 1e-300);
}

// A reference quantity's value in this run: a path into summary.json, or
// history.<column>.min|max|last of history.csv (the column's own dots kept).
std::optional<double> value_of(const nlohmann::json& summary, const History& history,
                               const std::string& quantity) {
  if (quantity.rfind("history.", 0) == 0) {
    const auto dot = quantity.rfind('.');
    const std::string column = quantity.substr(8, dot - 8), statistic = quantity.substr(dot + 1);
    if (dot <= 8 || !history.values.count(column) || history[column].empty())
      return std::nullopt;
    const auto& v = history[column];
    if (statistic == "min")
      return *std::min_element(v.begin(), v.end());
    if (statistic == "max")
      return *std::max_element(v.begin(), v.end());
    if (statistic == "last")
      return v.back();
    return std::nullopt;
  }
  const nlohmann::json* node = at_path(summary, quantity);
  return node && node->is_number() ? std::optional<double>(node->get<double>()) : std::nullopt;
}

struct Page {
  std::ostringstream html;
  std::vector<fs::path> images;

  void figure(const fs::path& png, const std::string& caption) {
    images.push_back(png);
    html << "<figure><img alt=\"" << escape_html(caption) << "\" src=\"data:image/png;base64,"
         << base64(slurp(png)) << "\"><figcaption>" << escape_html(caption)
         << "</figcaption></figure>\n";
  }
};

// A report chart against time: 900 × 560 px, the title and y label given, x in µs; `t` gets
// history.csv's time column in µs.
LineChart time_chart(const History& h, const std::string& title, const std::string& y_label,
                     std::vector<double>& t) {
  LineChart chart(900, 560);
  chart.set_title(title);
  chart.set_x_label("time (\u00b5s)");
  chart.set_y_label(y_label);
  t = h["time"];
  for (double& v : t)
    v *= 1e6;
  return chart;
}

// All energy columns of history.csv on one chart, J against µs.
fs::path energy_chart(const History& h, const fs::path& dir) {
  std::vector<double> t;
  LineChart chart = time_chart(h, "Energy balance", "energy (J)", t);
  std::size_t k = 0;
  for (const auto& c : h.columns)
    if (c.rfind("energy.", 0) == 0)
      chart.add_series(c.substr(7), t, h[c],
                       {c == "energy.total" ? Rgb{0, 0, 0} : LineChart::palette(k++),
                        c == "energy.total" ? 2.5 : 2.0, c == "energy.external_work"});
  const fs::path png = dir / "energy.png";
  chart.write_png(png);
  return png;
}

// Where the energy went: each body's kinetic (solid) and internal (dashed) energy, J against µs,
// from history.csv's body.<name>.kinetic|internal (runs before those columns have none: no chart).
std::optional<fs::path> body_energy_chart(const History& h, const std::vector<std::string>& bodies,
                                          const fs::path& dir) {
  for (const auto& b : bodies)
    if (!h.values.count("body." + b + ".kinetic") || !h.values.count("body." + b + ".internal"))
      return std::nullopt;
  std::vector<double> t;
  LineChart chart = time_chart(h, "Energy by body", "energy (J)", t);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const std::string c = "body." + bodies[b];
    chart.add_series(bodies[b] + " kinetic", t, h[c + ".kinetic"],
                     {LineChart::palette(b), 2.0, false});
    chart.add_series(bodies[b] + " internal", t, h[c + ".internal"],
                     {LineChart::palette(b), 2.0, true});
  }
  const fs::path png = dir / "energy_bodies.png";
  chart.write_png(png);
  return png;
}

// Every body's centre-of-mass velocity component along `axis` (x, y or z).
fs::path velocity_chart(const History& h, const std::vector<std::string>& bodies, char axis,
                        const fs::path& dir) {
  std::vector<double> t;
  LineChart chart = time_chart(h, std::string("Body centre-of-mass velocity v") + axis,
                               std::string("v") + axis + " (m/s)", t);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    chart.add_series(bodies[b], t, h["body." + bodies[b] + ".v" + axis],
                     {LineChart::palette(b), 2.0, false});
  const fs::path png = dir / (std::string("velocity_v") + axis + ".png");
  chart.write_png(png);
  return png;
}

// The perforation results DESIGN.md puts under summary.json's "results": perforated (a plug
// separated, or the projectile's nose is beyond the target's rear face with its path open), the
// residual velocities of the projectile (the other body with the largest initial momentum along the
// impact axis) and of the plug along that axis, 0 without perforation, and the plug's mass and
// size.
nlohmann::json perforation_results(const nlohmann::json& summary, const History& history,
                                   const PlugResult& r, const std::string& target) {
  const Vec3& axis = r.impact_axis;
  std::string projectile;
  double largest = 0;
  for (const auto& [name, body] : summary["bodies"].items()) {
    const std::string v = "body." + name + ".v";
    if (name == target || !history.values.count(v + "z") || history[v + "z"].empty())
      continue;
    const Vec3 v0(history[v + "x"][0], history[v + "y"][0], history[v + "z"][0]);
    const double momentum = body.value("mass", 0.0) * v0.dot(axis);
    if (momentum > largest) {
      largest = momentum;
      projectile = name;
    }
  }
  const bool perforated = r.plug >= 0 || r.passed_through;
  nlohmann::json out;
  out["perforated"] = perforated;
  out["target"] = target;
  out["projectile"] = projectile.empty() ? nlohmann::json() : nlohmann::json(projectile);
  out["impact_axis"] = {axis.x(), axis.y(), axis.z()};
  Vec3 projectile_velocity = Vec3::Zero();
  if (perforated && !projectile.empty()) {
    const auto& v = summary["bodies"][projectile]["com_velocity"];
    projectile_velocity = Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  }
  const Fragment plug = r.plug >= 0 ? r.fragments[r.plug] : Fragment{};
  out["residual_velocity"] = {{"projectile", projectile_velocity.dot(axis)},
                              {"plug", r.plug >= 0 ? plug.velocity.dot(axis) : 0.0}};
  // Where they go: each one's speed, its angle from the impact axis (its deviation from the
  // line of flight) and, for a plate scene, from the plate's normal −z (an oblique shot's
  // obliquity in, its exit angle out); null when it does not leave.
  const Vec3 normal = -Vec3::UnitZ();
  const auto degrees = [](const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 /
           std::numbers::pi;
  };
  // A symmetric model's bodies are parts of whole ones, whose velocities have no component
  // across the symmetry planes: a quarter's across x = 0 and y = 0, a half's across y = 0.
  const bool plate = summary.contains("scene");
  const std::string symmetry =
      plate ? summary["scene"].value("symmetry", std::string("none")) : std::string("none");
  const auto whole = [&symmetry](Vec3 v) {
    if (symmetry == "quarter")
      v.x() = 0;
    if (symmetry == "quarter" || symmetry == "half")
      v.y() = 0;
    return v;
  };
  for (const auto& [name, v] : {std::pair{"projectile", whole(projectile_velocity)},
                                std::pair{"plug", whole(plug.velocity)}}) {
    const bool leaves = perforated && v.norm() > 0 && (std::string(name) != "plug" || r.plug >= 0);
    out["speed"][name] = leaves ? v.norm() : 0.0;
    out["deviation_deg"][name] = leaves ? nlohmann::json(degrees(v, axis)) : nlohmann::json();
    if (plate)
      out["angle_from_normal_deg"][name] =
          leaves ? nlohmann::json(degrees(v, normal)) : nlohmann::json();
  }
  out["plug"] = {{"mass", plug.mass}, {"diameter", plug.diameter}, {"thickness", plug.thickness}};
  out["time"] = r.time;
  out["units"] = {
      {"velocity", "m/s"}, {"mass", "kg"}, {"length", "m"}, {"time", "s"}, {"angle", "degrees"}};
  return out;
}

} // namespace

double ReferenceRow::relative_error() const {
  return reference != 0 ? (value - reference) / reference
                        : std::numeric_limits<double>::quiet_NaN();
}

std::string base64(const std::string& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    unsigned v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k)
      out += k <= n ? digits[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::vector<ReferenceRow> read_reference_csv(const fs::path& file) {
  std::ifstream in(file);
  SPHFEM_CHECK(in, file.string(), ": cannot open the reference file");
  std::vector<ReferenceRow> rows;
  std::string line;
  int number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#' || line == "\r")
      continue;
    const auto cells = split_csv_line(line);
    if (!header) {
      SPHFEM_CHECK(cells.size() >= 2 && cells[0] == "quantity" && cells[1] == "value",
                   file.string(), ":", number, ": expected the header quantity,value,unit,source");
      header = true;
      continue;
    }
    ReferenceRow row;
    row.quantity = cells[0];
    try {
      std::size_t used = 0;
      row.reference = std::stod(cells.at(1), &used);
      SPHFEM_CHECK(used == cells[1].size(), "");
    } catch (const std::exception&) {
      throw Error(file.string() + ":" + std::to_string(number) + ": value '" +
                  (cells.size() > 1 ? cells[1] : "") + "' is not a number");
    }
    row.unit = cells.size() > 2 ? cells[2] : "";
    row.source = cells.size() > 3 ? cells[3] : "";
    row.when = cells.size() > 4 ? cells[4] : "";
    SPHFEM_CHECK(row.when.empty() || row.when.find('=') != std::string::npos, file.string(), ":",
                 number, ": when '", row.when, "': expected path=value");
    rows.push_back(row);
  }
  SPHFEM_CHECK(header, file.string(), ": empty (expected the header quantity,value,unit,source)");
  return rows;
}

Report write_report(const ReportOptions& o) {
  const fs::path summary_file = o.run / "summary.json";
  SPHFEM_CHECK(fs::is_regular_file(summary_file), o.run.string(),
               ": not a finished run (no summary.json; run `sphfem solve` first)");
  nlohmann::json summary;
  try {
    summary = nlohmann::json::parse(slurp(summary_file));
  } catch (const std::exception& e) {
    throw Error(summary_file.string() + ": not valid JSON: " + e.what());
  }
  check_summary(summary, summary_file);
  const fs::path history_file = o.run / "history.csv";
  const History history = read_history_csv(history_file);
  SPHFEM_CHECK(history.values.count("time"), history_file.string(), ":1: no time column");
  if (const auto bodies = summary.find("bodies"); bodies != summary.end())
    for (const auto& [name, body] : bodies->items())
      for (const char* axis : {"x", "y", "z"})
        SPHFEM_CHECK(history.values.count("body." + name + ".v" + axis), history_file.string(),
                     ":1: no column body.", name, ".v", axis, " (", summary_file.string(),
                     " lists body ", name, ")");
  fs::path reference_file = o.reference;
  if (reference_file.empty() && summary.contains("case_file")) {
    const fs::path candidate =
        fs::path(summary["case_file"].get<std::string>()).parent_path() / "reference.csv";
    if (fs::is_regular_file(candidate))
      reference_file = candidate;
  }
  Report report;
  std::size_t other_runs = 0; // reference rows for other runs (their `when` does not hold)
  if (!reference_file.empty())
    for (const ReferenceRow& r : read_reference_csv(reference_file)) {
      if (applies(r, summary))
        report.references.push_back(r);
      else
        ++other_runs;
    }

  const fs::path dir = o.out_dir.empty() ? o.run / "report" : o.out_dir;
  std::error_code failed;
  fs::create_directories(dir, failed);
  SPHFEM_CHECK(!failed, dir.string(), ": cannot create the folder: ", failed.message());

  std::vector<std::string> bodies;
  for (const auto& [name, body] : summary["bodies"].items())
    bodies.push_back(name);
  const std::string name = summary.value("case", std::string("run"));
  Page page;
  auto& h = page.html;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>sphfem report: "
    << escape_html(name)
    << "</title>\n<style>body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}"
       "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px "
       "8px;text-align:right}th{background:#eee}td:first-child,th:first-child{text-align:left}"
       "figure{margin:1em 0}img{max-width:100%}figcaption{color:#555;font-size:90%}"
       ".bad{color:#b00}</style></head><body>\n";
  h << "<h1>sphfem report: " << escape_html(name) << "</h1>\n";

  h << "<h2>Run</h2>\n<table><tr><th>quantity</th><th>value</th></tr>\n";
  auto row = [&](const std::string& what, const std::string& value) {
    h << "<tr><td>" << escape_html(what) << "</td><td>" << escape_html(value) << "</td></tr>\n";
  };
  if (summary.contains("case_file"))
    row("case file", summary["case_file"].get<std::string>());
  row("simulated time (s)", format("%.6g", summary.value("time", 0.0)));
  row("steps", std::to_string(summary.value("steps", 0LL)));
  for (const char* count : {"particles", "nodes", "elements"})
    row(std::string(count), std::to_string(summary["counts"].value(count, 0LL)));
  row("wall time (s)", format("%.3f", summary.value("wall_s", 0.0)));
  row("threads", std::to_string(summary.value("threads", 0)));
  row("entity-steps/s", format("%.4g", summary.value("entity_steps_per_s", 0.0)));
  row("energy balance error", format("%.3g", summary["energy"].value("balance_error", 0.0)));
  row("momentum drift", format("%.3g", summary.value("momentum_drift", 0.0)));
  h << "</table>\n";

  h << "<h2>Energy</h2>\n";
  page.figure(energy_chart(history, dir),
              "Energies (J): kinetic, internal, hourglass, contact, eroded, external work (dashed) "
              "and their total; the balance error is |total − W_ext − E_0| / scale.");
  if (const auto png = body_energy_chart(history, bodies, dir))
    page.figure(*png, "Each body's kinetic (solid) and internal energy (dashed, J: stress work "
                      "and viscous heating; the attachment's stored energy belongs to no body).");

  h << "<h2>Bodies</h2>\n<table><tr><th>body</th><th>mass (kg)</th><th>vx (m/s)</th><th>vy "
       "(m/s)</th><th>vz (m/s)</th><th>kinetic energy (J)</th><th>internal energy (J)</th>"
       "<th>killed particles</th><th>eroded elements</th></tr>\n";
  for (const auto& b : bodies) {
    const auto& s = summary["bodies"][b];
    h << "<tr><td>" << escape_html(b) << "</td><td>" << format("%.6g", s.value("mass", 0.0))
      << "</td>";
    for (int k = 0; k < 3; ++k)
      h << "<td>" << format("%.4g", s["com_velocity"][k].get<double>()) << "</td>";
    for (const char* energy : {"kinetic_energy", "internal_energy"})
      h << "<td>" << (s.contains(energy) ? format("%.4g", s[energy].get<double>()) : "") << "</td>";
    h << "<td>" << s.value("killed_particles", 0) << "</td><td>" << s.value("eroded_elements", 0)
      << "</td></tr>\n";
  }
  h << "</table>\n<p>Residual velocities: the centre-of-mass velocities at the end of the "
       "run.</p>\n";
  for (char axis : {'x', 'y', 'z'}) {
    bool moving = false;
    for (const auto& b : bodies)
      for (double v : history["body." + b + ".v" + axis])
        moving = moving || std::abs(v) > 1e-9;
    if (moving)
      page.figure(velocity_chart(history, bodies, axis, dir),
                  std::string("Centre-of-mass velocity v") + axis + " of each body (m/s).");
  }

  // The fragments first: the section leaves the pieces that left the target out of its deflection.
  std::optional<PlugResult> fragments;
  std::string no_fragments;
  try {
    PlugOptions plug;
    plug.run = o.run;
    plug.out_dir = dir;
    fragments = write_plug(plug);
    summary["results"] = perforation_results(summary, history, *fragments, fragments->body);
    write_text_atomically(summary_file, summary.dump(2) + "\n");
  } catch (const std::exception& e) {
    report.skipped.push_back(std::string("plug: ") + e.what());
    no_fragments = e.what();
  }

  h << "<h2>Section</h2>\n";
  try {
    const Model model = read_model_h5(o.run / "model.h5");
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (const auto* points : {&model.x_n, &model.x_p})
      for (const Vec3& x : *points) {
        low = low.cwiseMin(x);
        high = high.cwiseMax(x);
      }
    SectionOptions section;
    section.run = o.run;
    if (fragments) {
      section.leave_out_p = fragments->detached_p;
      section.leave_out_e = fragments->detached_e;
    }
    section.point = 0.5 * (low + high);
    section.normal = Vec3::UnitY();
    section.out_dir = dir;
    std::string where = "through the model's centre, normal y";
    if (const auto plane = summary.find("section_plane"); plane != summary.end()) {
      const auto vec = [](const nlohmann::json& v) {
        return Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
      };
      section.point = vec((*plane)["point"]);
      section.normal = vec((*plane)["normal"]);
      if (const auto range = plane->find("u_range"); range != plane->end())
        section.u_range =
            std::array<double, 2>{(*range)[0].get<double>(), (*range)[1].get<double>()};
      where = "through (" + format("%.4g", section.point.x() * 1e3) + ", " +
              format("%.4g", section.point.y() * 1e3) + ", " +
              format("%.4g", section.point.z() * 1e3) + ") mm, normal (" +
              format("%.3g", section.normal.x()) + ", " + format("%.3g", section.normal.y()) +
              ", " + format("%.3g", section.normal.z()) + "), the case's output.section";
      if (section.u_range)
        where += ", drawn for " + format("%.4g", (*section.u_range)[0] * 1e3) + " ≤ u ≤ " +
                 format("%.4g", (*section.u_range)[1] * 1e3) + " mm";
    }
    const SectionResult cut = write_section(section);
    page.figure(cut.png,
                "Deformed section at t = " + format("%.4g", cut.time * 1e6) + " µs " + where +
                    (cut.field.empty() ? "" : ", coloured by the equivalent plastic strain") +
                    " (section.csv).");
    h << "<p>Largest displacement along the section's w axis (deflection.csv, mm):";
    for (const auto& [body, deflection] : cut.max_deflection)
      h << " " << escape_html(body) << " " << format("%.4g", deflection * 1e3)
        << (fragments && body == fragments->body ? " (the pieces that left it, plug and debris, "
                                                   "left out: the plate's deflection)"
                                                 : "")
        << ";";
    h << " a body that moves freely (the projectile) measures its travel.</p>\n";
    if (fragments && fragments->plug >= 0)
      h << "<p>The plug's travel along the impact axis: "
        << format("%.4g", fragments->fragments[fragments->plug].travel * 1e3)
        << " mm (its centre of mass since the first frame, plug.json).</p>\n";
  } catch (const std::exception& e) {
    report.skipped.push_back(std::string("section: ") + e.what());
    h << "<p>No section: " << escape_html(e.what()) << "</p>\n";
  }

  h << "<h2>Fragments and plug</h2>\n";
  if (fragments) {
    page.figure(fragments->png, "Fragments of the target at t = " +
                                    format("%.4g", fragments->time * 1e6) + " µs (plug.json).");
    h << "<table><tr><th>fragment</th><th>mass (kg)</th><th>velocity along the impact axis "
         "(m/s)</th><th>diameter (mm)</th><th>thickness (mm)</th><th>travel (mm)</th></tr>\n";
    for (std::size_t k = 0; k < fragments->fragments.size() && k < 10; ++k) {
      const Fragment& f = fragments->fragments[k];
      const int index = static_cast<int>(k);
      h << "<tr><td>" << k << (index == fragments->plug ? " (plug)" : "")
        << (index == fragments->main ? " (target)" : "") << "</td><td>" << format("%.4g", f.mass)
        << "</td><td>" << format("%.4g", f.velocity.dot(fragments->impact_axis)) << "</td><td>"
        << format("%.4g", f.diameter * 1e3) << "</td><td>" << format("%.4g", f.thickness * 1e3)
        << "</td><td>" << format("%.4g", f.travel * 1e3) << "</td></tr>\n";
    }
    h << "</table>\n<p>Debris (killed particles, eroded elements): "
      << format("%.4g", fragments->debris_mass) << " kg.</p>\n";
  } else {
    h << "<p>No fragments: " << escape_html(no_fragments) << "</p>\n";
  }

  h << "<h2>Against the reference</h2>\n";
  if (report.references.empty()) {
    if (other_runs > 0)
      h << "<p>No reference values for this run in " << escape_html(reference_file.string())
        << " (its " << other_runs << " rows are for other runs: see their `when` column).</p>\n";
    else
      h << "<p>No reference values (put a reference.csv with columns quantity,value,unit,source "
           "beside the case file).</p>\n";
  } else {
    h << "<p>From " << escape_html(reference_file.string())
      << ".</p>\n<table><tr><th>quantity</th><th>reference</th><th>this run</th><th>unit</th>"
         "<th>relative error</th><th>source</th></tr>\n";
    for (ReferenceRow& r : report.references) {
      const std::optional<double> value = value_of(summary, history, r.quantity);
      r.found = value.has_value();
      r.value = value.value_or(std::numeric_limits<double>::quiet_NaN());
      h << "<tr><td>" << escape_html(r.quantity) << "</td><td>" << format("%.6g", r.reference)
        << "</td><td>" << (r.found ? format("%.6g", r.value) : "not in this run") << "</td><td>"
        << escape_html(r.unit) << "</td><td"
        << (r.found && std::abs(r.relative_error()) > 0.05 ? " class=\"bad\"" : "") << ">"
        << (r.found ? format("%+.2f%%", 100 * r.relative_error()) : "") << "</td><td>"
        << escape_html(r.source) << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  h << "</body></html>\n";
  report.html = dir / "report.html";
  report.images = page.images;
  write_text_atomically(report.html, h.str());
  // The same comparison for scripts (scripts/validate.sh reads it).
  if (!report.references.empty()) {
    std::string csv = "quantity,reference,value,unit,relative_error,source\n";
    const auto quoted = [](const std::string& text) {
      std::string out = "\"";
      for (const char c : text)
        out += c == '"' ? std::string("\"\"") : std::string(1, c);
      return out + "\"";
    };
    for (const ReferenceRow& r : report.references)
      csv += r.quantity + "," + format("%.10g", r.reference) + "," +
             (r.found ? format("%.10g", r.value) : "") + "," + r.unit + "," +
             (r.found && r.reference != 0 ? format("%.6g", r.relative_error()) : "") + "," +
             quoted(r.source) + "\n";
    write_text_atomically(dir / "reference.csv", csv);
  }
  return report;
}

} // namespace sphfem::post
