// Ballistic sweeps (sweep.hpp): run results, bisection, reference curve, tables, chart, page.
#include "post/sweep.hpp"
#include "post/text.hpp"

#include "post/line_chart.hpp"
#include "post/report.hpp"
#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace sphfem::post {

namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos)
    return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ','))
    cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',')
    cells.emplace_back();
  return cells;
}

// A number at a dotted path of `j`, if it is there.
const nlohmann::json* at(const nlohmann::json& j, const std::string& path) {
  const nlohmann::json* node = &j;
  std::stringstream s(path);
  std::string part;
  while (std::getline(s, part, '.')) {
    if (!node->is_object() || !node->contains(part))
      return nullptr;
    node = &(*node)[part];
  }
  return node;
}

std::optional<double> number_at(const nlohmann::json& j, const std::string& path) {
  const nlohmann::json* node = at(j, path);
  return node && node->is_number() ? std::optional<double>(node->get<double>()) : std::nullopt;
}

std::string cell(const std::optional<double>& v, const char* pattern = "%.6g") {
  return v ? format(pattern, *v) : "";
}

nlohmann::json json_number(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json();
}

struct ReferenceError {
  std::optional<double> run, fit; // this sweep's vr − the reference's, m/s
};

std::vector<ReferenceError> reference_errors(const Sweep& s) {
  std::vector<ReferenceError> errors;
  for (const ReferencePoint& r : s.reference) {
    ReferenceError e;
    for (const SweepRun& run : s.runs)
      if (run.known() && std::abs(run.v0 - r.v0) <= 1e-9 * std::max(1.0, std::abs(r.v0)))
        e.run = (*run.perforated ? run.residual_projectile.value_or(0) : 0.0) - r.vr;
    if (s.fit)
      e.fit = (*s.fit)(r.v0) - r.vr;
    errors.push_back(e);
  }
  return errors;
}

std::optional<double> rms(const std::vector<ReferenceError>& errors,
                          std::optional<double> ReferenceError::*member) {
  double sum = 0;
  int n = 0;
  for (const ReferenceError& e : errors)
    if (const auto& v = e.*member) {
      sum += *v * *v;
      ++n;
    }
  return n > 0 ? std::optional<double>(std::sqrt(sum / n)) : std::nullopt;
}

std::string perforated_text(const SweepRun& r) {
  return r.perforated ? (*r.perforated ? "1" : "0") : "unknown";
}

std::string csv_text(const std::vector<SweepRun>& runs) {
  std::string text = "v0_m_per_s,perforated,residual_projectile_m_per_s,residual_plug_m_per_s,"
                     "plug_mass_kg,wall_s,run_folder\n";
  for (const SweepRun& r : runs)
    text += format("%.10g", r.v0) + "," + perforated_text(r) + "," +
            cell(r.residual_projectile, "%.10g") + "," + cell(r.residual_plug, "%.10g") + "," +
            cell(r.plug_mass, "%.10g") + "," + format("%.4g", r.wall_s) + "," + r.folder.string() +
            "\n";
  return text;
}

