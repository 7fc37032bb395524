#include "post/post.hpp"

#include "solver/core/error.hpp"

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

History read_history_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  SPHFEM_CHECK(in, file.string(), ": cannot open");
  History h;
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
  h.columns = cells(line);
  for (const auto& c : h.columns) {
    SPHFEM_CHECK(!c.empty(), file.string(), ":", number, ": empty column name");
    SPHFEM_CHECK(h.values.emplace(c, std::vector<double>{}).second, file.string(), ":", number,
                 ": column ", c, " appears twice");
  }
  while (next_line()) {
    const auto row = cells(line);
    SPHFEM_CHECK(row.size() == h.columns.size(), file.string(), ":", number, ": expected ",
                 h.columns.size(), " values, found ", row.size());
    for (std::size_t c = 0; c < row.size(); ++c) {
      double value = std::numeric_limits<double>::quiet_NaN(); // an empty cell is a gap
      if (!row[c].empty()) {
        char* end = nullptr; // strtod, not stod: a denormal is a number, not an error
        value = std::strtod(row[c].c_str(), &end);
        SPHFEM_CHECK(end == row[c].c_str() + row[c].size(), file.string(), ":", number, ": column ",
                     h.columns[c], ": not a number: ", row[c]);
      }
      h.values[h.columns[c]].push_back(value);
    }
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
       it != std::sregex_iterator(); ++it)
    out.emplace_back(std::stod((*it)[1]), (*it)[2]);
  return out;
}

} // namespace sphfem::post
