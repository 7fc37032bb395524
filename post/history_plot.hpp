// `sphfem post history`: run histories (OUT/history.csv) as charts. For each chosen column one
// PNG, DIR/<column>.png, with the column against time from the run and from each compared run
// on the same axes (legend = run label) and, dashed, the same-named column of a reference CSV;
// and one CSV, DIR/<column>.csv, of exactly what is plotted, in the chart's units:
//     series,time [us],mid.vz [m/s]
//     bar_pressed_fe,0,0
//     ...
// Units: time in s, ms, us or ns by option; velocity m/s; stresses and pressures (s**,
// pressure, von_mises) GPa; displacements mm; energies J. A reference file is in SI units like
// history.csv (a `time` column in s; empty cells are gaps). Verified by
// tests/post/post_history_test.cpp.
#pragma once

#include "post/post.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace sphfem::post {

struct HistoryPlotOptions {
  std::filesystem::path run;                  // OUT, holding history.csv
  std::vector<std::filesystem::path> compare; // more runs on the same axes
  std::vector<std::string> labels;  // legend names of run, compare…; default folder name
  std::vector<std::string> columns; // empty: default_history_columns(), or those of:
  std::vector<std::string> probes;  // these probes' vz and szz
  std::vector<std::string> bodies;  // these bodies' centre-of-mass vz
  std::filesystem::path reference;  // optional CSV with `time` and same-named columns
  std::filesystem::path out_dir;    // empty: OUT/plots
  std::string time_unit = "us";     // s, ms, us or ns
  int width = 900, height = 560;    // pixels
};

struct HistoryPlot {
  std::string column;
  std::filesystem::path png, csv;
};

// Writes the charts and their CSVs; bad input throws sphfem::Error before anything is written.
std::vector<HistoryPlot> plot_history(const HistoryPlotOptions& options);

// Every probe's vz and szz and every body's vz, in the file's column order.
std::vector<std::string> default_history_columns(const History& history);
// The vz and szz of the named probes and the vz of the named bodies, in the file's column
// order; an unknown name is an Error that lists the known ones.
std::vector<std::string> selected_history_columns(const History& history,
                                                  const std::vector<std::string>& probes,
                                                  const std::vector<std::string>& bodies);

// How a column is plotted: plotted value = SI value × scale, in `unit`.
struct PlotUnit {
  double scale;
  std::string unit;
};
PlotUnit column_unit(const std::string& column);
PlotUnit time_unit(const std::string& name); // "s", "ms", "us" or "ns"

// "900x560" → {900, 560}.
std::pair<int, int> parse_image_size(const std::string& text);

} // namespace sphfem::post
