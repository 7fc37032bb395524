#include "app/post_commands.hpp"

#include "post/csv_chart.hpp"
#include "post/history_plot.hpp"
#include "post/plug.hpp"
#include "post/report.hpp"
#include "post/section.hpp"
#include "solver/core/error.hpp"

#include <cstdio>
#include <iostream>
#include <sstream>
#include <tuple>

namespace sphfem {

namespace {

namespace fs = std::filesystem;

void add_post_history(CLI::App& post, post::HistoryPlotOptions& o, std::string& size) {
  auto* history = post.add_subcommand(
      "history", "charts of run histories: one PNG and one CSV per column, runs compared");
  history->footer(
      "Writes DIR/<column>.png (the column against time, one curve per run, the reference\n"
      "dashed) and DIR/<column>.csv (series,time,value: exactly what is plotted, in the chart's\n"
      "units); DIR is -o, else RUN/post. Units: time by --time-unit, velocity m/s, stress and\n"
      "pressure GPa, displacement mm, energy J. Needs no display. Example:\n"
      "  sphfem post history out/bar_pressed_fe --compare out/bar_pressed_sph --columns mid.vz");
  history->add_option("RUN", o.run, "run folder (holding history.csv)")->required();
  history
      ->add_option("--columns", o.columns,
                   "columns to plot, comma-separated (default: every probe's vz and szz and "
                   "every body's vz)")
      ->delimiter(',');
  history->add_option("--probes", o.probes, "probes whose vz and szz to plot, comma-separated")
      ->delimiter(',');
  history
      ->add_option("--bodies", o.bodies, "bodies whose centre-of-mass vz to plot, comma-separated")
      ->delimiter(',');
  history->add_option("--compare", o.compare, "more run folders on the same axes")->expected(1, -1);
  history
      ->add_option("--label", o.labels,
                   "legend names of the run, then of each compared run (default: folder names)")
      ->expected(1, -1);
  history->add_option("--reference", o.reference,
                      "CSV with a time column (s) and columns named as in history.csv (SI), "
                      "plotted dashed");
  history->add_option("-o,--out", o.out_dir, "output folder (default: RUN/post)");
  history->add_option("--time-unit", o.time_unit, "time axis unit: s, ms, us or ns")
      ->capture_default_str();
  history->add_option("--size", size, "image size in pixels, WIDTHxHEIGHT")->capture_default_str();
}

// `sphfem post section`: vectors as comma-separated text, parsed after CLI11 so a bad one is
// a one-line sphfem error.
struct SectionCommand {
  post::SectionOptions o;
  std::string plane, axis, u_range, size = "900x560";
  double time = 0;
  bool last = false; // the default; --last only excludes --time
  CLI::Option* time_option = nullptr;
};

std::vector<double> parse_numbers(const std::string& text, std::size_t count,
                                  const std::string& option, const std::string& form) {
  std::vector<double> v;
  std::stringstream in(text);
  for (std::string cell; std::getline(in, cell, ',');) {
    std::size_t used = 0;
    try {
      v.push_back(std::stod(cell, &used));
    } catch (const std::exception&) {
      used = 0;
    }
    SPHFEM_CHECK(used > 0 && used == cell.size(), option, " ", text, ": expected ", form);
  }
  SPHFEM_CHECK(v.size() == count, option, " ", text, ": expected ", form);
  return v;
}

CLI::App* add_post_section(CLI::App& post, SectionCommand& c) {
  auto* section = post.add_subcommand(
      "section", "the deformed cross-section of the bodies at a plane, and its deflection");
  section->footer(
      "Writes into DIR (-o, else RUN/post): section.csv (body,part,polyline,u_m,w_m,x_m,y_m,z_m:\n"
      "the outline polylines, part fe or sph, killed particles as part killed), section.png (the\n"
      "outlines with equal axis scales in mm over the --field on the cut, with a colour bar),\n"
      "deflection.csv (body,radius_m,deflection_m: the\n"
      "displacement along the axis averaged in bins of |u|) and section.json. Plane coordinates:\n"
      "w along --axis projected into the plane (default: the in-plane direction closest to z),\n"
      "u = w x n, both from the plane's point. FE bodies are cut through their hexahedra (eroded\n"
      "ones left out); SPH bodies are outlined from the particles within a spacing of the plane.\n"
      "Needs no display. Example:\n"
      "  sphfem post section out/plate --plane 0,0,0,0,1,0 --time 50e-6 --bodies plate,core");
  section->add_option("RUN", c.o.run, "run folder (holding results.pvd and model.h5)")->required();
  section
      ->add_option("--plane", c.plane,
                   "PX,PY,PZ,NX,NY,NZ: a point of the plane (m) and its normal (any length)")
      ->required();
  c.time_option =
      section->add_option("--time", c.time, "time of the frame, s (the nearest frame is used)");
  section->add_flag("--last", c.last, "use the last frame (the default)")->excludes(c.time_option);
  section->add_option("--bodies", c.o.bodies, "bodies to cut, comma-separated (default: all)")
      ->delimiter(',');
  section->add_option("--axis", c.axis,
                      "AX,AY,AZ: deflection axis, projected into the plane (default: the "
                      "in-plane direction closest to z)");
  section->add_option("--u-range", c.u_range,
                      "U0,U1: draw only U0 <= u <= U1 (m from the plane's point); the CSV and "
                      "deflection keep the whole section");
  section
      ->add_option("--field", c.o.field,
                   "colours the cut: plastic_strain, damage or none (outlines only)")
      ->check(CLI::IsMember({"plastic_strain", "damage", "none"}))
      ->capture_default_str();
  section->add_option("-o,--out", c.o.out_dir, "output folder (default: RUN/post)");
  section->add_option("--size", c.size, "image size in pixels, WIDTHxHEIGHT")
      ->capture_default_str();
  return section;
}

void run_post_section(SectionCommand& c) {
  const auto plane = parse_numbers(c.plane, 6, "--plane", "PX,PY,PZ,NX,NY,NZ (six numbers)");
  c.o.point = {plane[0], plane[1], plane[2]};
  c.o.normal = {plane[3], plane[4], plane[5]};
  if (!c.axis.empty()) {
    const auto a = parse_numbers(c.axis, 3, "--axis", "AX,AY,AZ (three numbers)");
    c.o.axis = Vec3(a[0], a[1], a[2]);
  }
  if (!c.u_range.empty()) {
    const auto u = parse_numbers(c.u_range, 2, "--u-range", "U0,U1 (two numbers, m)");
    c.o.u_range = std::array<double, 2>{u[0], u[1]};
  }
  if (c.time_option->count() > 0)
    c.o.time = c.time;
  std::tie(c.o.width, c.o.height) = post::parse_image_size(c.size);
  const auto r = post::write_section(c.o);
  std::cout << "section:    " << r.png.string() << "  (data: " << r.csv.string() << ")\n"
            << "deflection: " << r.deflection_csv.string() << "\n"
            << "summary:    " << r.json.string() << "\n";
  for (const auto& [body, w] : r.max_deflection)
    std::cout << "max |deflection| " << body << ": " << w * 1e3 << " mm\n";
}

struct PlugCommand {
  post::PlugOptions options;
  double time = 0;
  bool last = false; // the default; the flag only documents it and excludes --time
  std::string size = "900x560";
  CLI::App* app = nullptr;
  CLI::Option* time_option = nullptr;
};

void add_post_plug(CLI::App& post, PlugCommand& c) {
  auto& o = c.options;
  c.app = post.add_subcommand(
      "plug", "the fragments separated from the target and the plug: JSON, CSV and a picture");
  c.app->footer(
      "Fragments: connected pieces of the target's surviving particles and elements (particles\n"
      "closer than F x spacing, elements through shared nodes); killed particles and eroded\n"
      "elements are debris. The plug is the most massive fragment after the main one moving\n"
      "along the impact axis (the other bodies' momentum direction in the first frame, else +z)\n"
      "that holds at least N particles and elements (--min-pieces).\n"
      "Writes DIR/plug.json (SI units), DIR/fragments.csv and DIR/plug.png (outlines: convex\n"
      "hulls on a plane containing the impact axis, mm); DIR is -o, else RUN/post. Example:\n"
      "  sphfem post plug out/perforation --time 15e-6");
  c.app->add_option("RUN", o.run, "run folder (holding results.pvd and model.h5)")->required();
  c.app->add_option("--body", o.body, "target body (default: the only body with particles)");
  c.time_option = c.app->add_option("--time", c.time, "time in s: the frame nearest to it");
  c.app->add_flag("--last", c.last, "the last frame (the default)")->excludes(c.time_option);
  c.app->add_option("--connect", o.connect, "connectivity distance F, in lattice spacings")
      ->capture_default_str();
  c.app
      ->add_option("--min-pieces", o.min_pieces,
                   "N: a plug holds at least N particles and elements (smaller moving pieces "
                   "are fragments)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  c.app->add_option("-o,--out", o.out_dir, "output folder (default: RUN/post)");
  c.app->add_option("--size", c.size, "image size in pixels, WIDTHxHEIGHT")->capture_default_str();
}

// One line per finding: what the plug is and where the files are.
void print_plug(const post::PlugResult& r) {
  std::printf("time %.3g s: fragments %zu, debris %.4g kg, impact axis [%.3g, %.3g, %.3g]\n",
              r.time, r.fragments.size(), r.debris_mass, r.impact_axis.x(), r.impact_axis.y(),
              r.impact_axis.z());
  if (r.main >= 0)
    std::printf("main:  fragment %d, %.4g kg\n", r.main, r.fragments[r.main].mass);
  if (r.plug >= 0) {
    const auto& p = r.fragments[r.plug];
    std::printf("plug:  fragment %d, %.4g kg, %.4g m/s along the impact axis, diameter %.3g mm, "
                "thickness %.3g mm\n",
                r.plug, p.mass, p.velocity.dot(r.impact_axis), p.diameter * 1e3, p.thickness * 1e3);
  } else {
    std::printf("plug:  none (no other fragment moves along the impact axis)\n");
  }
  if (r.passed_through)
    std::printf(
        "the projectile's nose is beyond the target's rear face, nothing of the plate ahead of it: "
        "perforated\n");
  std::printf("files: %s, %s, %s\n", r.json.string().c_str(), r.csv.string().c_str(),
              r.png.string().c_str());
}

struct ReportCommand {
  post::ReportOptions options;
  CLI::App* app = nullptr;
};

void add_post_report(CLI::App& post, ReportCommand& c) {
  auto& o = c.options;
  c.app = post.add_subcommand(
      "report", "one self-contained HTML report of a run, beside the case's reference values");
  c.app->footer(
      "Writes DIR/report.html (DIR: -o, else RUN/report) with every picture embedded, so it\n"
      "opens offline as one file: the run's cost, the energy balance, the bodies' velocity\n"
      "histories and residual velocities, a section through the model's centre (normal y),\n"
      "the fragments and plug of the body with particles, and a table against the reference\n"
      "values: reference.csv beside the case file (or --reference), columns\n"
      "quantity,value,unit,source, quantity a path into summary.json\n"
      "(bodies.bar_a.com_velocity.2) or history.<column>.min|max|last. The charts stay beside\n"
      "it as PNG and CSV. `sphfem run` writes it at the end of every run. Example:\n"
      "  sphfem post report out/bar_impact");
  c.app->add_option("RUN", o.run, "run folder (holding summary.json and history.csv)")->required();
  c.app->add_option("--reference", o.reference,
                    "reference CSV (default: reference.csv beside the case file, if any)");
  c.app->add_option("-o,--out", o.out_dir, "output folder (default: RUN/report)");
}

void print_report(const post::Report& r) {
  std::cout << "report:  " << r.html.string() << "  (" << r.images.size()
            << " pictures embedded; open it in a browser)\n";
  for (const auto& row : r.references)
    if (row.found)
      std::printf("  %-40s %12.6g vs %12.6g %-5s %+7.2f%%\n", row.quantity.c_str(), row.value,
                  row.reference, row.unit.c_str(), 100 * row.relative_error());
    else
      std::printf("  %-40s not in this run\n", row.quantity.c_str());
  for (const auto& why : r.skipped)
    std::cout << "  left out: " << why << "\n";
}

struct ChartCommand {
  post::CsvChartOptions options;
  bool markers_only = false;
  std::string size = "900x560";
  CLI::App* app = nullptr;
};

void add_post_chart(CLI::App& post, ChartCommand& c) {
  auto& o = c.options;
  c.app = post.add_subcommand(
      "chart", "a chart of two columns of any CSV file, one series per group, log axes if asked");
  c.app->footer(
      "Reads CSV (a header line, then rows; # lines skipped) and draws column Y against column X\n"
      "as a PNG, one series per distinct value of the --group column, its points joined in file\n"
      "order. With --log-x/--log-y the axis spans whole decades (every value must be > 0).\n"
      "Example (the error-vs-cost chart of docs/accuracy-vs-cost.md):\n"
      "  sphfem post chart docs/charts/accuracy-vs-cost.csv -o cost.png --x wall_s \\\n"
      "      --y error_pct --group model --log-x --log-y --x-label 'wall time (s)'");
  c.app->add_option("CSV", o.csv, "the CSV file")->required();
  c.app->add_option("-o,--out", o.png, "the PNG to write")->required();
  c.app->add_option("--x", o.x, "column on the x axis")->required();
  c.app->add_option("--y", o.y, "column on the y axis")->required();
  c.app->add_option("--group", o.group, "column naming each row's series (default: one series)");
  c.app->add_flag("--log-x", o.log_x, "logarithmic x axis");
  c.app->add_flag("--log-y", o.log_y, "logarithmic y axis");
  c.app->add_flag("--markers-only", c.markers_only, "points only, not joined");
  c.app->add_option("--title", o.title, "chart title");
  c.app->add_option("--x-label", o.x_label, "x axis label (default: the column name)");
  c.app->add_option("--y-label", o.y_label, "y axis label (default: the column name)");
  c.app->add_option("--size", c.size, "image size in pixels, WIDTHxHEIGHT")->capture_default_str();
}

void run_post_chart(ChartCommand& c) {
  c.options.lines = !c.markers_only;
  std::tie(c.options.width, c.options.height) = post::parse_image_size(c.size);
  const post::CsvChart chart = post::write_csv_chart(c.options);
  std::cout << "chart:  " << c.options.png.string() << "  (" << chart.points << " points, "
            << chart.series.size() << " series)\n";
}

} // namespace

struct PostCommands::Options {
  CLI::App* post = nullptr;
  post::HistoryPlotOptions history;
  std::string history_size = "900x560";
  SectionCommand section;
  CLI::App* section_app = nullptr;
  PlugCommand plug;
  ReportCommand report;
  ChartCommand chart;
};

PostCommands::PostCommands(CLI::App& app) : o_(std::make_unique<Options>()) {
  o_->post = app.add_subcommand("post", "charts, sections, fragments and reports from a run");
  o_->post->require_subcommand(1);
  add_post_history(*o_->post, o_->history, o_->history_size);
  o_->section_app = add_post_section(*o_->post, o_->section);
  add_post_plug(*o_->post, o_->plug);
  add_post_report(*o_->post, o_->report);
  add_post_chart(*o_->post, o_->chart);
}

PostCommands::~PostCommands() = default;

bool PostCommands::parsed() const {
  return o_->post->parsed();
}

void PostCommands::run() {
  if (o_->section_app->parsed()) {
    run_post_section(o_->section);
  } else if (o_->plug.app->parsed()) {
    auto& plug = o_->plug;
    std::tie(plug.options.width, plug.options.height) = post::parse_image_size(plug.size);
    if (plug.time_option->count() > 0)
      plug.options.time = plug.time;
    print_plug(post::write_plug(plug.options));
  } else if (o_->chart.app->parsed()) {
    run_post_chart(o_->chart);
  } else if (o_->report.app->parsed()) {
    print_report(post::write_report(o_->report.options));
  } else {
    auto& h = o_->history;
    std::tie(h.width, h.height) = post::parse_image_size(o_->history_size);
    for (const auto& plot : post::plot_history(h))
      std::cout << "chart:  " << plot.png.string() << "  (data: " << plot.csv.string() << ")\n";
  }
}

void write_run_report(const fs::path& run) {
  try {
    const post::Report r = post::write_report({run, {}, {}});
    std::cout << "report:   " << r.html.string() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "sphfem: warning: no report: " << e.what() << "\n";
  }
}

} // namespace sphfem
