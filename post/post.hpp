// Reading results back for scripts and tests: history.csv as named columns and results.pvd
// as its list of (time, frame file). The extraction tools (sections, plug, reports) build
// on these.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace sphfem::post {

struct History {
  std::vector<std::string> columns;
  std::map<std::string, std::vector<double>> values; // column → one value per row

  const std::vector<double>& operator[](const std::string& column) const;
  std::size_t rows() const { return columns.empty() ? 0 : values.at(columns[0]).size(); }
};

// A CSV file as text: a header of unique column names, then rows of as many cells (trimmed);
// blank lines, lines starting with # and a Windows line end are skipped. Errors name file:line.
struct CsvTable {
  std::filesystem::path file;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> line_of_row; // line numbers in the file, for messages

  // The index of `name`; an Error naming the file and the columns there are if it is absent.
  std::size_t column(const std::string& name) const;
  // Row `row`'s cell of column `c` as a number; an empty cell is NaN (a gap), text an Error
  // naming file:line and the column.
  double number(std::size_t row, std::size_t c) const;
};
CsvTable read_csv_table(const std::filesystem::path& file);

// A CsvTable of numbers only (an empty cell is NaN, a gap).
History read_history_csv(const std::filesystem::path& file);

// (time s, frame file as written in the collection, relative to the .pvd's folder).
std::vector<std::pair<double, std::string>> read_pvd(const std::filesystem::path& file);

} // namespace sphfem::post
