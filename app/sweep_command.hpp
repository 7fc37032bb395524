// `sphfem sweep`: one case run at many values of one key (the impact velocity by default), each
// run by the `run` subcommand in this process into DIR/run_<key>_<value>, optionally followed
// by a bisection of the ballistic limit; the runs' results, a Recht–Ipson fit, a reference curve
// and comparison series from the same file (another code's results for the same tests) go to
// DIR/sweep.csv, sweep.json, ballistic_curve.png and sweep.html (post/sweep.hpp).
// Verified by tests/post/sweep_test.cpp.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sphfem {

struct SweepCommandOptions {
  std::string case_file, out_dir;
  std::string key = "projectile.velocity";
  std::vector<std::string> values; // numbers
  bool values_given = false;       // else the experiment's (projectile.velocity only)
  std::string param;         // KEY=START:STOP:STEP (DESIGN.md's form): --key and --values in one
  std::string format = "{}"; // the key's YAML value, {} standing for the number
  bool bisect = false;
  bool resume = false;  // take finished runs in out_dir as they are, continue stopped ones
  double tolerance = 1; // m/s
  std::vector<std::string> overrides;
  int threads = 0;
  std::string reference;
  std::string reference_columns = "v0,vr"; // v0,vr[,other...]: the reference, then comparisons
  std::string reference_labels;            // one per vr column; empty: the column names
};

// Adds the subcommand to `app`, filling `o` when it is parsed.
CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& o);

// Runs it; throws sphfem::Error on bad input. A run that fails or has no results is reported
// as unknown and the sweep goes on. SIGINT/SIGTERM stop the run in progress with a checkpoint
// and then the sweep (Interrupted, saying how to continue); with `resume` the same sweep takes
// the runs that reached the end as they are and continues the others from their checkpoints.
void run_sweep_command(const SweepCommandOptions& o);

} // namespace sphfem
