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

// A header of unique column names, then rows of as many numbers; blank lines, lines starting
// with # and a Windows line end are skipped, an empty cell is NaN (a gap). Errors name file:line.
History read_history_csv(const std::filesystem::path& file);

// (time s, frame file as written in the collection, relative to the .pvd's folder).
std::vector<std::pair<double, std::string>> read_pvd(const std::filesystem::path& file);

} // namespace sphfem::post
