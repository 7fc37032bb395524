// `sphfem sweep` (sweep_command.hpp): options, the list of values and the bisection, each run
// through the `run` subcommand (run_command_line, in this process, its output kept out of the
// sweep's own), --resume's reading of the runs' folders and checkpoints, the stop on a signal,
// and the tables. No physics here; the tables and the fit are in post/.
#include "app/sweep_command.hpp"

#include "app/commands.hpp"
#include "post/sweep.hpp"
#include "post/text.hpp"
#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/time/restart_check.hpp"
#include "solver/time/run.hpp"
#include "solver/time/stop_signals.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <sstream>

namespace sphfem {

namespace {

namespace fs = std::filesystem;

// The experiment's impact velocities (m/s): Børvik et al., 12 mm Weldox 460 E plates, as printed
// in Table 3 of Zhang, Qiang & Gao, Eng. Struct. 33 (2011) 255–264
// (Børvik et al.; the paper's Table 3, the rows with an experimental residual velocity).
const std::vector<double> experiment_velocities{181.5, 189.6, 200.4, 224.7, 244.2, 285.4, 303.5};

// %.7g: to 0.1 mm/s at ballistic speeds, short enough for folder names; the run's v0 is the
// number as written, so the table holds exactly what was run.
std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", v);
  return text;
}

std::string fixed(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", v);
  return text;
}

std::vector<double> values_of(const SweepCommandOptions& o) {
  if (!o.values_given) {
    if (o.key != "projectile.velocity")
      throw Error("--values: required for --key " + o.key +
                  " (the experiment's velocities are the default only for projectile.velocity)");
    return experiment_velocities;
  }
  std::vector<double> values;
  for (const std::string& text : o.values) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (text.empty() || used != text.size() || !std::isfinite(v))
      throw Error("--values: expected comma-separated numbers, got '" + text + "'");
    values.push_back(v);
  }
  if (values.empty())
    throw Error("--values: expected comma-separated numbers, got none");
  return values;
}

// --param KEY=START:STOP:STEP as --key KEY --values START,START+STEP,...,STOP (inclusive).
void expand_param(SweepCommandOptions& o) {
  const auto fail = [&o](const std::string& what) {
    throw Error("--param: expected KEY=START:STOP:STEP with STEP > 0 and STOP >= START, " + what +
                " in '" + o.param + "'");
  };
  if (o.values_given)
    fail("not with --values,");
  const auto equals = o.param.find('=');
  if (equals == std::string::npos || equals == 0)
    fail("no KEY=");
  std::vector<double> range;
  std::stringstream s(o.param.substr(equals + 1));
  for (std::string part; std::getline(s, part, ':');) {
    std::size_t used = 0;
    try {
      range.push_back(std::stod(part, &used));
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size() || !std::isfinite(range.back()))
      fail("'" + part + "' is not a number");
  }
  if (range.size() != 3 || range[2] <= 0 || range[1] < range[0])
    fail("got something else");
  const double n = std::floor((range[1] - range[0]) / range[2] * (1 + 1e-12));
  if (n > 1000)
    fail("more than 1000 values");
  o.key = o.param.substr(0, equals);
  o.values.clear();
  for (int k = 0; k <= static_cast<int>(n); ++k)
    o.values.push_back(number_text(range[0] + k * range[2]));
  o.values_given = true;
}

std::string yaml_value(const SweepCommandOptions& o, const std::string& number) {
  std::string value = o.format;
  const auto at = value.find("{}");
  if (at == std::string::npos)
    throw Error("--format: expected {} where the number goes, got '" + o.format + "'");
  return value.replace(at, 2, number);
}

std::vector<std::string> overrides_for(const SweepCommandOptions& o, const std::string& value) {
  std::vector<std::string> overrides = o.overrides;
  overrides.push_back(o.key + "=" + value);
  return overrides;
}

