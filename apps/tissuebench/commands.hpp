// The subcommands of the tissuebench program. Each returns the process exit
// code: 0 success, 1 a run that failed (blow-up, non-finite value), 2 bad input.
#pragma once

#include <string>
#include <vector>

namespace app {

struct RunArgs {
  std::string spec, out, solver = "msd";
  std::string calibration;  ///< calibration file for the msd solver ("" = the spec's constants)
  bool quiet = false;
  double checkpoint_every = 0.0;  ///< simulated seconds between checkpoints (msd solver); 0: none
  std::string resume;             ///< a checkpoint to continue from
};
int cmd_run(const RunArgs& args);

struct SuiteArgs {
  std::string out = "results";
  std::string specs_dir;
  std::string tier = "quick";   ///< quick | full | thesis | a tier file
  bool quiet = false, no_report = false;
};
int cmd_suite(const SuiteArgs& args);

struct InspectArgs {
  std::string spec;
};
int cmd_inspect(const InspectArgs& args);

struct ConvergeArgs {
  std::string spec, out = "convergence";
  std::vector<int> levels{0, 1, 2};
  unsigned degree = 0;  ///< 0: the spec's
  bool quiet = false;
};
int cmd_converge(const ConvergeArgs& args);

struct CompareArgs {
  std::string msd, fem, json;
};
int cmd_compare(const CompareArgs& args);

struct CalibrateArgs {
  std::string material, out = "calibration";
  std::vector<std::string> specs;  ///< empty: the built-in calibrate_uniaxial, calibrate_shear, calibrate_ringdown
  int max_evaluations = 40;
  int max_damping_evaluations = 20;
  double volume_weight = 2.0;
  bool edge_classes = false;  ///< also fit the lattice's axis stiffness and compression exponent
  std::string start;          ///< a calibration file to start from (empty: the spec's constants)
  /// Specs the fitted set must run without a blow-up or an inverted element
  /// (empty: bench::shipped_benchmark_specs()); --no-check: none.
  std::vector<std::string> check_specs;
  bool no_check = false;
  bool quiet = false;
};
int cmd_calibrate(const CalibrateArgs& args);

struct SweepArgs {
  std::string spec, out = "sweep", reference;
  std::vector<double> spacing, dt;
  std::vector<std::string> integrators, terms, thresholds, fem_levels;
  double point_timeout = 0.0;
  bool no_cvode = false, quiet = false, quasi_static = false;
};
int cmd_sweep(const SweepArgs& args);

struct StabilityArgs {
  std::string spec, out = "stability";
  std::vector<std::string> integrators{"explicit_euler", "symplectic_euler", "velocity_verlet"};
  std::vector<std::string> terms{"springs_dampers", "all"};
  bool no_dt_search = false, no_extremes = false, quiet = false;
};
int cmd_stability(const StabilityArgs& args);

struct CheckArgs {
  std::vector<std::string> dirs;  ///< one; with --update several (repeated runs)
  std::string baseline, tier;
  bool update = false;
};
/// The regression guard: 0 when every baseline metric holds, 1 with the list
/// of what moved; --update rewrites the baseline and says what changed (from
/// several folders: every tolerance from the measured spread, with its table).
int cmd_check(const CheckArgs& args);

/// The specs of the default suite (the thesis' three uni-axial experiments).
std::vector<std::string> default_suite();

}  // namespace app
