// One number in printf form ("%.4g"), for messages, logs and reports.
#pragma once

#include <cstdio>
#include <string>

namespace sphfem {

// `value` in the printf `pattern`.
inline std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

} // namespace sphfem
