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

// The same impact velocity, to round-off of numbers read back from text.
bool same_v0(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b));
}

// A run's residual velocity: 0 without perforation.
double run_vr(const SweepRun& r) {
  return *r.perforated ? r.residual_projectile.value_or(0) : 0.0;
}

// One row of the reference table. Errors: vr − the reference's vr, m/s.
struct ReferenceTableRow {
  double v0 = 0;
  std::string label;
  std::optional<double> reference, run;           // vr, m/s
  std::vector<std::optional<double>> comparisons; // vr, m/s, one per comparison series
  std::optional<double> error_run, error_fit;
  std::vector<std::optional<double>> error_comparisons;
};

// The reference table of write_sweep (sweep.hpp); `runs` sorted by v0.
std::vector<ReferenceTableRow> reference_rows(const Sweep& s, const std::vector<SweepRun>& runs) {
  std::vector<ReferenceTableRow> rows;
  const auto add = [&rows](const ReferencePoint& p) -> ReferenceTableRow& {
    ReferenceTableRow& r = rows.emplace_back();
    r.v0 = p.v0;
    r.label = p.label;
    return r;
  };
  for (const ReferencePoint& p : s.reference.points)
    add(p).reference = p.vr;
  for (const ReferenceSeries& c : s.comparisons)
    for (const ReferencePoint& p : c.points)
      if (std::ranges::none_of(rows,
                               [&p](const ReferenceTableRow& r) { return same_v0(p.v0, r.v0); }))
        add(p);
  std::ranges::stable_sort(rows, {}, &ReferenceTableRow::v0);

  const auto minus_reference = [](const ReferenceTableRow& r, const std::optional<double>& vr) {
    return r.reference && vr ? std::optional<double>(*vr - *r.reference) : std::nullopt;
  };
  for (ReferenceTableRow& r : rows) {
    for (const SweepRun& run : runs)
      if (run.known() && same_v0(run.v0, r.v0))
        r.run = run_vr(run);
    r.error_run = minus_reference(r, r.run);
    if (s.fit)
      r.error_fit = minus_reference(r, (*s.fit)(r.v0));
    for (const ReferenceSeries& c : s.comparisons) {
      const auto p = std::ranges::find_if(
          c.points, [&r](const ReferencePoint& q) { return same_v0(q.v0, r.v0); });
      r.comparisons.push_back(p == c.points.end() ? std::nullopt : std::optional<double>(p->vr));
      r.error_comparisons.push_back(minus_reference(r, r.comparisons.back()));
    }
  }
  return rows;
}

struct Rms {
  std::optional<double> value; // m/s; empty without points
  int points = 0;
};

// The rms of the errors `error` picks from the rows, over the rows that have one.
template <class Pick> Rms rms(const std::vector<ReferenceTableRow>& rows, Pick error) {
  double sum = 0;
  Rms r;
  for (const ReferenceTableRow& row : rows)
    if (const std::optional<double> e = error(row)) {
      sum += *e * *e;
      ++r.points;
    }
  if (r.points > 0)
    r.value = std::sqrt(sum / r.points);
  return r;
}

// The rms of the run's, the fit's and each comparison's errors.
struct ReferenceRms {
  Rms run, fit;
  std::vector<Rms> comparisons;
};

