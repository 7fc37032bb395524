// `sphfem post chart`: one chart of two columns of any CSV file, one series per distinct value
// of a grouping column (in order of first appearance), points joined in file order, either axis
// optionally logarithmic — the error-vs-cost charts of docs/ are drawn by it. The CSV follows
// read_csv_table (post.hpp); x and y cells must be numbers, an empty one is a gap. Verified by
// tests/post/csv_chart_test.cpp.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sphfem::post {

struct CsvChartOptions {
  std::filesystem::path csv;
  std::filesystem::path png; // the chart written
  std::string x, y;          // column names
  std::string group;         // column naming each row's series; empty: one series, named y
  bool log_x = false, log_y = false;
  bool lines = true;                   // join a series' points (else markers only)
  std::string title, x_label, y_label; // labels default to the column names
  int width = 900, height = 560;
};

struct CsvChart {
  std::vector<std::string> series; // legend names, in order
  std::size_t points = 0;          // points drawn (finite and, on a log axis, positive)
};

// Draws the chart; an absent column, a non-number or a value ≤ 0 on a logarithmic axis is an
// Error naming the file and line (nothing written).
CsvChart write_csv_chart(const CsvChartOptions& o);

} // namespace sphfem::post
