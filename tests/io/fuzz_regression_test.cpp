// Inputs that once crashed a reader under fuzzing (scripts/hostile-input.sh), kept in
// fuzz/regressions/<reader>/ and replayed here on every build: each must now give a result or
// a one-line sphfem::Error, nothing else. The folders also hold hand-made hostile files (empty,
// binary, deeply nested, huge numbers), so the test has inputs before fuzzing finds any.
#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"
#include "solver/io/model_h5.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> inputs(const std::string& reader) {
  std::vector<fs::path> out;
  for (const auto& entry :
       fs::directory_iterator(fs::path(SPHFEM_SOURCE_DIR) / "fuzz" / "regressions" / reader))
    if (entry.is_regular_file() && entry.path().filename() != "README.md")
      out.push_back(entry.path());
  return out;
}

std::string text_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

} // namespace

TEST(FuzzRegressions, CaseReaderGivesACaseOrAnError) {
  const auto files = inputs("case_reader");
  EXPECT_GE(files.size(), 4u);
  for (const auto& file : files) {
    try {
      sphfem::read_case_text(text_of(file), file);
    } catch (const sphfem::Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << file;
    } catch (const std::exception& e) {
      ADD_FAILURE() << file << ": not a sphfem::Error: " << e.what();
    }
  }
}

TEST(FuzzRegressions, ModelReaderGivesAModelOrAnError) {
  const auto files = inputs("model_h5");
  EXPECT_GE(files.size(), 2u);
  for (const auto& file : files) {
    try {
      sphfem::read_model_h5(file);
    } catch (const sphfem::Error& e) {
      EXPECT_NE(std::string(e.what()).find(file.filename().string()), std::string::npos) << file;
      // What crashed inside HDF5 must not reach it: the seal refuses it first.
      if (file.filename().string().starts_with("hdf5_")) {
        EXPECT_NE(std::string(e.what()).find("without sphfem's seal"), std::string::npos) << file;
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << file << ": not a sphfem::Error: " << e.what();
    }
  }
}
