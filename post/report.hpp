// `sphfem post report`: one self-contained HTML page per run (OUT/report/report.html, every
// picture embedded as a base64 PNG, so it opens offline and can be mailed as one file): the
// case, the run's cost, the energy balance chart, the bodies' velocity histories, their
// residual velocities, a deformed section, the fragments and plug, and a table against the
// case's reference values. The charts are also left beside it as PNG and CSV, and the
// comparison as reference.csv (quantity,reference,value,unit,relative_error,source).
// With a body of particles the report also writes summary.json's "results" (DESIGN.md):
// perforated (a plug, post/plug.hpp, has separated), residual_velocity.projectile and .plug
// (m/s along the impact axis, 0 without perforation; the projectile is the other body with
// the largest initial momentum along that axis), plug.mass (kg) and its size (m), and each one's
// speed (m/s), deviation_deg from the impact axis and, for a plate scene, angle_from_normal_deg
// from the plate's normal −z (null for what does not leave).
// A reference file is `reference.csv` in the case's folder (the run records its case file in
// summary.json), with columns quantity,value,unit,source: quantity is a path into
// summary.json (`bodies.bar_a.com_velocity.2`, `energy.balance_error`, `results.plug.mass`)
// or `history.<column>.min|max|last` of history.csv (`history.contact.bar_b.fz.max`), and
// each row is reported with the run's value and the relative error.
// Verified by tests/post/report_test.cpp.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sphfem::post {

struct ReportOptions {
  std::filesystem::path run;       // OUT, holding summary.json, history.csv and the frames
  std::filesystem::path reference; // empty: reference.csv in the case's folder, if any
  std::filesystem::path out_dir;   // empty: OUT/report
};

struct ReferenceRow {
  std::string quantity, unit, source;
  std::string when; // "path=value": the row applies to runs whose summary.json has it; "": all
  double reference = 0, value = 0;
  bool found = false; // whether the run has the quantity
  double relative_error() const;
};

struct Report {
  std::filesystem::path html;
  std::vector<std::filesystem::path> images;
  std::vector<ReferenceRow> references;
  std::vector<std::string> skipped; // parts left out, with the reason
};

// Writes the report; a missing summary.json or history.csv is an Error (nothing written),
// a part that cannot be made (no frames, no particles) is left out and listed in `skipped`.
Report write_report(const ReportOptions& options);

// Reads a reference CSV (quantity,value,unit,source[,when]; # comments); errors name file:line.
// `when` (e.g. scene.projectile.velocity=303.5) limits a row to the runs whose summary.json has
// that value at that path (numbers equal to 1e-9 relative), so one file serves several runs.
std::vector<ReferenceRow> read_reference_csv(const std::filesystem::path& file);

// RFC 4648 base64 of `bytes`.
std::string base64(const std::string& bytes);

} // namespace sphfem::post
