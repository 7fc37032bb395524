// Time histories: history.csv (one row per recorded step, header = column names, appended as
// the run goes) and history.h5 (dataset /history rows × columns, its column names and units,
// rewritten atomically whenever flush() is called). Verified by tests/e2e/run_test.cpp.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace sphfem {

class HistoryWriter {
public:
  HistoryWriter(const std::filesystem::path& out_dir, std::vector<std::string> columns);

  void append(const std::vector<double>& row);
  // Makes history.csv and history.h5 complete up to the last appended row.
  void flush();
  const std::vector<std::string>& columns() const { return columns_; }

private:
  std::filesystem::path out_dir_;
  std::vector<std::string> columns_;
  std::vector<double> rows_; // row-major
  std::ofstream csv_;
};

// Unit of a history column, from its name (e.g. "p1.vz" → "m/s").
std::string history_unit(const std::string& column);

} // namespace sphfem