ReferenceRms reference_rms(const Sweep& s, const std::vector<ReferenceTableRow>& rows) {
  ReferenceRms r{rms(rows, [](const ReferenceTableRow& row) { return row.error_run; }),
                 rms(rows, [](const ReferenceTableRow& row) { return row.error_fit; }),
                 {}};
  for (std::size_t k = 0; k < s.comparisons.size(); ++k)
    r.comparisons.push_back(
        rms(rows, [k](const ReferenceTableRow& row) { return row.error_comparisons[k]; }));
  return r;
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
                        const std::vector<ReferenceTableRow>& rows) {
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
    const auto json_numbers = [](const std::vector<std::optional<double>>& values) {
      nlohmann::json list = nlohmann::json::array();
      for (const std::optional<double>& v : values)
        list.push_back(json_number(v));
      return list;
    };
    const ReferenceRms summary = reference_rms(s, rows);
    nlohmann::json ref = {{"file", s.reference_file.string()},
                          {"column", s.reference.column},
                          {"label", s.reference.label},
                          {"comparisons", nlohmann::json::array()},
                          {"points", nlohmann::json::array()},
                          {"rms_error_run_m_per_s", json_number(summary.run.value)},
                          {"common_points_run", summary.run.points},
                          {"rms_error_fit_m_per_s", json_number(summary.fit.value)},
                          {"common_points_fit", summary.fit.points}};
    for (std::size_t k = 0; k < s.comparisons.size(); ++k)
      ref["comparisons"].push_back(
          {{"column", s.comparisons[k].column},
           {"label", s.comparisons[k].label},
           {"rms_error_m_per_s", json_number(summary.comparisons[k].value)},
           {"common_points", summary.comparisons[k].points}});
    for (const ReferenceTableRow& r : rows)
      ref["points"].push_back({{"v0_m_per_s", r.v0},
                               {"label", r.label},
                               {"vr_m_per_s", json_number(r.reference)},
                               {"run_vr_m_per_s", json_number(r.run)},
                               {"comparison_vr_m_per_s", json_numbers(r.comparisons)},
                               {"error_run_m_per_s", json_number(r.error_run)},
                               {"error_fit_m_per_s", json_number(r.error_fit)},
                               {"error_comparison_m_per_s", json_numbers(r.error_comparisons)}});
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
      y.push_back(run_vr(r));
      v_min = std::min(v_min, r.v0);
      v_max = std::max(v_max, r.v0);
    }
  const auto span = [&v_min, &v_max](const ReferenceSeries& series) {
    for (const ReferencePoint& p : series.points) {
      v_min = std::min(v_min, p.v0);
      v_max = std::max(v_max, p.v0);
    }
  };
  span(s.reference);
  for (const ReferenceSeries& c : s.comparisons)
    span(c);
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
  // Largest dots first, so that equal points stay visible: reference, comparisons, runs.
  const auto add_points = [&chart](const std::string& label, const ReferenceSeries& series,
                                   const LineStyle& style) {
    std::vector<double> px, py;
    for (const ReferencePoint& p : series.points) {
      px.push_back(p.v0);
      py.push_back(p.vr);
    }
    chart.add_series(label, px, py, style);
  };
  if (!s.reference_file.empty())
    add_points("reference: " + s.reference.label, s.reference, {{0, 0, 0}, 0.0, false, 6.0});
  for (std::size_t k = 0; k < s.comparisons.size(); ++k)
    add_points(s.comparisons[k].label, s.comparisons[k],
               {LineChart::palette(2 + k), 0.0, false, 5.0});
  chart.add_series("runs", x, y, {LineChart::palette(0), 0.0, false, 4.0});
  chart.write_png(png);
}

