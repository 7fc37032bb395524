#include "solver/io/atomic_file.hpp"

#include "solver/core/error.hpp"

#include <fstream>

namespace sphfem {

void write_atomically(const std::filesystem::path& file,
                      const std::function<void(const std::filesystem::path& temporary)>& write) {
  std::filesystem::path temporary = file;
  temporary += ".tmp";
  try {
    write(temporary);
  } catch (...) {
    std::error_code ignored; // a failed write leaves neither a half file nor its temporary
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) {
    std::error_code ignored; // nor does a file that cannot be replaced (a folder in its place)
    std::filesystem::remove(temporary, ignored);
  }
  SPHFEM_CHECK(!ec, file.string(), ": cannot replace the file: ", ec.message());
}

void write_text_atomically(const std::filesystem::path& file, const std::string& text) {
  write_atomically(file, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    out.close();
    SPHFEM_CHECK(out, temporary.string(), ": cannot write");
  });
}

} // namespace sphfem
