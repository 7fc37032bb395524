// The run's log: each line goes to OUT/run.log (time-stamped) and, unless quiet, to stderr.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace sphfem {

class RunLog {
public:
  RunLog(const std::filesystem::path& file, bool echo);
  void line(const std::string& text);
  bool echo() const { return echo_; }

private:
  std::ofstream file_;
  bool echo_;
};

} // namespace sphfem
