// tissuebench: the command-line program. Parses arguments and calls the
// libraries; every error becomes one clear message and a non-zero exit.
#include "commands.hpp"

#include "bench/results_file.hpp"
#include "fem/blas_tuning.hpp"
#include "fem/fem.hpp"
#include "msd/core/types.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  fem::tune_blas_and_reexec(argv);
  // MPI (for the FEM solver) first; every process parses the same arguments.
  fem::Session session(argc, argv);
  CLI::App cli{"tissuebench - the thesis' mass-spring-damper soft-tissue model and its validation harness"};
  cli.set_version_flag("--version", bench::tissuebench_version() + " (" + bench::git_revision() + ")");
  cli.require_subcommand(1);

  app::RunArgs run;
  auto* run_cmd = cli.add_subcommand("run", "Run one test specification and write its results file");
  run_cmd->add_option("spec", run.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);
  run_cmd->add_option("--out", run.out,
                      "Results file to write (HDF5; a CSV copy goes beside it); a folder with --solver both")
      ->required();
  run_cmd->add_option("--solver", run.solver,
                      "Solver: msd (mass-spring-damper), fem (finite-element reference; mpirun -np N for N "
                      "processes) or both")
      ->check(CLI::IsMember({"msd", "fem", "both"}))
      ->capture_default_str();
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

  app::ConvergeArgs converge;
  auto* converge_cmd = cli.add_subcommand(
      "converge", "Refinement study of the FEM reference: observed order and error estimate of the finest level");
  converge_cmd->add_option("spec", converge.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);
  converge_cmd->add_option("--levels", converge.levels,
                           "Refinement levels (box, cylinder: global refinements; Cook's membrane: the spec's "
                           "cells times 2^level); at least three for an order")
      ->delimiter(',')
      ->capture_default_str();
  converge_cmd->add_option("--degree", converge.degree, "Element degree (default: the spec's)");
  converge_cmd->add_option("--out", converge.out, "Folder for the results files and the JSON study")
      ->capture_default_str();
  converge_cmd->add_flag("--quiet", converge.quiet, "No progress line");

  app::CompareArgs compare;
  auto* compare_cmd = cli.add_subcommand("compare", "Compare an MSD results file with an FEM one of the same spec");
  compare_cmd->add_option("msd", compare.msd, "MSD results file (HDF5)")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("fem", compare.fem, "FEM results file (HDF5)")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("--json", compare.json, "Write the metrics as JSON (keys: benchmarks/RESULTS.md)");

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (*run_cmd) return app::cmd_run(run);
    if (*suite_cmd) return app::cmd_suite(suite);
    if (*inspect_cmd) return app::cmd_inspect(inspect);
    if (*converge_cmd) return app::cmd_converge(converge);
    if (*compare_cmd) return app::cmd_compare(compare);
  } catch (const msd::Error& e) {
    if (fem::Session::rank() == 0) std::cerr << "tissuebench: error: " << e.what() << "\n";
    return 2;
  } catch (const fem::Error& e) {
    if (fem::Session::rank() == 0) std::cerr << "tissuebench: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "tissuebench: unexpected error: " << e.what() << "\n";
    return 2;
  }
  return 2;
}
