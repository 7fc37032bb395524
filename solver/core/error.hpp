// Errors: one exception type for everything a user can cause (bad input, instability).
// The command catches it, prints its one-line message and exits non-zero; library code
// never calls exit(). SPHFEM_CHECK is always on; use assert() for internal invariants.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace sphfem {

class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

namespace detail {
template <class... Parts> std::string concat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}
} // namespace detail

} // namespace sphfem

#define SPHFEM_CHECK(condition, ...)                                                               \
  do {                                                                                             \
    if (!(condition))                                                                              \
      throw ::sphfem::Error(::sphfem::detail::concat(__VA_ARGS__));                                \
  } while (false)
