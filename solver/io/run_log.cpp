#include "solver/io/run_log.hpp"

#include <chrono>
#include <ctime>
#include <iostream>

namespace sphfem {

RunLog::RunLog(const std::filesystem::path& file, bool echo)
    : file_(file, std::ios::app), echo_(echo) {}

void RunLog::line(const std::string& text) {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  file_ << stamp << ' ' << text << std::endl;
  if (echo_)
    std::cerr << text << std::endl;
}

} // namespace sphfem
