// Time histories: history.csv (one row per recorded step, header = column names) and
// history.h5 (dataset /history rows × columns, its column names and units), both written
// atomically whenever flush() is called (and only then), so a killed run leaves them whole.
// Verified by tests/e2e/run_test.cpp.
#pragma once

#include "solver/io/state_archive.hpp"

#include <filesystem>
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
  // Checkpoint: the rows so far. Reading them back replaces the rows held (the files change at
  // the next flush(), so a checkpoint that fails to read leaves them as they were); a restart
  // then appends the same rows the uninterrupted run wrote after the checkpoint.
  void persist(StateArchive& a);

private:
  void write_csv_row(const double* row);

  std::filesystem::path out_dir_;
  std::vector<std::string> columns_;
  std::vector<double> rows_; // row-major
  std::string csv_;          // history.csv's text so far
};

// Unit of a history column, from its name (e.g. "p1.vz" → "m/s").
std::string history_unit(const std::string& column);

} // namespace sphfem