nlohmann::json json_doc(const Sweep& s, const std::vector<SweepRun>& runs,
                        const std::vector<ReferenceError>& errors) {
  nlohmann::json j;
  j["case"] = s.case_file;
  j["key"] = s.key;
  j["command"] = s.command;
  j["units"] = {{"velocity", "m/s"}, {"mass", "kg"}, {"time", "s"}};
  j["runs"] = nlohmann::json::array();
  for (const SweepRun& r : runs) {
    nlohmann::json row = {
        {"v0_m_per_s", r.v0},
        {"value", r.value},
        {"perforated", r.perforated ? nlohmann::json(*r.perforated) : nlohmann::json("unknown")},
        {"residual_projectile_m_per_s", json_number(r.residual_projectile)},
        {"residual_plug_m_per_s", json_number(r.residual_plug)},
        {"plug_mass_kg", json_number(r.plug_mass)},
        {"wall_s", r.wall_s},
        {"run_folder", r.folder.string()}};
    if (!r.note.empty())
      row["note"] = r.note;
    j["runs"].push_back(row);
  }
  if (s.fit)
    j["fit"] = {{"model", "vr = a (v0^p - vbl^p)^(1/p) for v0 > vbl, else 0 (Recht-Ipson)"},
                {"a", s.fit->a},
                {"p", s.fit->p},
                {"vbl_m_per_s", s.fit->vbl},
                {"rms_m_per_s", s.fit->rms},
                {"points", s.fit->points},
                {"vbl_bounds_m_per_s", {s.fit->vbl_min, s.fit->vbl_max}}};
  else
    j["fit"] = nullptr;
  if (!s.reference_file.empty()) {
    nlohmann::json ref = {{"file", s.reference_file.string()}, {"points", nlohmann::json::array()}};
    for (std::size_t k = 0; k < s.reference.size(); ++k)
      ref["points"].push_back({{"v0_m_per_s", s.reference[k].v0},
                               {"vr_m_per_s", s.reference[k].vr},
                               {"label", s.reference[k].label},
                               {"error_run_m_per_s", json_number(errors[k].run)},
                               {"error_fit_m_per_s", json_number(errors[k].fit)}});
    ref["rms_error_run_m_per_s"] = json_number(rms(errors, &ReferenceError::run));
    ref["rms_error_fit_m_per_s"] = json_number(rms(errors, &ReferenceError::fit));
    j["reference"] = ref;
  }
  return j;
}

void write_chart(const Sweep& s, const std::vector<SweepRun>& runs, const fs::path& png) {
  LineChart chart(900, 560);
  chart.set_title("Ballistic curve: residual velocity against impact velocity");
  chart.set_x_label("impact velocity v0 (m/s)");
  chart.set_y_label("residual projectile velocity vr (m/s)");
  double v_min = std::numeric_limits<double>::infinity(), v_max = -v_min;
  std::vector<double> x, y;
  for (const SweepRun& r : runs)
    if (r.known()) {
      x.push_back(r.v0);
      y.push_back(*r.perforated ? r.residual_projectile.value_or(0) : 0.0);
      v_min = std::min(v_min, r.v0);
      v_max = std::max(v_max, r.v0);
    }
  for (const ReferencePoint& p : s.reference) {
    v_min = std::min(v_min, p.v0);
    v_max = std::max(v_max, p.v0);
  }
  if (s.fit && v_max > v_min) {
    std::vector<double> fx, fy;
    constexpr int n = 400;
    for (int k = 0; k <= n; ++k) {
      fx.push_back(v_min + (v_max - v_min) * k / n);
      fy.push_back((*s.fit)(fx.back()));
    }
    chart.add_series("Recht-Ipson fit: vbl " + format("%.1f", s.fit->vbl) + " m/s, p " +
                         format("%.2f", s.fit->p) + ", a " + format("%.3f", s.fit->a),
                     fx, fy, {LineChart::palette(1), 2.0, false});
  }
  if (!s.reference.empty()) {
    std::vector<double> rx, ry;
    for (const ReferencePoint& p : s.reference) {
      rx.push_back(p.v0);
      ry.push_back(p.vr);
    }
    chart.add_series("reference: " + s.reference_file.filename().string(), rx, ry,
                     {{0, 0, 0}, 0.0, false, 6.0});
  }
  chart.add_series("runs", x, y, {LineChart::palette(0), 0.0, false, 4.0});
  write_atomically(png, [&chart](const fs::path& temporary) { chart.write_png(temporary); });
}

