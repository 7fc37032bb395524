#include "post/history_plot.hpp"

#include "post/line_chart.hpp"
#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>

namespace sphfem::post {

namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

struct Run {
  std::string label;
  fs::path file;
  History history;
};

// OUT or OUT/history.csv → the run's history, labelled by its folder's name.
Run load_run(const fs::path& path, const std::string& label) {
  const fs::path file = fs::is_directory(path) ? path / "history.csv" : path;
  SPHFEM_CHECK(fs::exists(path), path.string(), ": no such run folder");
  SPHFEM_CHECK(fs::is_regular_file(file), path.string(),
               ": not a run folder (no history.csv; run `sphfem solve` first)");
  fs::path folder = fs::weakly_canonical(fs::absolute(file)).parent_path();
  return {label.empty() ? folder.filename().string() : label, file, read_history_csv(file)};
}

std::string list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names)
    s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::string csv_field(const std::string& s) { // quoted when it holds a comma or a quote
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v))
    return ""; // a gap, as read_history_csv reads it
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", v); // history.csv's precision
  return buffer;
}

std::string file_name(const std::string& column) { // column names are plain; keep them so
  std::string s = column;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-')
      c = '_';
  return s;
}

std::vector<double> scaled(const std::vector<double>& v, double scale) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    out[i] = v[i] * scale;
  return out;
}

} // namespace

std::vector<std::string> default_history_columns(const History& history) {
  std::vector<std::string> out;
  for (const auto& c : history.columns)
    if (ends_with(c, ".vz") || (ends_with(c, ".szz") && c.rfind("body.", 0) != 0))
      out.push_back(c);
  return out;
}

std::vector<std::string> selected_history_columns(const History& history,
                                                  const std::vector<std::string>& probes,
                                                  const std::vector<std::string>& bodies) {
  std::vector<std::string> known_probes, known_bodies;
  for (const auto& c : history.columns)
    if (c.rfind("body.", 0) == 0 && ends_with(c, ".vz"))
      known_bodies.push_back(c.substr(5, c.size() - 8));
    else if (ends_with(c, ".vz") && c.find('.') == c.size() - 3)
      known_probes.push_back(c.substr(0, c.size() - 3));
  std::vector<std::string> wanted;
  for (const auto& p : probes) {
    SPHFEM_CHECK(std::ranges::find(known_probes, p) != known_probes.end(), "--probes: no probe ", p,
                 " in the history; probes: ", list(known_probes));
    wanted.push_back(p + ".vz");
    wanted.push_back(p + ".szz");
  }
  for (const auto& b : bodies) {
    SPHFEM_CHECK(std::ranges::find(known_bodies, b) != known_bodies.end(), "--bodies: no body ", b,
                 " in the history; bodies: ", list(known_bodies));
    wanted.push_back("body." + b + ".vz");
  }
  std::vector<std::string> out;
  for (const auto& c : history.columns)
    if (std::ranges::find(wanted, c) != wanted.end())
      out.push_back(c);
  return out;
}

PlotUnit time_unit(const std::string& name) {
  if (name == "s")
    return {1, "s"};
  if (name == "ms")
    return {1e3, "ms"};
  if (name == "us")
    return {1e6, "\u00b5s"};
  if (name == "ns")
    return {1e9, "ns"};
  throw Error("--time-unit " + name + ": expected s, ms, us or ns");
}

PlotUnit column_unit(const std::string& column) {
  const auto dot = column.rfind('.');
  const std::string quantity = dot == std::string::npos ? column : column.substr(dot + 1);
  if (column.rfind("energy.", 0) == 0 || quantity == "kinetic" || quantity == "internal")
    return {1, "J"};
  if (quantity == "ux" || quantity == "uy" || quantity == "uz")
    return {1e3, "mm"};
  if (quantity == "vx" || quantity == "vy" || quantity == "vz")
    return {1, "m/s"};
  static const std::regex stress("s(xx|yy|zz|xy|yz|zx|xz)|pressure|von_mises");
  if (std::regex_match(quantity, stress))
    return {1e-9, "GPa"};
  if (column == "time" || column == "dt")
    return {1, "s"};
  return {1, ""};
}

