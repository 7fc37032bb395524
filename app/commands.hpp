// The `sphfem` command line: git-style subcommands (mesh, solve, run, post, material, sweep),
// each with --help. Parses arguments, reads and validates the case before anything is written,
// and turns any sphfem::Error into one line on stderr and a non-zero exit code.
#pragma once

namespace sphfem {

// Returns the process exit code.
int run_command_line(int argc, char** argv);

} // namespace sphfem