std::string html_text(const Sweep& s, const std::vector<SweepRun>& runs,
                      const std::vector<ReferenceError>& errors, const fs::path& png) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>sphfem sweep: "
    << escape_html(s.case_file)
    << "</title>\n<style>body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}"
       "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px "
       "8px;text-align:right}th{background:#eee}td:first-child,th:first-child{text-align:left}"
       "figure{margin:1em 0}img{max-width:100%}figcaption{color:#555;font-size:90%}"
       "code{font-size:90%}</style></head><body>\n";
  h << "<h1>sphfem sweep: " << escape_html(s.case_file) << "</h1>\n<p><code>"
    << escape_html(s.command) << "</code></p>\n";
  h << "<figure><img alt=\"ballistic curve\" src=\"data:image/png;base64," << base64(slurp(png))
    << "\"><figcaption>Residual projectile velocity against impact velocity (" << escape_html(s.key)
    << "): the runs (dots), the Recht–Ipson fit (line)"
    << (s.reference.empty() ? "" : " and the reference (black)") << ".</figcaption></figure>\n";

  h << "<h2>Fit</h2>\n";
  if (s.fit)
    h << "<p>vr = a (v0<sup>p</sup> − vbl<sup>p</sup>)<sup>1/p</sup> for v0 &gt; vbl, else 0; "
         "least squares on vr over the "
      << s.fit->points << " perforating runs, vbl held in [" << format("%.4g", s.fit->vbl_min)
      << ", " << format("%.4g", s.fit->vbl_max) << "] m/s.</p>\n"
      << "<table><tr><th>ballistic limit vbl (m/s)</th><th>p</th><th>a</th><th>rms residual "
         "(m/s)</th></tr>\n<tr><td>"
      << format("%.2f", s.fit->vbl) << "</td><td>" << format("%.3f", s.fit->p) << "</td><td>"
      << format("%.4f", s.fit->a) << "</td><td>" << format("%.2f", s.fit->rms)
      << "</td></tr></table>\n";
  else
    h << "<p>No fit: it needs at least three perforating runs.</p>\n";

  h << "<h2>Runs</h2>\n<table><tr><th>v0 (m/s)</th><th>perforated</th><th>vr projectile "
       "(m/s)</th><th>vr plug (m/s)</th><th>plug mass (kg)</th><th>wall time (s)</th><th>run "
       "folder</th></tr>\n";
  for (const SweepRun& r : runs)
    h << "<tr><td>" << format("%.6g", r.v0) << "</td><td>"
      << (r.perforated ? (*r.perforated ? "yes" : "no") : "unknown: " + escape_html(r.note))
      << "</td><td>" << cell(r.residual_projectile, "%.1f") << "</td><td>"
      << cell(r.residual_plug, "%.1f") << "</td><td>" << cell(r.plug_mass, "%.4g") << "</td><td>"
      << format("%.1f", r.wall_s) << "</td><td>" << escape_html(r.folder.filename().string())
      << "</td></tr>\n";
  h << "</table>\n";

  if (!s.reference_file.empty()) {
    h << "<h2>Reference</h2>\n<p>" << escape_html(s.reference_file.string())
      << ": errors are this sweep's vr − the reference's, from the run at the same v0 and from "
         "the fit.</p>\n<table><tr><th>v0 (m/s)</th><th>label</th><th>vr (m/s)</th><th>error of "
         "the run (m/s)</th><th>error of the fit (m/s)</th></tr>\n";
    for (std::size_t k = 0; k < s.reference.size(); ++k)
      h << "<tr><td>" << format("%.6g", s.reference[k].v0) << "</td><td>"
        << escape_html(s.reference[k].label) << "</td><td>" << format("%.1f", s.reference[k].vr)
        << "</td><td>" << cell(errors[k].run, "%.1f") << "</td><td>" << cell(errors[k].fit, "%.1f")
        << "</td></tr>\n";
    h << "<tr><th>rms</th><th></th><th></th><th>" << cell(rms(errors, &ReferenceError::run), "%.2f")
      << "</th><th>" << cell(rms(errors, &ReferenceError::fit), "%.2f") << "</th></tr></table>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

} // namespace

void read_run_results(SweepRun& run) {
  const fs::path file = run.folder / "summary.json";
  if (!fs::exists(file)) {
    run.note = "no " + file.string();
    return;
  }
  nlohmann::json summary;
  try {
    summary = nlohmann::json::parse(slurp(file));
  } catch (const nlohmann::json::exception& e) {
    run.note = file.string() + ": " + e.what();
    return;
  }
  const nlohmann::json* perforated = at(summary, "results.perforated");
  if (!perforated || !perforated->is_boolean()) {
    run.note = file.string() + " has no results.perforated";
    return;
  }
  run.perforated = perforated->get<bool>();
  run.residual_projectile = number_at(summary, "results.residual_velocity.projectile");
  run.residual_plug = number_at(summary, "results.residual_velocity.plug");
  run.plug_mass = number_at(summary, "results.plug.mass");
}

