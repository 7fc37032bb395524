// Entry point of the `sphfem` command (app/commands.hpp does the work).
#include "app/commands.hpp"

int main(int argc, char** argv) {
  return sphfem::run_command_line(argc, argv);
}
