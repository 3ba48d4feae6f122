// tissuebench: the command-line program. Parses arguments and calls the
// libraries; every error becomes one clear message and a non-zero exit.
#include "cli_checks.hpp"
#include "commands.hpp"
#include "leg_commands.hpp"

#include "tbio/results_file.hpp"
#include "fem/blas_tuning.hpp"
#include "fem/fem.hpp"
#include "msd/core/types.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

namespace {

int dispatch(int argc, char** argv);

}  // namespace

int main(int argc, char** argv) {
  fem::tune_blas_and_reexec(argv);
  // MPI (for the FEM solver) first; every process parses the same arguments.
  fem::Session session(argc, argv);
  // A results file on a full disk that could not be closed ends the process
  // here (tbio::end_program): shutting HDF5 down would crash.
  return tbio::end_program(dispatch(argc, argv));
}

namespace {

int dispatch(int argc, char** argv) {
  CLI::App cli{"tissuebench - the thesis' mass-spring-damper soft-tissue model and its validation harness"};
  cli.set_version_flag("--version", tbio::tissuebench_version() + " (" + tbio::git_revision() + ")");
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
  run_cmd->add_option("--calibration", run.calibration,
                      "Calibration file (tissuebench calibrate) for the msd solver's physical constants")
      ->check(CLI::ExistingFile);
  run_cmd->add_option("--checkpoint-every", run.checkpoint_every,
                      "Write a checkpoint (OUT.checkpoint) every this many simulated seconds (msd solver with a "
                      "fixed-step integrator); removed when the run completes")
      ->check(app::finite_positive("simulated seconds"));
  run_cmd->add_option("--resume", run.resume,
                      "Continue from a checkpoint of the same spec (results bit-identical to an uninterrupted run)")
      ->check(CLI::ExistingFile);
  run_cmd->footer(
      "Files: OUT and its CSV twin are written under temporary names (OUT.partial-PID) and renamed into place "
      "when the run ends, complete or failed; an existing OUT is untouched until then. A second run to the same "
      "OUT is refused (exit 2) while the first holds OUT.lock. SIGINT/SIGTERM stop the msd solver at its next "
      "step: OUT is kept marked failed (\"interrupted by signal N at t = ...\"), exit 128+N (130, 143).");

  app::SuiteArgs suite;
  auto* suite_cmd = cli.add_subcommand(
      "suite", "The main job: the standard set of comparison benchmarks (FEM and MSD variants), sweep, stability "
               "and FEM verification, then the report (DIR/report/index.html, summary.md)");
  suite_cmd->add_option("--tier", suite.tier,
                        "quick (a few minutes), full, thesis (the thesis' three uni-axial experiments, MSD only) or "
                        "a tier file")
      ->capture_default_str();
  suite_cmd->add_option("--out", suite.out, "Folder for the results files and the report")->capture_default_str();
  suite_cmd->add_option("--specs", suite.specs_dir, "Folder holding the specs (default: the built-in ones)");
  suite_cmd->add_flag("--no-report", suite.no_report, "Skip the HTML/Markdown report");
  suite_cmd->add_flag("--quiet", suite.quiet, "No progress lines");

  app::InspectArgs inspect;
  auto* inspect_cmd = cli.add_subcommand("inspect", "Mesh a specification and print its counts and constants");
  inspect_cmd->add_option("spec", inspect.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);

  app::LegCommands leg_commands;
  app::add_leg_commands(cli, leg_commands);

  app::ConvergeArgs converge;
  auto* converge_cmd = cli.add_subcommand(
      "converge", "Refinement study of the FEM reference: observed order and error estimate of the finest level");
  converge_cmd->add_option("spec", converge.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);
  converge_cmd->add_option("--levels", converge.levels,
                           "Refinement levels (box, cylinder: global refinements; Cook's membrane: the spec's "
                           "cells times 2^level); at least three for an order")
      ->delimiter(',')
      ->check(app::integer_in(0, 8, "a refinement level"))
      ->capture_default_str();
  converge_cmd->add_option("--degree", converge.degree, "Element degree (default: the spec's)")
      ->check(app::integer_in(1, 4, "a finite-element degree"));
  converge_cmd->add_option("--out", converge.out, "Folder for the results files and the JSON study")
      ->capture_default_str();
  converge_cmd->add_flag("--quiet", converge.quiet, "No progress line");

  app::CompareArgs compare;
  auto* compare_cmd = cli.add_subcommand("compare", "Compare an MSD results file with an FEM one of the same spec");
  compare_cmd->add_option("msd", compare.msd, "MSD results file (HDF5)")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("fem", compare.fem, "FEM results file (HDF5)")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("--json", compare.json, "Write the metrics as JSON (keys: benchmarks/RESULTS.md)");

  app::CalibrateArgs calibrate;
  auto* calibrate_cmd = cli.add_subcommand(
      "calibrate", "Fit a material's MSD constants to the FEM reference: stiffness scale, repulsion and volume "
                   "factors over the uni-axial and shear calibration specs, then the dampers' time constant on "
                   "a ring-down");
  calibrate_cmd->add_option("--material", calibrate.material, "Material (an entry of benchmarks/materials.yaml)")
      ->required();
  calibrate_cmd->add_option("--out", calibrate.out, "Folder for NAME.yaml and the FEM references")
      ->capture_default_str();
  calibrate_cmd->add_option("--specs", calibrate.specs,
                            "Calibration specs (uniaxial or simple_shear; vibration with a preload for the "
                            "damping; default: the built-in calibrate_uniaxial.yaml, calibrate_shear.yaml and "
                            "calibrate_ringdown.yaml)")
      ->delimiter(',')
      ->check(CLI::ExistingFile);
  calibrate_cmd->add_option("--max-evaluations", calibrate.max_evaluations,
                            "Budget of objective evaluations for the optimiser (stage 1: the elastic factors)")
      ->check(app::integer_in(4, 1000, "objective evaluations"))
      ->capture_default_str();
  calibrate_cmd->add_option("--max-damping-evaluations", calibrate.max_damping_evaluations,
                            "Budget of objective evaluations for the damping fit (stage 2)")
      ->check(app::integer_in(2, 1000, "objective evaluations"))
      ->capture_default_str();
  calibrate_cmd->add_flag("--edge-classes", calibrate.edge_classes,
                          "Also fit the lattice's edge classes: the cube edges' stiffness relative to the face "
                          "diagonals' and the spring law's compression exponent (docs/msd-model.md section 4, edge classes)");
  calibrate_cmd->add_option("--start", calibrate.start,
                            "A calibration file of the same material whose parameters start the fit (default: "
                            "the spec's constants; with --edge-classes the isotropic lattice); its damping_time "
                            "starts stage 2")
      ->check(CLI::ExistingFile);
  calibrate_cmd->add_option("--check-specs", calibrate.check_specs,
                            "Specs the fitted set is run on after the fit; a blow-up or an inverted element "
                            "refuses the set (default: the shipped uniaxial, shear, bending, bending_gravity, "
                            "vibration and indentation specs)")
      ->delimiter(',')
      ->check(CLI::ExistingFile);
  calibrate_cmd->add_flag("--no-check", calibrate.no_check, "Skip the run of the fitted set on the check specs");
  calibrate_cmd->add_option("--volume-weight", calibrate.volume_weight,
                            "Weight w of the uni-axial volume-ratio residual w (V_msd - V_fem) against the "
                            "relative stress residuals (0: stress only)")
      ->check(app::finite_in(0.0, 1e3, "a residual weight"))
      ->capture_default_str();
  calibrate_cmd->add_flag("--quiet", calibrate.quiet, "No per-evaluation lines");

  app::SweepArgs sweep;
  auto* sweep_cmd = cli.add_subcommand(
      "sweep", "Speed-accuracy trade: run the MSD model over a grid of h, dt, integrator, force terms and the "
               "0.7 threshold; errors against the FEM reference, cost, Pareto front (mpirun -np N spreads the "
               "points)");
  sweep_cmd->add_option("spec", sweep.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);
  sweep_cmd->add_option("--out", sweep.out, "Folder for the points, the FEM reference and the merged table")
      ->capture_default_str();
  sweep_cmd->add_option("--spacing", sweep.spacing, "Mesh spacings h in m (default: the spec's h and 2h)")
      ->delimiter(',')
      ->check(app::finite_positive("a mesh spacing, m"));
  sweep_cmd->add_option("--dt", sweep.dt, "Time steps in s (default: the spec's dt and 2.5 dt)")
      ->delimiter(',')
      ->check(app::finite_positive("a time step, s"));
  sweep_cmd->add_option("--integrators", sweep.integrators,
                        "Fixed-step integrators (default: symplectic_euler,velocity_verlet,explicit_euler)")
      ->delimiter(',');
  sweep_cmd->add_option("--terms", sweep.terms,
                        "Term sets: all, no_repulsion, no_volume, springs_dampers, continuum, neo_lattice, neo_lattice_repulsion (default: the first four)")
      ->delimiter(',');
  sweep_cmd->add_option("--thresholds", sweep.thresholds, "Non-linear thresholds: off or a value in (0,1] "
                                                          "(default: off,0.7)")
      ->delimiter(',');
  sweep_cmd->add_flag("--no-cvode", sweep.no_cvode,
                      "Leave out the CVODE point of each spatial configuration (no time errors)");
  sweep_cmd->add_flag("--quasi-static", sweep.quasi_static,
                      "Add a quasi-static point (dt = the output interval, no dampers) per spatial configuration and "
                      "term set, for a static loading");
  sweep_cmd->add_option("--reference", sweep.reference,
                        "An existing FEM results file of the same spec (default: computed into --out, reused "
                        "when the spec is unchanged)")
      ->check(CLI::ExistingFile);
  sweep_cmd->add_option("--point-timeout", sweep.point_timeout,
                        "Wall seconds a point may take before it is stopped and marked timeout (0: no limit)")
      ->check(app::finite_non_negative("wall seconds"))
      ->capture_default_str();
  sweep_cmd->add_option("--fem-levels", sweep.fem_levels,
                        "FEM runs besides the reference, DEGREE:REFINEMENT on the spec's cells (e.g. 1:0,1:1): "
                        "their cost and load-curve error against the reference join the table")
      ->delimiter(',');
  sweep_cmd->add_flag("--quiet", sweep.quiet, "No per-point lines");

  app::StabilityArgs stability;
  auto* stability_cmd = cli.add_subcommand(
      "stability", "Stability at the extremes: largest stable time step per integrator and term set (bisection "
                   "with a blow-up detector) and extreme loads (uniaxial specs)");
  stability_cmd->add_option("spec", stability.spec, "Test specification (YAML)")->required()->check(CLI::ExistingFile);
  stability_cmd->add_option("--out", stability.out, "Folder for the JSON table")->capture_default_str();
  stability_cmd->add_option("--integrators", stability.integrators, "Integrators of the dt search")
      ->delimiter(',')
      ->capture_default_str();
  stability_cmd->add_option("--terms", stability.terms, "Term sets (all, no_repulsion, no_volume, springs_dampers, continuum)")
      ->delimiter(',')
      ->capture_default_str();
  stability_cmd->add_flag("--no-dt-search", stability.no_dt_search, "Skip the time-step bisection");
  stability_cmd->add_flag("--no-extremes", stability.no_extremes, "Skip the extreme loads");
  stability_cmd->add_flag("--quiet", stability.quiet, "No per-trial lines");

  app::CheckArgs check;
  auto* check_cmd = cli.add_subcommand(
      "check", "Regression guard: the comparison metrics under DIR against a baseline (exit 1 with what moved)");
  check_cmd->add_option("dir", check.dirs,
                        "Folder of *_compare.json files, leg summaries and suite.json (a suite's or run --solver "
                        "both's output); with --update, several folders (repeated runs) derive the tolerances "
                        "from their spread")
      ->required();
  check_cmd->add_option("--baseline", check.baseline, "Baseline file (reports/baselines/*.yaml)")->required();
  check_cmd->add_flag("--update", check.update,
                      "Rewrite the baseline from DIR (one folder: keeping its tolerances; several: tolerances "
                      "from the measured spread) and list what changed");
  check_cmd->add_option("--tier", check.tier, "Tier name recorded in a baseline written by --update");

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (*run_cmd) return app::cmd_run(run);
    if (*suite_cmd) return app::cmd_suite(suite);
    if (*inspect_cmd) return app::cmd_inspect(inspect);
    if (const auto rc = app::run_leg_command(leg_commands, fem::Session::rank() == 0)) return *rc;
    if (*converge_cmd) return app::cmd_converge(converge);
    if (*compare_cmd) return app::cmd_compare(compare);
    if (*calibrate_cmd) return app::cmd_calibrate(calibrate);
    if (*sweep_cmd) return app::cmd_sweep(sweep);
    if (*stability_cmd) return app::cmd_stability(stability);
    if (*check_cmd) return app::cmd_check(check);
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

}  // namespace
