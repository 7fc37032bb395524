#include "post/post.hpp"

#include "solver/core/error.hpp"

#include <fstream>
#include <regex>
#include <sstream>

namespace sphfem::post {

const std::vector<double>& History::operator[](const std::string& column) const {
  const auto it = values.find(column);
  SPHFEM_CHECK(it != values.end(), "history has no column ", column);
  return it->second;
}

History read_history_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  SPHFEM_CHECK(in, file.string(), ": cannot open");
  History h;
  std::string line, cell;
  SPHFEM_CHECK(std::getline(in, line), file.string(), ": empty file, expected a header line");
  std::istringstream header(line);
  while (std::getline(header, cell, ','))
    h.columns.push_back(cell);
  for (const auto& c : h.columns)
    h.values[c];
  for (int number = 2; std::getline(in, line); ++number) {
    std::istringstream row(line);
    std::size_t column = 0;
    for (; std::getline(row, cell, ','); ++column) {
      SPHFEM_CHECK(column < h.columns.size(), file.string(), ":", number, ": too many values");
      try {
        h.values[h.columns[column]].push_back(std::stod(cell));
      } catch (const std::exception&) {
        throw Error(file.string() + ":" + std::to_string(number) + ": not a number: " + cell);
      }
    }
    SPHFEM_CHECK(column == h.columns.size(), file.string(), ":", number, ": expected ",
                 h.columns.size(), " values, found ", column);
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