std::vector<BallisticPoint> ballistic_points(const std::vector<SweepRun>& runs) {
  std::vector<BallisticPoint> points;
  for (const SweepRun& r : runs)
    if (r.known())
      points.push_back(
          {r.v0, *r.perforated ? r.residual_projectile.value_or(0) : 0.0, *r.perforated});
  return points;
}

std::optional<double> next_bisection(const std::vector<BallisticPoint>& points, double tolerance) {
  double above = std::numeric_limits<double>::infinity();
  for (const BallisticPoint& b : points)
    if (b.perforated)
      above = std::min(above, b.v0);
  double below = -std::numeric_limits<double>::infinity();
  for (const BallisticPoint& b : points)
    if (!b.perforated && b.v0 < above)
      below = std::max(below, b.v0);
  if (!std::isfinite(above) || !std::isfinite(below) || above - below <= tolerance)
    return std::nullopt;
  return 0.5 * (below + above);
}

std::vector<ReferencePoint> read_ballistic_reference(const fs::path& file,
                                                     const std::string& v0_column,
                                                     const std::string& vr_column) {
  std::ifstream in(file);
  if (!in)
    throw Error(file.string() + ": cannot read the reference curve");
  std::vector<ReferencePoint> points;
  std::string line;
  int number = 0;
  std::vector<std::string> header;
  std::ptrdiff_t v0_at = -1, vr_at = -1, label_at = -1;
  while (std::getline(in, line)) {
    ++number;
    const std::string where = file.string() + ":" + std::to_string(number);
    if (trim(line).empty() || trim(line)[0] == '#')
      continue;
    const std::vector<std::string> cells = split(line);
    if (header.empty()) {
      header = cells;
      const auto index = [&](const std::string& name) -> std::ptrdiff_t {
        const auto it = std::ranges::find(header, name);
        return it == header.end() ? -1 : it - header.begin();
      };
      v0_at = index(v0_column);
      vr_at = index(vr_column);
      label_at = index("label");
      if (v0_at < 0 || vr_at < 0)
        throw Error(where + ": expected a header with columns '" + v0_column + "' and '" +
                    vr_column + "' (m/s), got '" + trim(line) + "'");
      continue;
    }
    const auto value = [&](std::ptrdiff_t k) {
      return k < static_cast<std::ptrdiff_t>(cells.size()) ? cells[k] : std::string();
    };
    if (value(v0_at).empty() || value(vr_at).empty())
      continue;
    ReferencePoint p;
    for (auto [k, target] : {std::pair{v0_at, &p.v0}, std::pair{vr_at, &p.vr}}) {
      std::size_t used = 0;
      try {
        *target = std::stod(value(k), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != value(k).size() || !std::isfinite(*target))
        throw Error(where + ": column '" + header[k] + "': expected a number, got '" + value(k) +
                    "'");
    }
    p.label = label_at >= 0 ? value(label_at) : "";
    points.push_back(p);
  }
  if (points.empty())
    throw Error(file.string() + ": no reference points (columns '" + v0_column + "', '" +
                vr_column + "')");
  return points;
}

SweepFiles write_sweep(const Sweep& sweep, const fs::path& dir) {
  std::vector<SweepRun> runs = sweep.runs;
  std::ranges::stable_sort(runs, {}, &SweepRun::v0);
  const std::vector<ReferenceError> errors = reference_errors(sweep);
  fs::create_directories(dir);
  const SweepFiles files{dir / "sweep.csv", dir / "sweep.json", dir / "ballistic_curve.png",
                         dir / "sweep.html"};
  write_text_atomically(files.csv, csv_text(runs));
  write_text_atomically(files.json, json_doc(sweep, runs, errors).dump(2) + "\n");
  write_chart(sweep, runs, files.png);
  write_text_atomically(files.html, html_text(sweep, runs, errors, files.png));
  return files;
}

} // namespace sphfem::post
