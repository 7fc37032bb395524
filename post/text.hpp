// Small text helpers shared by the post tool's pages and tables: a file's whole content and HTML
// escaping (one number in printf form: sphfem::format, solver/core/format.hpp).
#pragma once

#include "solver/core/format.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace sphfem::post {

inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// `text` with <, >, & and " escaped for HTML.
inline std::string escape_html(const std::string& text) {
  std::string out;
  for (char c : text)
    switch (c) {
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '&':
      out += "&amp;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += c;
    }
  return out;
}

} // namespace sphfem::post