// The comma-separated items of `option`'s `text`, trimmed; none may be empty.
std::vector<std::string> list_of(const std::string& option, const std::string& text) {
  std::vector<std::string> items;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) {
    const auto first = item.find_first_not_of(' ');
    items.push_back(first == std::string::npos
                        ? ""
                        : item.substr(first, item.find_last_not_of(' ') - first + 1));
  }
  if (text.empty() || text.back() == ',' || std::ranges::count(items, "") > 0)
    throw Error(option + ": expected comma-separated names, got an empty one in '" + text + "'");
  return items;
}

// --reference FILE --reference-columns v0,vr[,other...] [--reference-labels L,...]: the first
// vr column is the reference the errors are against; the others are comparison series.
void read_reference(const SweepCommandOptions& o, post::Sweep& sweep) {
  const std::vector<std::string> columns = list_of("--reference-columns", o.reference_columns);
  if (columns.size() < 2 || std::ranges::any_of(columns, [&columns](const std::string& c) {
        return std::ranges::count(columns, c) > 1;
      }))
    throw Error("--reference-columns: expected v0,vr[,other...], distinct column names, got '" +
                o.reference_columns + "'");
  const std::vector<std::string> vr_columns(columns.begin() + 1, columns.end());
  std::vector<std::string> labels = vr_columns;
  if (!o.reference_labels.empty()) {
    labels = list_of("--reference-labels", o.reference_labels);
    if (labels.size() != vr_columns.size())
      throw Error("--reference-labels: expected one label per vr column of --reference-columns (" +
                  std::to_string(vr_columns.size()) + "), got " + std::to_string(labels.size()) +
                  " in '" + o.reference_labels + "'");
  }
  std::vector<post::ReferenceSeries> series =
      post::read_ballistic_reference(o.reference, columns.front(), vr_columns);
  for (std::size_t k = 0; k < series.size(); ++k)
    series[k].label = labels[k];
  sweep.reference_file = o.reference;
  sweep.reference = series.front();
  sweep.comparisons.assign(series.begin() + 1, series.end());
}

// Keeps the inner run's stdout and stderr out of the sweep's own while it runs.
class Captured {
public:
  Captured() : out_(std::cout.rdbuf(out_text_.rdbuf())), err_(std::cerr.rdbuf(err_text_.rdbuf())) {}
  ~Captured() {
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
  }
  Captured(const Captured&) = delete;
  Captured& operator=(const Captured&) = delete;
  // The run's error line, if it printed one.
  std::string error() const {
    std::istringstream lines(err_text_.str());
    std::string line, last;
    while (std::getline(lines, line))
      if (line.rfind("sphfem: ", 0) == 0 && line.find("error") != std::string::npos)
        last = line;
    return last;
  }

private:
  std::ostringstream out_text_, err_text_;
  std::streambuf *out_, *err_;
};

// What --resume does with a run's folder: run it from the start, continue it from its
// checkpoint, or take the results of a run that reached the end time.
enum class Resume { from_start, from_checkpoint, finished };

struct RunPlan {
  post::SweepRun run;
  Resume resume = Resume::from_start;
  double checkpoint_time = 0; // s, when continued
};

