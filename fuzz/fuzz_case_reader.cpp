// libFuzzer target: any bytes as a case file. The reader must answer with a Case or a
// sphfem::Error — never a crash, a hang, undefined behaviour or another exception type.
#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    sphfem::read_case_text(text, "fuzz.yaml");
  } catch (const sphfem::Error&) {
  }
  return 0;
}