std::pair<int, int> parse_image_size(const std::string& text) {
  std::smatch m;
  static const std::regex size(R"((\d{1,5})x(\d{1,5}))");
  SPHFEM_CHECK(std::regex_match(text, m, size), "--size ", text,
               ": expected WIDTHxHEIGHT in pixels, e.g. 900x560");
  return {std::stoi(m[1]), std::stoi(m[2])};
}

std::vector<HistoryPlot> plot_history(const HistoryPlotOptions& o) {
  // Everything is read and checked before anything is written.
  SPHFEM_CHECK(o.labels.size() <= 1 + o.compare.size(), o.labels.size(), " --label values for ",
               1 + o.compare.size(), " runs");
  std::vector<Run> runs;
  for (std::size_t i = 0; i <= o.compare.size(); ++i)
    runs.push_back(
        load_run(i == 0 ? o.run : o.compare[i - 1], i < o.labels.size() ? o.labels[i] : ""));
  const std::vector<std::string> columns =
      !o.columns.empty() ? o.columns
      : o.probes.empty() && o.bodies.empty()
          ? default_history_columns(runs[0].history)
          : selected_history_columns(runs[0].history, o.probes, o.bodies);
  SPHFEM_CHECK(!columns.empty(), runs[0].file.string(),
               ": no probe or body velocity columns; choose some with --columns from: ",
               list(runs[0].history.columns));
  for (const Run& run : runs) {
    SPHFEM_CHECK(run.history.values.count("time"), run.file.string(), ": no time column");
    for (const auto& c : columns)
      SPHFEM_CHECK(run.history.values.count(c), run.file.string(), ": unknown column ", c,
                   "; available: ", list(run.history.columns));
  }
  History reference;
  const std::string reference_label = o.reference.stem().string();
  if (!o.reference.empty()) {
    reference = read_history_csv(o.reference);
    SPHFEM_CHECK(reference.values.count("time"), o.reference.string(),
                 ":1: no time column (expected time in s and columns named as in history.csv)");
    bool shared = false;
    for (const auto& c : columns)
      shared = shared || reference.values.count(c);
    SPHFEM_CHECK(shared, o.reference.string(), ":1: none of the plotted columns (", list(columns),
                 ") is among its columns (", list(reference.columns), ")");
  }
  const PlotUnit t_unit = time_unit(o.time_unit);
  const std::string time_header = "time [" + o.time_unit + "]"; // ASCII: us, not µs
  (void)LineChart(o.width, o.height);                           // checks the size

  const fs::path dir = o.out_dir.empty() ? runs[0].file.parent_path() / "post" : o.out_dir;
  std::error_code failed;
  fs::create_directories(dir, failed);
  SPHFEM_CHECK(!failed, dir.string(), ": cannot create the folder: ", failed.message());
  std::vector<HistoryPlot> written;
  for (const auto& column : columns) {
    const PlotUnit unit = column == "dt" ? t_unit : column_unit(column);
    const std::string unit_suffix = unit.unit.empty() ? "" : " (" + unit.unit + ")";
    LineChart chart(o.width, o.height);
    chart.set_title(column);
    chart.set_x_label("time (" + t_unit.unit + ")");
    chart.set_y_label(column + unit_suffix);
    const HistoryPlot plot{column, dir / (file_name(column) + ".png"),
                           dir / (file_name(column) + ".csv")};
    std::ostringstream csv;
    const std::string csv_unit = column == "dt" ? o.time_unit : unit.unit; // ASCII
    csv << "series," << time_header << ","
        << csv_field(column + (csv_unit.empty() ? "" : " [" + csv_unit + "]")) << "\n";
    auto add = [&](const std::string& label, const History& h, LineStyle style) {
      const auto t = scaled(h["time"], t_unit.scale), v = scaled(h[column], unit.scale);
      for (std::size_t i = 0; i < t.size(); ++i)
        csv << csv_field(label) << "," << number(t[i]) << "," << number(v[i]) << "\n";
      chart.add_series(label, t, v, style);
    };
    for (std::size_t i = 0; i < runs.size(); ++i)
      add(runs[i].label, runs[i].history, {LineChart::palette(i), 2.0, false});
    if (reference.values.count(column))
      add(reference_label, reference, {{0, 0, 0}, 1.5, true});
    write_text_atomically(plot.csv, csv.str());
    chart.write_png(plot.png);
    written.push_back(plot);
  }
  return written;
}

} // namespace sphfem::post
