// The regression guard: the metrics of a suite's (or any) output folder
// against a baseline with a tolerance per metric.
//
// Metrics are collected from three kinds of files under the folder:
//  - every `*_compare.json` (what `run --solver both`, `compare --json` and
//    `suite` write), keyed "SUBFOLDER/SPEC.KEY" (SUBFOLDER: the file's folder
//    under the one checked, e.g. a suite's variant; none for files directly in
//    it) with KEY one of kGuardedKeys;
//  - the FEM verification rows of the folder's `suite.json`, keyed
//    "verification/NAME.value" and "verification/NAME.rel_error";
//  - every leg run's `summary.json` (what `leg` and the suite's leg scenes
//    write), keyed "FOLDER.KEY" with KEY one of kGuardedLegValues (a run that
//    did not complete contributes nothing, so its baseline entries fail as
//    missing).
// Accuracy metrics and leg outcomes are deterministic (bit-identical from run
// to run); speed is not. One comparison's `cost_ratio` (MSD cost over FEM cost,
// in CPU time, measured in the same run) moves by up to ~30 % between
// identical runs on a shared machine, so the guarded speed figures are the
// geometric means of the cost ratios per folder and over all,
// "cost/FOLDER.cost_ratio_geomean" and "cost/all.cost_ratio_geomean" (see
// kCostGeomeanMinimum). The tolerance rule, derived from measured spread, is
// documented in benchmarks/README.md ("The regression guard").
//
// Baseline file (YAML; written by `tissuebench check --update`):
//     tier: quick
//     metrics:
//       physical/uniaxial.load_rel_rms: {value: 0.807, tolerance: 0.01, relative: true, basis: "..."}
// `basis` says how the tolerance was chosen.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace bench {

/// The compare-JSON keys the guard reads.
extern const std::vector<std::string> kGuardedKeys;
/// The leg summary `values` the guard reads (the scenes' main outcomes).
extern const std::vector<std::string> kGuardedLegValues;

/// The speed figures guarded: geometric means of the comparisons' cost_ratio
/// (MSD over FEM CPU cost, measured in the same run) over each folder (a
/// suite's variant) holding at least this many comparisons, and over all.
constexpr int kCostGeomeanMinimum = 3;
/// Relative tolerance of a deterministic metric (accuracy errors, FEM
/// verification values, leg outcomes): 1 %, so a 5 % change fails.
constexpr double kDeterministicTolerance = 0.01;
/// Smallest relative tolerance of a cost metric, and the factor on the measured
/// relative spread (max - min) / median over repeated runs (see the README).
/// 20 %: CI's run on an idle machine moved cost/all.cost_ratio_geomean by
/// +14.5 % from a baseline whose three runs (6.8 % apart) shared the machine
/// with other jobs, so the spread of a few runs under one load understates
/// the move between loads. A 30 % slowdown still fails at the load the
/// baseline was measured at (idle); under other jobs' load the ratio falls
/// about 14 %, which can hide most of it.
constexpr double kCostToleranceFloor = 0.20;
constexpr double kCostSpreadFactor = 2.0;

/// True for a speed metric (KEY `cost_ratio...`): relative, spread-derived tolerance.
bool is_cost_metric(const std::string& key);

/// "KEY" -> value for every finite guarded value in DIR's comparison files,
/// suite.json verification rows and leg summaries (recursively). Throws
/// msd::Error naming a file that cannot be read, a spec that appears twice in
/// one folder, or a folder with nothing to check.
std::map<std::string, double> collect_metrics(const std::string& dir);

struct GuardEntry {
  double value = 0.0;
  double tolerance = 0.0;
  bool relative = false;   ///< tolerance as a fraction of |value|
  std::string basis;       ///< how the tolerance was chosen (kept by --update)
};

struct Baseline {
  std::string tier;
  std::map<std::string, GuardEntry> metrics;
};

/// Reads a baseline. Refuses (msd::Error naming the file, line and field) an
/// unknown field, a missing, non-finite or negative tolerance, a non-finite
/// value and an empty `metrics` map.
Baseline read_baseline(const std::string& path);
/// Writes it (atomically: a temporary file renamed).
void write_baseline(const Baseline& b, const std::string& path);

/// The tolerance of a new baseline entry from one run: deterministic metrics
/// kDeterministicTolerance relative; cost_ratio kCostToleranceFloor relative.
GuardEntry default_entry(const std::string& key, double value);

struct GuardReport {
  std::vector<std::string> failures;   ///< what moved beyond its tolerance, or is missing
  std::vector<std::string> notes;      ///< metrics not in the baseline
  int checked = 0;                     ///< baseline metrics found in the folder
  int total = 0;                       ///< metrics in the baseline
  bool ok() const { return failures.empty(); }
};

/// Compares the metrics with the baseline: a metric fails when
/// |value - baseline| > tolerance (times |baseline| when relative) or when the
/// baseline has it and the folder does not.
GuardReport check_metrics(const std::map<std::string, double>& metrics, const Baseline& baseline);

/// A baseline from the metrics of one run, keeping the tolerances (and bases)
/// of entries `old` already had; `changes` receives one line per added,
/// removed or moved entry.
Baseline updated_baseline(const std::map<std::string, double>& metrics, const Baseline& old,
                          std::vector<std::string>& changes);

/// One metric over repeated runs.
struct Spread {
  std::string key;
  double min = 0.0, max = 0.0, median = 0.0;
  int runs = 0;
  double relative() const;  ///< (max - min) / |median| (0 when identical)
};

/// A baseline from several runs of the same tier, every tolerance derived from
/// the measured spread: metrics identical in every run get
/// kDeterministicTolerance (an accuracy metric that varies gets
/// max(kDeterministicTolerance, kCostSpreadFactor x spread) and a basis saying
/// it is not deterministic); cost metrics get max(kCostToleranceFloor,
/// kCostSpreadFactor x spread). Values are the median run's. A metric missing
/// from some run is left out and listed in `changes`. `spreads` receives the
/// table.
Baseline baseline_from_runs(const std::vector<std::map<std::string, double>>& runs, const std::string& tier,
                            std::vector<Spread>& spreads, std::vector<std::string>& changes);

}  // namespace bench
