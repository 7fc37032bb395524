// Ballistic sweeps (`sphfem sweep`, app/sweep_command.hpp): the results of many runs that differ
// in one case key (the impact velocity), read back from each run's summary.json ("results":
// perforated, residual velocities of projectile and plug along the impact axis, plug mass), the
// bisection of the ballistic limit, a reference curve (an experiment) with comparison series from
// the same file (another code's or a paper's results for the same tests), and the tables, chart
// and page: DIR/sweep.csv, sweep.json, ballistic_curve.png and sweep.html. A run without those
// results (an older run, a failed one) is "unknown": listed, never fitted. Velocities in m/s,
// masses in kg, times in s. Verified by tests/post/sweep_test.cpp.
#pragma once

#include "post/recht_ipson.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sphfem::post {

struct SweepRun {
  double v0 = 0;                  // the swept number, m/s
  std::string value;              // the key's value as given to --set (YAML)
  std::filesystem::path folder;   // the run's output folder
  std::optional<bool> perforated; // empty: unknown
  std::optional<double> residual_projectile, residual_plug, plug_mass; // m/s, m/s, kg
  double wall_s = 0; // the whole run: mesh, solve and report
  std::string note;  // why the results are unknown

  bool known() const { return perforated.has_value(); }
};

// Fills `run`'s results from FOLDER/summary.json; what is missing is left empty and named in
// `run.note`.
void read_run_results(SweepRun& run);

// The runs whose outcome is known, as points of the ballistic curve (vr: the projectile's).
std::vector<BallisticPoint> ballistic_points(const std::vector<SweepRun>& runs);

// The next impact velocity to run when bisecting the ballistic limit: the middle of the bracket
// (highest non-perforating v0 below the lowest perforating v0, lowest perforating v0), or
// nothing when the bracket is at most `tolerance` wide or there is no bracket yet.
std::optional<double> next_bisection(const std::vector<BallisticPoint>& points, double tolerance);

// When there is no bracket yet, the next impact velocity that should make one, and why:
// every run perforated — below the lowest, at 0.95 √(v0² − vr²) of its (v0, vr), the limit a
// Recht–Ipson curve with p = 2 and a = 1 would put through it (a ≤ 1 puts the real one lower
// still; a step of at least 10%); no run perforated — above the highest, by half. Nothing once a
// bracket exists or without points.
struct BracketStep {
  double v0 = 0;      // m/s
  std::string reason; // "every run perforated: extending downward to … m/s"
};
std::optional<BracketStep> next_bracket_step(const std::vector<BallisticPoint>& points);

struct ReferencePoint {
  double v0 = 0, vr = 0; // m/s
  std::string label;     // the row's `label` cell, if the file has that column
};

// One vr column of a reference file: the rows with a number in it.
struct ReferenceSeries {
  std::string column;
  std::string label; // in the chart's legend and the tables (the column's name unless set)
  std::vector<ReferencePoint> points;
};

// Reads reference curves: CSV with a header naming the columns `v0_column` and each of
// `vr_columns` (m/s) and optionally `label`; # comments. One series per vr column, in order: a
// row with an empty v0 cell is skipped, one with an empty vr cell is skipped for that column
// only. Errors name the file and line; a column missing from the header, the option that names
// it (--reference-columns).
std::vector<ReferenceSeries>
read_ballistic_reference(const std::filesystem::path& file, const std::string& v0_column = "v0",
                         const std::vector<std::string>& vr_columns = {"vr"});

struct Sweep {
  std::string case_file, key, command; // command: the sweep's own command line, for the page
  std::vector<SweepRun> runs;
  std::optional<RechtIpson> fit;
  std::filesystem::path reference_file;     // empty: none
  ReferenceSeries reference;                // the errors are against it
  std::vector<ReferenceSeries> comparisons; // from the same file, compared with it as the runs are
};

struct SweepFiles {
  std::filesystem::path csv, json, png, html;
};

// Writes DIR/sweep.csv, sweep.json, ballistic_curve.png and sweep.html, the runs sorted by v0.
// With a reference: a table, ascending in v0, with a row per reference point and per other v0 of
// a comparison: the vr of the reference, of the run at that v0 (the last known one) and of each
// comparison (its first point there); at the reference's points the errors (vr − the
// reference's) of the run, the fit and each comparison that has a value there; and the rms of
// each over its points with an error, with their number, side by side. A non-perforating run
// counts as vr = 0.
SweepFiles write_sweep(const Sweep& sweep, const std::filesystem::path& dir);

} // namespace sphfem::post
