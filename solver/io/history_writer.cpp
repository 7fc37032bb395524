#include "solver/io/history_writer.hpp"

#include "solver/core/error.hpp"
#include "solver/io/atomic_file.hpp"

#include <H5Cpp.h>

#include <array>
#include <cstdio>

namespace sphfem {

HistoryWriter::HistoryWriter(const std::filesystem::path& out_dir, std::vector<std::string> columns)
    : out_dir_(out_dir), columns_(std::move(columns)) {
  for (std::size_t c = 0; c < columns_.size(); ++c)
    csv_ += (c ? "," : "") + columns_[c];
  csv_ += '\n';
}

void HistoryWriter::append(const std::vector<double>& row) {
  SPHFEM_CHECK(row.size() == columns_.size(), "history row has ", row.size(), " values for ",
               columns_.size(), " columns");
  rows_.insert(rows_.end(), row.begin(), row.end());
  write_csv_row(row.data());
}

void HistoryWriter::write_csv_row(const double* row) {
  char buffer[32];
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    std::snprintf(buffer, sizeof buffer, "%.10g", row[c]);
    if (c)
      csv_ += ',';
    csv_ += buffer;
  }
  csv_ += '\n';
}

void HistoryWriter::persist(StateArchive& a) {
  std::string names;
  for (const auto& c : columns_)
    names += c + "\n";
  std::string stored = names;
  a.text("run/history_columns", stored);
  SPHFEM_CHECK(stored == names, "checkpoint: its history has other columns than this run's");
  a.array("run/history_rows", rows_);
  if (!a.reading())
    return;
  SPHFEM_CHECK(rows_.size() % columns_.size() == 0, "checkpoint: history rows of ", rows_.size(),
               " values for ", columns_.size(), " columns");
  for (std::size_t at = 0; at < rows_.size(); at += columns_.size())
    write_csv_row(&rows_[at]);
}

void HistoryWriter::flush() {
  write_text_atomically(out_dir_ / "history.csv", csv_);
  write_atomically(out_dir_ / "history.h5", [&](const std::filesystem::path& temporary) {
    try {
      H5::Exception::dontPrint();
      H5::H5File file(temporary.string(), H5F_ACC_TRUNC);
      // No modification times in the objects: the same history gives the same file, byte for
      // byte (a restarted run's history.h5 equals the uninterrupted run's).
      H5::DSetCreatPropList untimed;
      H5Pset_obj_track_times(untimed.getId(), false);
      const hsize_t ncol = columns_.size();
      const std::array<hsize_t, 2> dims{rows_.size() / ncol, ncol};
      H5::DataSet data = file.createDataSet("history", H5::PredType::NATIVE_DOUBLE,
                                            H5::DataSpace(2, dims.data()), untimed);
      if (!rows_.empty())
        data.write(rows_.data(), H5::PredType::NATIVE_DOUBLE);
      const H5::StrType text(H5::PredType::C_S1, H5T_VARIABLE);
      const hsize_t count = ncol;
      std::vector<const char*> names, units;
      std::vector<std::string> unit_strings;
      for (const auto& c : columns_)
        unit_strings.push_back(history_unit(c));
      for (std::size_t c = 0; c < ncol; ++c) {
        names.push_back(columns_[c].c_str());
        units.push_back(unit_strings[c].c_str());
      }
      file.createDataSet("columns", text, H5::DataSpace(1, &count), untimed)
          .write(names.data(), text);
      file.createDataSet("units", text, H5::DataSpace(1, &count), untimed)
          .write(units.data(), text);
    } catch (const H5::Exception& e) {
      throw Error(temporary.string() + ": cannot write history: " + e.getDetailMsg());
    }
  });
}

std::string history_unit(const std::string& column) {
  const auto dot = column.rfind('.');
  const std::string q = dot == std::string::npos ? column : column.substr(dot + 1);
  if (column == "time" || column == "dt")
    return "s";
  if (column.rfind("energy.", 0) == 0 || q == "kinetic" || q == "internal")
    return "J";
  if (q == "fx" || q == "fy" || q == "fz")
    return "N";
  if (q == "ux" || q == "uy" || q == "uz")
    return "m";
  if (q == "vx" || q == "vy" || q == "vz")
    return "m/s";
  if (q.size() == 3 && q[0] == 's')
    return "Pa";
  if (q == "pressure" || q == "von_mises")
    return "Pa";
  return "1";
}

} // namespace sphfem
