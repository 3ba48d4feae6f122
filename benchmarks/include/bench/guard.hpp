// The regression guard: the metrics of a folder of comparisons against a
// baseline with a tolerance per metric.
//
// Metrics are read from every `*_compare.json` under a folder (the files
// `run --solver both`, `compare --json` and `suite` write), keyed
// "SUBFOLDER/SPEC.KEY" (SUBFOLDER: the file's folder under the one checked, e.g.
// a suite's variant; none for files directly in it) with KEY one of
// kGuardedKeys. Accuracy metrics carry absolute tolerances (the error
// fractions themselves); the one speed figure, `cost_ratio` (MSD cost over FEM
// cost measured on the same machine), carries a relative one - never an
// absolute time.
//
// Baseline file (YAML; written by `tissuebench check --update`):
//     tier: quick
//     metrics:
//       physical/uniaxial.load_rel_rms: {value: 0.807, tolerance: 0.04}
//       physical/uniaxial.cost_ratio: {value: 0.11, tolerance: 0.5, relative: true}
#pragma once

#include <map>
#include <string>
#include <vector>

namespace bench {

/// The compare-JSON keys the guard reads.
extern const std::vector<std::string> kGuardedKeys;

/// "SUBFOLDER/SPEC.KEY" -> value for every finite guarded value in DIR's
/// *_compare.json files (recursively). Throws msd::Error naming a file that
/// cannot be read or a spec that appears twice in one folder.
std::map<std::string, double> collect_metrics(const std::string& dir);

struct GuardEntry {
  double value = 0.0;
  double tolerance = 0.0;
  bool relative = false;   ///< tolerance as a fraction of |value|
};

struct Baseline {
  std::string tier;
  std::map<std::string, GuardEntry> metrics;
};

/// Reads a baseline; errors name the file and the entry.
Baseline read_baseline(const std::string& path);
/// Writes it (atomically: a temporary file renamed).
void write_baseline(const Baseline& b, const std::string& path);

/// The default tolerance of a new baseline entry: accuracy metrics
/// max(0.005, 10 % of the value) absolute; cost_ratio 100 % relative (timings
/// on a shared two-core machine: it flags MSD becoming twice as slow relative to the FEM).
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

/// A baseline from the metrics, keeping the tolerances of entries `old`
/// already had; `changes` receives one line per added, removed or moved entry.
Baseline updated_baseline(const std::map<std::string, double>& metrics, const Baseline& old,
                          std::vector<std::string>& changes);

}  // namespace bench
