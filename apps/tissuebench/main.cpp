// tissuebench: the command-line program. Parses arguments and calls the
// libraries; every error becomes one clear message and a non-zero exit.
#include "commands.hpp"

#include "bench/results_file.hpp"
#include "msd/core/types.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App cli{"tissuebench - the thesis' mass-spring-damper soft-tissue model and its validation harness"};
  cli.set_version_flag("--version", bench::tissuebench_version() + " (" + bench::git_revision() + ")");
  cli.require_subcommand(1);

  app::RunArgs run;
  auto* run_cmd = cli.add_subcommand("run", "Run one test specification and write its results file");
  run_cmd->add_option("spec", run.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);
  run_cmd->add_option("--out", run.out, "Results file to write (HDF5; a CSV copy goes beside it)")->required();
  run_cmd->add_option("--solver", run.solver, "Solver: msd")->check(CLI::IsMember({"msd"}));
  run_cmd->add_flag("--quiet", run.quiet, "No progress line");

  app::SuiteArgs suite;
  auto* suite_cmd = cli.add_subcommand(
      "suite", "Run the standard set (the thesis' three uni-axial experiments) and print a summary");
  suite_cmd->add_option("--out", suite.out, "Folder for the results files")->capture_default_str();
  suite_cmd->add_option("--specs", suite.specs_dir, "Folder holding the specs (default: the built-in ones)");
  suite_cmd->add_flag("--quiet", suite.quiet, "No progress lines");

  app::InspectArgs inspect;
  auto* inspect_cmd = cli.add_subcommand("inspect", "Mesh a specification and print its counts and constants");
  inspect_cmd->add_option("spec", inspect.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (*run_cmd) return app::cmd_run(run);
    if (*suite_cmd) return app::cmd_suite(suite);
    if (*inspect_cmd) return app::cmd_inspect(inspect);
  } catch (const msd::Error& e) {
    std::cerr << "tissuebench: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "tissuebench: unexpected error: " << e.what() << "\n";
    return 2;
  }
  return 2;
}
