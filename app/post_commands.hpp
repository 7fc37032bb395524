// `sphfem post …`: the post-processing subcommands on a run folder — history (charts),
// section (deformed cross-section and deflection), plug (fragments) and report (one HTML page
// with all of it beside the case's reference values) — and the report `sphfem run` ends with.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>

namespace sphfem {

class PostCommands {
public:
  // Registers `post` and its subcommands on `app`.
  explicit PostCommands(CLI::App& app);
  ~PostCommands();
  bool parsed() const;
  // Runs the chosen subcommand (after app.parse()); throws sphfem::Error on bad input.
  void run();

private:
  struct Options;
  std::unique_ptr<Options> o_;
};

// Writes RUN/report/report.html after a run and says where it is; a report that cannot be
// made is a warning, not a failed run.
void write_run_report(const std::filesystem::path& run);

} // namespace sphfem