RunPlan plan_run(const SweepCommandOptions& o, double v0) {
  RunPlan plan;
  post::SweepRun& run = plan.run;
  const std::string number = number_text(v0);
  run.v0 = std::stod(number);
  run.value = yaml_value(o, number);
  run.folder = fs::path(o.out_dir) / ("run_" + o.key + "_" + number);
  const fs::path checkpoint = run.folder / "checkpoint.h5";
  if (!o.resume || !fs::exists(checkpoint))
    return plan;
  const Case c = read_case(o.case_file, overrides_for(o, run.value));
  CheckpointMeta meta;
  try {
    meta = read_checkpoint_meta(checkpoint);
  } catch (const Error& e) {
    std::cerr << "sweep: " << e.what() << "; running " << run.folder.string()
              << " again from the start\n";
    return plan;
  }
  try {
    check_restart_case(checkpoint, meta, c);
  } catch (const Error& e) {
    throw Error(std::string("--resume: ") + e.what() +
                "; the folder holds another sweep's run: use another -o, or leave out --resume "
                "to run it again");
  }
  const double eps = 1e-9 * c.time.end; // the run loop's
  if (meta.time < c.time.end - eps) {
    plan.resume = Resume::from_checkpoint;
    plan.checkpoint_time = meta.time;
    return plan;
  }
  if (meta.time <= c.time.end + eps) {
    post::read_run_results(run);
    if (run.known()) {
      plan.resume = Resume::finished;
      return plan;
    }
    run.note.clear(); // the report is missing: the restart makes it again
    plan.resume = Resume::from_checkpoint;
    plan.checkpoint_time = meta.time;
  }
  return plan; // a run beyond this end time cannot be taken back: from the start
}

// The run's wall time as its summary.json gives it (solve only), for a run made earlier.
double summary_wall_time(const fs::path& folder) {
  try {
    return nlohmann::json::parse(post::slurp(folder / "summary.json")).value("wall_s", 0.0);
  } catch (const std::exception&) {
    return 0;
  }
}

post::SweepRun run_one(const SweepCommandOptions& o, RunPlan plan) {
  post::SweepRun& run = plan.run;
  if (plan.resume == Resume::finished) {
    run.wall_s = summary_wall_time(run.folder);
    return run;
  }
  std::vector<std::string> args{"sphfem", "run", o.case_file, "-o", run.folder.string(), "-q"};
  if (plan.resume == Resume::from_checkpoint) {
    std::cerr << "sweep: " << o.key << " = " << run.value
              << ": continuing from t = " << plan.checkpoint_time << " s\n";
    args.push_back("--restart");
    args.push_back((run.folder / "checkpoint.h5").string());
  }
  for (const std::string& s : overrides_for(o, run.value)) {
    args.push_back("--set");
    args.push_back(s);
  }
  if (o.threads > 0) {
    args.push_back("-j");
    args.push_back(std::to_string(o.threads));
  }
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(a.data());

  const auto start = std::chrono::steady_clock::now();
  int code = 0;
  std::string error;
  {
    Captured captured;
    code = run_command_line(static_cast<int>(argv.size()), argv.data());
    error = captured.error();
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (code == 128 + SIGINT || code == 128 + SIGTERM) {
    run.note = "stopped by a signal, its checkpoint kept";
    return run;
  }
  if (code != 0) {
    run.note =
        "run failed (exit " + std::to_string(code) + ")" + (error.empty() ? "" : ": ") + error;
    return run;
  }
  post::read_run_results(run);
  return run;
}

void print_progress(const SweepCommandOptions& o, const post::SweepRun& r, Resume resume) {
  std::cerr << "sweep: " << o.key << " = " << r.value << ": ";
  if (!r.perforated)
    std::cerr << "unknown (" << r.note << ")";
  else if (*r.perforated)
    std::cerr << "perforated, vr "
              << (r.residual_projectile ? fixed(*r.residual_projectile) + " m/s" : "unknown");
  else
    std::cerr << "not perforated";
  std::cerr << ", " << fixed(r.wall_s) << " s"
            << (resume == Resume::finished ? " (run before)" : "") << "\n";
}

std::string command_text(const SweepCommandOptions& o) {
  std::string text = "sphfem sweep " + o.case_file + " -o " + o.out_dir + " --key " + o.key;
  if (!o.values.empty()) {
    text += " --values ";
    for (std::size_t k = 0; k < o.values.size(); ++k)
      text += (k ? "," : "") + o.values[k];
  }
  if (o.format != "{}")
    text += " --format '" + o.format + "'";
  if (o.bisect)
    text += " --bisect --tolerance " + number_text(o.tolerance);
  for (const std::string& s : o.overrides)
    text += " --set " + s;
  if (o.threads > 0)
    text += " -j " + std::to_string(o.threads);
  if (!o.reference.empty())
    text += " --reference " + o.reference + " --reference-columns " + o.reference_columns;
  if (!o.reference_labels.empty())
    text += " --reference-labels '" + o.reference_labels + "'";
  return text;
}

} // namespace

CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& o) {
  auto* cmd = app.add_subcommand(
      "sweep", "run a case at many values of one key: the ballistic curve and its limit");
  cmd->footer(
      "Each value is run as `sphfem run CASE -o DIR/run_<key>_<value> --set <key>=<value>`;\n"
      "the results are read from each run's summary.json (results.perforated, residual\n"
      "velocities, plug mass). --bisect then halves the bracket between the highest\n"
      "non-perforating and the lowest perforating value until it is at most --tolerance wide;\n"
      "if every run perforated it first runs lower (0.95 sqrt(v0^2 - vr^2) of the slowest),\n"
      "if none did higher (1.5 x the fastest), saying so, up to 8 times, until it has one.\n"
      "A Recht-Ipson curve vr = a (v0^p - vbl^p)^(1/p) is fitted to the perforating runs.\n"
      "--reference compares the runs and the fit with one vr column of a CSV file and, from\n"
      "further vr columns, compares other results (a paper's) with it alike, side by side.\n"
      "Writes DIR/sweep.csv, sweep.json, ballistic_curve.png and sweep.html.\n"
      "Ctrl-C (SIGINT) or SIGTERM stops the run in progress at its next step with a checkpoint;\n"
      "the same command with --resume continues the sweep where it stopped. Examples:\n"
      "  sphfem sweep case.yaml --param projectile.velocity=180:310:10 -o sweep\n"
      "  sphfem sweep case.yaml -o sweep --bisect \\\n"
      "    --reference borvik_12mm_table3.csv --reference-columns v0,exp_vpr,spfem_vpr \\\n"
      "    --reference-labels 'experiment,paper SPH-FEM'\n"
      "  sphfem sweep punch.yaml -o s --key bodies.projectile.velocity --format '[0,0,-{}]' \\\n"
      "    --values 300,800");
  cmd->add_option("case", o.case_file, "case file (YAML, SI units)")->required();
  cmd->add_option("-o,--out", o.out_dir, "output folder")->required();
  cmd->add_option("--key", o.key, "the case key to sweep")->capture_default_str();
  cmd->add_option("--param", o.param,
                  "KEY=START:STOP:STEP: --key KEY and the values START to STOP (inclusive), "
                  "e.g. projectile.velocity=180:310:10");
  cmd->add_option_function<std::vector<std::string>>(
         "--values",
         [&o](const std::vector<std::string>& values) {
           o.values = values;
           o.values_given = true;
         },
         "comma-separated numbers, m/s (default for projectile.velocity: the experiment's "
         "impact velocities, Borvik et al.)")
      ->delimiter(',');
  cmd->add_option("--format", o.format,
                  "the key's YAML value with {} for the number, e.g. '[0,0,-{}]'")
      ->capture_default_str();
  cmd->add_flag("--bisect", o.bisect, "bisect the ballistic limit after the list");
  cmd->add_flag("--resume", o.resume,
                "continue a stopped sweep in the same -o: runs that reached the end are taken "
                "as they are, stopped ones continue from their checkpoints, the rest run");
  cmd->add_option("--tolerance", o.tolerance, "bisection bracket width to stop at, m/s")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--set", o.overrides,
                  "override another case key in every run (repeatable; value is YAML)")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_option("-j,--threads", o.threads, "OpenMP threads per run (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--reference", o.reference,
                  "reference curve, CSV with columns v0,vr (m/s) and optionally label; an empty "
                  "cell is no point");
  cmd->add_option("--reference-columns", o.reference_columns,
                  "v0,vr[,other...]: the v0 column, the reference's vr column, and vr columns of "
                  "comparison series drawn and compared with the reference as the runs are")
      ->capture_default_str();
  cmd->add_option("--reference-labels", o.reference_labels,
                  "one label per vr column of --reference-columns, comma-separated, for the "
                  "chart and the tables (default: the column names)");
  return cmd;
}

