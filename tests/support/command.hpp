// Test helpers for running the `sphfem` command as users do: a scratch folder, a file's whole
// text, one command with its exit code, stdout and stderr (no X display, as on a server or in
// CI), and one started in the background to be signalled.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace sphfem::test {

inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh folder per test and process (test runs from several build folders may overlap),
// removed when the test passes: TMP/sphfem_<name>_<pid>.
struct Scratch {
  std::filesystem::path dir;
  explicit Scratch(const std::string& name)
      : dir(std::filesystem::temp_directory_path() /
            ("sphfem_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~Scratch() {
    if (!::testing::Test::HasFailure())
      std::filesystem::remove_all(dir);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
};

struct Result {
  int code;
  std::string out, err;
};

// `sphfem ARGS` in the background (exec'd by the shell, so the pid is sphfem's), stdout and
// stderr in files of `dir`: for tests that signal a running command.
inline pid_t spawn_sphfem(const std::string& args, const std::filesystem::path& dir) {
  const std::string cmd = "exec env -u DISPLAY " + std::string(SPHFEM_BINARY) + " " + args + " >" +
                          (dir / "stdout.txt").string() + " 2>" + (dir / "stderr.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// Waits (up to a minute) until `file` exists; false if it does not or process `pid` ended first.
inline bool wait_for_file(const std::filesystem::path& file, pid_t pid) {
  for (int i = 0; i < 6000; ++i) {
    if (std::filesystem::exists(file))
      return true;
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid)
      return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// A run's summary.json without what varies from run to run of the same case (wall time, rate,
// thread count, peak memory): what two runs that must agree are compared on.
inline nlohmann::json summary_without_timing(const std::filesystem::path& run) {
  auto s = nlohmann::json::parse(slurp(run / "summary.json"));
  for (const char* varies : {"wall_s", "entity_steps_per_s", "threads", "peak_resident_MB"})
    s.erase(varies);
  return s;
}

// Runs `sphfem ARGS` with stdout and stderr captured in files of `dir`.
inline Result run_sphfem(const std::string& args, const std::filesystem::path& dir) {
  const std::string cmd = "env -u DISPLAY " + std::string(SPHFEM_BINARY) + " " + args + " >" +
                          (dir / "stdout.txt").string() + " 2>" + (dir / "stderr.txt").string();
  const int status = std::system(cmd.c_str());
  return {WEXITSTATUS(status), slurp(dir / "stdout.txt"), slurp(dir / "stderr.txt")};
}

// Runs a shell command line (a script) with stdout and stderr captured in files of `dir`.
inline Result run_shell(const std::string& command, const std::filesystem::path& dir) {
  const int status = std::system(
      (command + " >" + (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string()).c_str());
  return {WEXITSTATUS(status), slurp(dir / "out.txt"), slurp(dir / "err.txt")};
}

} // namespace sphfem::test
