#include "solver/io/sealed_h5.hpp"

#include "solver/core/error.hpp"
#include "solver/io/fnv1a.hpp"

#include <cstdio>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace sphfem {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t block_bytes = 512; // HDF5's smallest user block
constexpr std::string_view magic = "sphfem seal 1\n";

struct Content {
  unsigned long long bytes = 0;
  unsigned long long hash = 0;
};

// Byte count and hash of everything after the user block.
Content content_of(std::istream& in) {
  in.seekg(block_bytes);
  Content content;
  Fnv1a fnv;
  std::vector<char> chunk(std::size_t{1} << 20);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    fnv.add(std::as_bytes(std::span(chunk.data(), n)));
    content.bytes += n;
  }
  content.hash = fnv.hash;
  return content;
}

} // namespace

H5::FileCreatPropList sealed_file_properties() {
  H5::FileCreatPropList properties;
  properties.setUserblock(block_bytes);
  return properties;
}

void seal_h5_file(const fs::path& file) {
  std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
  SPHFEM_CHECK(io, file.string(), ": cannot open it to seal it");
  const Content content = content_of(io);
  std::string block(magic);
  block += "bytes " + std::to_string(content.bytes) + "\n";
  char hash[32];
  std::snprintf(hash, sizeof hash, "fnv1a64 %016llx\n", content.hash);
  block += hash;
  block.resize(block_bytes, '\0');
  io.clear();
  io.seekp(0);
  io.write(block.data(), static_cast<std::streamsize>(block.size()));
  io.close();
  SPHFEM_CHECK(io, file.string(), ": cannot write its seal");
}

void check_h5_seal(const fs::path& file) {
  std::error_code status;
  SPHFEM_CHECK(fs::exists(file, status), "no such file");
  SPHFEM_CHECK(fs::is_regular_file(file, status), "not a regular file");
  std::ifstream in(file, std::ios::binary);
  SPHFEM_CHECK(in, "cannot open it");
  std::string block(block_bytes, '\0');
  in.read(block.data(), static_cast<std::streamsize>(block.size()));
  if (!in || !block.starts_with(magic)) {
    SPHFEM_CHECK(H5::H5File::isHdf5(file.string()), "not an HDF5 file");
    throw Error("an HDF5 file without sphfem's seal: written by another program or by an older "
                "sphfem");
  }
  Content sealed;
  SPHFEM_CHECK(std::sscanf(block.c_str() + magic.size(), "bytes %llu fnv1a64 %16llx", &sealed.bytes,
                           &sealed.hash) == 2,
               "its seal is unreadable: the file is corrupt");
  const Content content = content_of(in);
  SPHFEM_CHECK(content.bytes >= sealed.bytes, "truncated: ", content.bytes + block_bytes,
               " of the ", sealed.bytes + block_bytes, " bytes sphfem wrote");
  SPHFEM_CHECK(content.bytes == sealed.bytes, content.bytes + block_bytes,
               " bytes where sphfem wrote ", sealed.bytes + block_bytes,
               ": changed after it was written");
  SPHFEM_CHECK(content.hash == sealed.hash,
               "its content does not match its seal: corrupt or changed after sphfem wrote it");
}

} // namespace sphfem
