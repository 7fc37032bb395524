#include "post/post.hpp"

#include "solver/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <regex>

namespace sphfem::post {

const std::vector<double>& History::operator[](const std::string& column) const {
  const auto it = values.find(column);
  SPHFEM_CHECK(it != values.end(), "history has no column ", column);
  return it->second;
}

namespace {

std::string trim(const std::string& s) {
  const std::size_t first = s.find_first_not_of(" \t");
  return first == std::string::npos ? "" : s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// The comma-separated cells of a line, trimmed ("a,,b," has four).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t end; (end = line.find(',', start)) != std::string::npos; start = end + 1)
    out.push_back(trim(line.substr(start, end - start)));
  out.push_back(trim(line.substr(start)));
  return out;
}

} // namespace

CsvTable read_csv_table(const std::filesystem::path& file) {
  std::ifstream in(file);
  SPHFEM_CHECK(in, file.string(), ": cannot open");
  CsvTable t;
  t.file = file;
  std::string line;
  int number = 0;
  auto next_line = [&] { // skips blank and # comment lines; drops a Windows \r
    while (std::getline(in, line)) {
      ++number;
      if (!line.empty() && line.back() == '\r')
        line.pop_back();
      if (line.find_first_not_of(" \t") != std::string::npos && line[0] != '#')
        return true;
    }
    return false;
  };
  SPHFEM_CHECK(next_line(), file.string(), ": empty file, expected a header line");
  t.columns = cells(line);
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    SPHFEM_CHECK(!t.columns[c].empty(), file.string(), ":", number, ": empty column name");
    SPHFEM_CHECK(std::find(t.columns.begin(), t.columns.begin() + c, t.columns[c]) ==
                     t.columns.begin() + c,
                 file.string(), ":", number, ": column ", t.columns[c], " appears twice");
  }
  while (next_line()) {
    t.rows.push_back(cells(line));
    t.line_of_row.push_back(number);
    SPHFEM_CHECK(t.rows.back().size() == t.columns.size(), file.string(), ":", number,
                 ": expected ", t.columns.size(), " values, found ", t.rows.back().size());
  }
  return t;
}

std::size_t CsvTable::column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end()) {
    std::string all;
    for (const auto& c : columns)
      all += (all.empty() ? "" : ", ") + c;
    throw Error(file.string() + ": no column " + name + " (columns: " + all + ")");
  }
  return std::size_t(it - columns.begin());
}

double CsvTable::number(std::size_t row, std::size_t c) const {
  const std::string& cell = rows[row][c];
  if (cell.empty())
    return std::numeric_limits<double>::quiet_NaN(); // an empty cell is a gap
  char* end = nullptr; // strtod, not stod: a denormal is a number, not an error
  const double value = std::strtod(cell.c_str(), &end);
  SPHFEM_CHECK(end == cell.c_str() + cell.size(), file.string(), ":", line_of_row[row], ": column ",
               columns[c], ": not a number: ", cell);
  return value;
}

History read_history_csv(const std::filesystem::path& file) {
  const CsvTable t = read_csv_table(file);
  History h;
  h.columns = t.columns;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    auto& values = h.values[t.columns[c]];
    values.reserve(t.rows.size());
    for (std::size_t r = 0; r < t.rows.size(); ++r)
      values.push_back(t.number(r, c));
  }
  return h;
}

std::vector<std::pair<double, std::string>> read_pvd(const std::filesystem::path& file) {
  std::ifstream in(file);
  SPHFEM_CHECK(in, file.string(), ": cannot open");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  static const std::regex dataset(R"re(<DataSet\s+timestep="([^"]+)"[^>]*file="([^"]+)")re");
  std::vector<std::pair<double, std::string>> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset);
       it != std::sregex_iterator(); ++it) {
    const std::string time = (*it)[1];
    char* end = nullptr;
    const double t = std::strtod(time.c_str(), &end);
    SPHFEM_CHECK(end != time.c_str() && *end == '\0' && std::isfinite(t), file.string(), ":",
                 1 + std::count(text.begin(), text.begin() + it->position(), '\n'),
                 ": DataSet timestep \"", time, "\": expected a time in s");
    out.emplace_back(t, (*it)[2]);
  }
  return out;
}

} // namespace sphfem::post
