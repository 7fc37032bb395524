// The benchmarks' command line: -h/--help prints the usage and exits 0; an argument that is not
// a whole number (or a missing value) is an error naming it, with the usage, exit 2.
#pragma once

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace sphfem::bench {

inline void exit_with_usage(const char* usage, int code) {
  std::fputs(usage, code == 0 ? stdout : stderr);
  std::exit(code);
}

// Exits with the usage when any argument asks for help.
inline void help(int argc, char** argv, const char* usage) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "-h" || std::string(argv[i]) == "--help")
      exit_with_usage(usage, 0);
}

inline int whole_number(const std::string& arg, const char* usage) {
  int value = 0;
  const auto [end, error] = std::from_chars(arg.data(), arg.data() + arg.size(), value);
  if (error != std::errc() || end != arg.data() + arg.size() || value < 0) {
    std::fprintf(stderr, "error: '%s' is not a whole number\n", arg.c_str());
    exit_with_usage(usage, 2);
  }
  return value;
}

} // namespace sphfem::bench
