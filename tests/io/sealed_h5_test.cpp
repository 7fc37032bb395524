// The seal of model.h5 and checkpoint.h5 (solver/io/sealed_h5.hpp): a sealed file is still an
// ordinary HDF5 file with its seal readable as text at its start, and any change to it — a byte,
// a cut, an appended tail, a garbled seal — is refused before HDF5 reads it. (Files of the two
// kinds: tests/io/model_h5_test.cpp and checkpoint_test.cpp.)
#include "solver/core/error.hpp"
#include "solver/io/sealed_h5.hpp"

#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using sphfem::check_h5_seal;
using sphfem::seal_h5_file;

namespace {

class SealedFile : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sphfem_seal_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    file_ = dir_ / "sealed.h5";
    H5::H5File h5(file_.string(), H5F_ACC_TRUNC, sphfem::sealed_file_properties());
    const hsize_t n = 1000;
    std::string bytes(n, 'x');
    h5.createDataSet("data", H5::PredType::NATIVE_CHAR, H5::DataSpace(1, &n))
        .write(bytes.data(), H5::PredType::NATIVE_CHAR);
    h5.close();
    seal_h5_file(file_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string bytes() const {
    std::ifstream in(file_, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  void write(const std::string& bytes) const {
    std::ofstream(file_, std::ios::binary | std::ios::trunc) << bytes;
  }
  std::string error() const {
    try {
      check_h5_seal(file_);
      return "";
    } catch (const sphfem::Error& e) {
      return e.what();
    }
  }

  fs::path dir_;
  fs::path file_;
};

} // namespace

TEST_F(SealedFile, IsAnOrdinaryHdf5FileWithItsSealAsText) {
  EXPECT_EQ(error(), "");
  const std::string content = bytes();
  const std::string content_bytes = std::to_string(content.size() - 512);
  EXPECT_EQ(content.rfind("sphfem seal 1\nbytes " + content_bytes + "\nfnv1a64 ", 0), 0u)
      << content.substr(0, 64);
  H5::H5File h5(file_.string(), H5F_ACC_RDONLY);
  EXPECT_EQ(h5.openDataSet("data").getSpace().getSimpleExtentNpoints(), 1000);
}

TEST_F(SealedFile, AnyChangeIsRefused) {
  const std::string whole = bytes();
  write(whole + "tail");
  EXPECT_NE(error().find(std::to_string(whole.size() + 4) + " bytes where sphfem wrote " +
                         std::to_string(whole.size()) + ": changed after it was written"),
            std::string::npos)
      << error();
  write(whole.substr(0, 700));
  EXPECT_NE(
      error().find("truncated: 700 of the " + std::to_string(whole.size()) + " bytes sphfem wrote"),
      std::string::npos)
      << error();
  write(whole.substr(0, 100)); // not even the seal whole
  EXPECT_EQ(error(), "not an HDF5 file");
  std::string garbled = whole;
  garbled.replace(garbled.find("bytes"), 5, "BYTES");
  write(garbled);
  EXPECT_EQ(error(), "its seal is unreadable: the file is corrupt");
  for (std::size_t at = 512; at < whole.size(); at += 997) {
    std::string changed = whole;
    changed[at] = static_cast<char>(changed[at] ^ 1);
    write(changed);
    EXPECT_EQ(error(), "its content does not match its seal: corrupt or changed after sphfem "
                       "wrote it")
        << "byte " << at;
  }
  write(whole);
  EXPECT_EQ(error(), "");
}

TEST_F(SealedFile, UnsealedHdf5FileIsNamedSo) {
  H5::H5File(file_.string(), H5F_ACC_TRUNC).close();
  EXPECT_EQ(error(), "an HDF5 file without sphfem's seal: written by another program or by an "
                     "older sphfem");
  fs::remove(file_);
  EXPECT_EQ(error(), "no such file");
}