void run_sweep_command(const SweepCommandOptions& options) {
  SweepCommandOptions o = options;
  if (!o.param.empty())
    expand_param(o);
  const std::vector<double> values = values_of(o);
  post::Sweep sweep;
  sweep.case_file = o.case_file;
  sweep.key = o.key;
  sweep.command = command_text(o);
  if (!o.reference.empty())
    read_reference(o, sweep);
  else if (!o.reference_labels.empty())
    throw Error("--reference-labels: only with --reference");
  // Bad keys and values stop the sweep before the first run, with the case reader's message.
  for (const double v : values)
    read_case(o.case_file, overrides_for(o, yaml_value(o, number_text(v))));

  // With --resume, another sweep's runs in the folder stop this one before its first run.
  std::vector<RunPlan> plans;
  for (const double v : values)
    plans.push_back(plan_run(o, v));

  const StopSignals signals; // a signal stops the run in progress (its own StopSignals) and then
                             // the sweep
  const auto run_next = [&](const RunPlan& plan) {
    sweep.runs.push_back(run_one(o, plan));
    print_progress(o, sweep.runs.back(), plan.resume);
    if (const int signal = signals.received())
      throw Interrupted(
          detail::concat("sweep interrupted by ", signal == SIGINT ? "SIGINT" : "SIGTERM",
                         " during the run in ", sweep.runs.back().folder.string(),
                         " (its checkpoint and the other runs' folders are kept); continue with: ",
                         command_text(o), " --resume"),
          signal);
  };
  for (const RunPlan& plan : plans)
    run_next(plan);
  const auto already_run = [&sweep](double v) {
    return std::ranges::any_of(
        sweep.runs, [v](const post::SweepRun& r) { return number_text(r.v0) == number_text(v); });
  };
  if (o.bisect) {
    // First a bracket (every run perforated, or none did: extend the list), then halve it.
    constexpr int most_extensions = 8;
    for (int extensions = 0;;) {
      const std::vector<post::BallisticPoint> points = post::ballistic_points(sweep.runs);
      if (const auto step = post::next_bracket_step(points)) {
        if (extensions == most_extensions || already_run(step->v0) || !(step->v0 > 0)) {
          std::cout << "sweep: no bracket of the ballistic limit after " << extensions
                    << " extensions (" << step->reason << " was next); not bisecting\n";
          break;
        }
        ++extensions;
        std::cout << "sweep: " << step->reason << "\n";
        run_next(plan_run(o, step->v0));
        continue;
      }
      const auto v = post::next_bisection(points, o.tolerance);
      if (!v || already_run(*v)) // done, or the bracket is below the values' resolution
        break;
      run_next(plan_run(o, *v));
    }
  }
  sweep.fit = post::fit_recht_ipson(post::ballistic_points(sweep.runs));
  const post::SweepFiles files = post::write_sweep(sweep, o.out_dir);

  if (sweep.fit)
    std::cout << "ballistic limit " << number_text(sweep.fit->vbl) << " m/s (Recht-Ipson: p "
              << number_text(sweep.fit->p) << ", a " << number_text(sweep.fit->a) << ", rms "
              << number_text(sweep.fit->rms) << " m/s over " << sweep.fit->points
              << " perforating runs)\n";
  else
    std::cout << "no Recht-Ipson fit: it needs at least three perforating runs\n";
  std::cout << "table:  " << files.csv.string() << "\n"
            << "json:   " << files.json.string() << "\n"
            << "chart:  " << files.png.string() << "\n"
            << "page:   " << files.html.string() << "\n";
}

} // namespace sphfem
