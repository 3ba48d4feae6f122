// tissuebench without the FEM reference and the harness (-DTISSUEBENCH_WITH_FEM=OFF):
// the leg's commands only - mesh, leg, leg-geometry - built from msd, tbio and
// the leg layer. Errors and exit codes as the full program.
#include "leg_commands.hpp"

#include "tbio/results_file.hpp"
#include "msd/core/types.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

namespace {

int dispatch(int argc, char** argv);

}  // namespace

int main(int argc, char** argv) {
  // A results file on a full disk that could not be closed ends the process
  // here (tbio::end_program): shutting HDF5 down would crash.
  return tbio::end_program(dispatch(argc, argv));
}

namespace {

int dispatch(int argc, char** argv) {
  CLI::App cli{"tissuebench (leg only: built without the FEM reference and the validation harness)"};
  cli.set_version_flag("--version", tbio::tissuebench_version() + " (" + tbio::git_revision() + ")");
  cli.require_subcommand(1);
  app::LegCommands leg_commands;
  app::add_leg_commands(cli, leg_commands);
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (const auto rc = app::run_leg_command(leg_commands, true)) return *rc;
  } catch (const msd::Error& e) {
    std::cerr << "tissuebench: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "tissuebench: unexpected error: " << e.what() << "\n";
    return 2;
  }
  return 2;
}

}  // namespace
