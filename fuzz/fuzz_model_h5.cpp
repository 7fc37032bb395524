// libFuzzer target: any bytes as model.h5 (written to a scratch file, since HDF5 reads files).
// The reader must answer with a Model or a sphfem::Error — never a crash or another exception.
#include "solver/core/error.hpp"
#include "solver/io/model_h5.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("sphfem_fuzz_model_" + std::to_string(::getpid()) + ".h5");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    sphfem::read_model_h5(file);
  } catch (const sphfem::Error&) {
  }
  return 0;
}
