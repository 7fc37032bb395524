#include "solver/io/state_archive.hpp"

#include "solver/core/error.hpp"

namespace sphfem {

void StateArchive::text(const std::string& name, std::string& s) {
  std::vector<char> chars(s.begin(), s.end());
  array(name, chars);
  if (reading())
    s.assign(chars.begin(), chars.end());
}

void StateArchive::expect_count(const std::string& name, std::size_t element, std::size_t count) {
  const std::size_t stored = stored_count(name, element);
  SPHFEM_CHECK(stored == count, "field ", name, ": ", stored, " values stored, ", count,
               " expected");
}

} // namespace sphfem