std::string html_text(const Sweep& s, const std::vector<SweepRun>& runs,
                      const std::vector<ReferenceTableRow>& rows, const fs::path& png) {
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
    << (s.reference_file.empty() ? ""
        : s.comparisons.empty()  ? " and the reference (black)"
                                 : ", the reference (black) and the comparisons (coloured dots)")
    << ".</figcaption></figure>\n";

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
    const std::string& ref = s.reference.label;
    const bool labels =
        std::ranges::any_of(rows, [](const ReferenceTableRow& r) { return !r.label.empty(); });
    const ReferenceRms summary = reference_rms(s, rows);
    h << "<h2>Reference</h2>\n<p>" << escape_html(s.reference_file.string()) << ", column "
      << escape_html(s.reference.column) << " (" << escape_html(ref)
      << "). Errors are vr − the reference's at its impact velocities: of the run at the same v0 "
         "(this code), of the fit and of each comparison series from the same file, where both "
         "have a value.</p>\n<table><tr><th>against "
      << escape_html(ref) << "</th><th>column</th><th>rms error (m/s)</th><th>points</th></tr>\n";
    const auto rms_row = [&h](const std::string& who, const std::string& column, const Rms& r) {
      h << "<tr><td>" << escape_html(who) << "</td><td>" << escape_html(column) << "</td><td>"
        << cell(r.value, "%.2f") << "</td><td>" << r.points << "</td></tr>\n";
    };
    rms_row("this code", "", summary.run);
    rms_row("Recht–Ipson fit", "", summary.fit);
    for (std::size_t k = 0; k < s.comparisons.size(); ++k)
      rms_row(s.comparisons[k].label, s.comparisons[k].column, summary.comparisons[k]);
    h << "</table>\n<table><tr><th>v0 (m/s)</th>" << (labels ? "<th>label</th>" : "") << "<th>"
      << escape_html(ref) << " vr (m/s)</th><th>this code vr (m/s)</th>";
    for (const ReferenceSeries& c : s.comparisons)
      h << "<th>" << escape_html(c.label) << " vr (m/s)</th>";
    h << "<th>error of this code (m/s)</th><th>error of the fit (m/s)</th>";
    for (const ReferenceSeries& c : s.comparisons)
      h << "<th>error of " << escape_html(c.label) << " (m/s)</th>";
    h << "</tr>\n";
    for (const ReferenceTableRow& r : rows) {
      h << "<tr><td>" << format("%.6g", r.v0) << "</td>"
        << (labels ? "<td>" + escape_html(r.label) + "</td>" : "") << "<td>"
        << cell(r.reference, "%.1f") << "</td><td>" << cell(r.run, "%.1f") << "</td>";
      for (const std::optional<double>& vr : r.comparisons)
        h << "<td>" << cell(vr, "%.1f") << "</td>";
      h << "<td>" << cell(r.error_run, "%.1f") << "</td><td>" << cell(r.error_fit, "%.1f")
        << "</td>";
      for (const std::optional<double>& e : r.error_comparisons)
        h << "<td>" << cell(e, "%.1f") << "</td>";
      h << "</tr>\n";
    }
    h << "</table>\n";
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
      points.push_back({r.v0, run_vr(r), *r.perforated});
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

std::optional<BracketStep> next_bracket_step(const std::vector<BallisticPoint>& points) {
  if (points.empty())
    return std::nullopt;
  const bool any_perforated = std::ranges::any_of(points, &BallisticPoint::perforated);
  const bool all_perforated = std::ranges::all_of(points, &BallisticPoint::perforated);
  if (all_perforated) {
    const BallisticPoint& low = std::ranges::min(points, {}, &BallisticPoint::v0);
    const double estimate = 0.95 * std::sqrt(std::max(0.0, low.v0 * low.v0 - low.vr * low.vr));
    const double v0 = std::min(estimate, 0.9 * low.v0);
    return BracketStep{v0, "every run perforated: extending downward to " + format("%.4g", v0) +
                               " m/s (below " + format("%.4g", low.v0) + " m/s)"};
  }
  if (!any_perforated) {
    const double high = std::ranges::max(points, {}, &BallisticPoint::v0).v0;
    return BracketStep{1.5 * high, "no run perforated: extending upward to " +
                                       format("%.4g", 1.5 * high) + " m/s (above " +
                                       format("%.4g", high) + " m/s)"};
  }
  return std::nullopt;
}

std::vector<ReferenceSeries> read_ballistic_reference(const fs::path& file,
                                                      const std::string& v0_column,
                                                      const std::vector<std::string>& vr_columns) {
  std::ifstream in(file);
  if (!in)
    throw Error(file.string() + ": cannot read the reference curve");
  std::vector<ReferenceSeries> series;
  for (const std::string& column : vr_columns)
    series.push_back({column, column, {}});
  std::string line;
  int number = 0;
  std::vector<std::string> header;
  std::ptrdiff_t v0_at = -1, label_at = -1;
  std::vector<std::ptrdiff_t> vr_at;
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
        if (it == header.end())
          throw Error("--reference-columns: no column '" + name + "' in the header of " + where +
                      ", '" + trim(line) + "'");
        return it - header.begin();
      };
      v0_at = index(v0_column);
      for (const std::string& column : vr_columns)
        vr_at.push_back(index(column));
      const auto label = std::ranges::find(header, "label");
      label_at = label == header.end() ? -1 : label - header.begin();
      continue;
    }
    const auto value = [&](std::ptrdiff_t k) {
      return k >= 0 && k < static_cast<std::ptrdiff_t>(cells.size()) ? cells[k] : std::string();
    };
    const auto number_in = [&](std::ptrdiff_t k) {
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(value(k), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != value(k).size() || !std::isfinite(v))
        throw Error(where + ": column '" + header[k] + "': expected a number, got '" + value(k) +
                    "'");
      return v;
    };
    if (value(v0_at).empty() ||
        std::ranges::all_of(vr_at, [&](std::ptrdiff_t k) { return value(k).empty(); }))
      continue;
    const double v0 = number_in(v0_at);
    for (std::size_t c = 0; c < series.size(); ++c)
      if (!value(vr_at[c]).empty())
        series[c].points.push_back({v0, number_in(vr_at[c]), value(label_at)});
  }
  for (const ReferenceSeries& s : series)
    if (s.points.empty())
      throw Error(file.string() + ": no reference points in column '" + s.column +
                  "' (rows with numbers in '" + v0_column + "' and '" + s.column + "')");
  return series;
}

SweepFiles write_sweep(const Sweep& sweep, const fs::path& dir) {
  std::vector<SweepRun> runs = sweep.runs;
  std::ranges::stable_sort(runs, {}, &SweepRun::v0);
  const std::vector<ReferenceTableRow> rows = reference_rows(sweep, runs);
  fs::create_directories(dir);
  const SweepFiles files{dir / "sweep.csv", dir / "sweep.json", dir / "ballistic_curve.png",
                         dir / "sweep.html"};
  write_text_atomically(files.csv, csv_text(runs));
  write_text_atomically(files.json, json_doc(sweep, runs, rows).dump(2) + "\n");
  write_chart(sweep, runs, files.png);
  write_text_atomically(files.html, html_text(sweep, runs, rows, files.png));
  return files;
}

} // namespace sphfem::post
