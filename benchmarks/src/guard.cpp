#include "bench/guard.hpp"
#include "bench/shared_io.hpp"

#include "msd/core/types.hpp"
#include "msd/io/atomic_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace bench {

namespace fs = std::filesystem;

const std::vector<std::string> kGuardedKeys{"load_rel_rms",          "load_rel_rms_working",
                                            "volume_ratio_max_error", "displacement_rel_rms",
                                            "frequency_rel_error",    "damping_ratio_abs_error"};

// The outcomes reports/leg_outcomes.yaml shows for the quick tier's scenes
// (drop, hamstrings) and the knee angles every scene reports (not the start
// and smallest angles: the scene sets those, they measure nothing).
const std::vector<std::string> kGuardedLegValues{
    "knee_angle_max_deg",           "knee_angle_end_deg",
    "lower_leg_highest_below_horizontal_deg",
    "drop_swing_period_s",          "drop_successive_peak_ratio",
    "drop_damping_ratio",           "drop_first_swing_amplitude_deg",
    "drop_rest_angle_deg",          "drop_oscillations",
    "drop_swing_centre_deg",
    "back_muscle_length_ratio_min", "back_muscle_radius_ratio_max",
    "tendon_back_lower_straightness_max", "tendon_back_lower_tension_max_N",
    "bulge_back_of_thigh_max_m"};

bool is_cost_metric(const std::string& key) { return key.find(".cost_ratio") != std::string::npos; }

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

YAML::Node load_json(const fs::path& f, const std::string& what) {
  try {
    return YAML::LoadFile(f.string());
  } catch (const YAML::Exception& e) {
    throw msd::Error(f.string() + ": not a " + what + " (" + e.msg + ")");
  }
}

// A finite number, or false (null, missing, text).
bool finite_number(const YAML::Node& v, double& x) {
  if (!v || !v.IsScalar()) return false;
  try {
    x = v.as<double>();
  } catch (const YAML::Exception&) {
    return false;
  }
  return std::isfinite(x);
}

std::string folder_key(const fs::path& file, const std::string& dir) {
  const std::string rel = fs::relative(file.parent_path(), dir).generic_string();
  return rel.empty() || rel == "." ? "" : rel;
}

// Cost ratios of the comparisons, by folder ("" for files directly in DIR).
using CostRatios = std::map<std::string, std::vector<double>>;

void collect_comparison(const fs::path& f, const std::string& dir, std::map<std::string, double>& m,
                        std::map<std::string, std::string>& source, CostRatios& costs) {
  const YAML::Node j = load_json(f, "comparison file");
  if (!j["spec"] || !j["load_rel_rms"]) throw msd::Error(f.string() + ": not a comparison file (no spec / load_rel_rms)");
  const std::string folder = folder_key(f, dir);
  const std::string spec = (folder.empty() ? "" : folder + "/") + j["spec"].as<std::string>();
  if (source.count(spec))
    throw msd::Error(f.string() + ": spec '" + spec + "' is compared twice (also in " + source[spec] + ")");
  source[spec] = f.string();
  for (const auto& k : kGuardedKeys) {
    double x = 0.0;
    if (finite_number(j[k], x)) m[spec + "." + k] = x;
  }
  double ratio = 0.0;
  if (finite_number(j["cost_ratio"], ratio) && ratio > 0.0) costs[folder].push_back(ratio);
}

double geometric_mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += std::log(x);
  return std::exp(sum / static_cast<double>(v.size()));
}

// The guarded speed figures: the geometric mean of the cost ratios of each
// folder with at least kCostGeomeanMinimum comparisons ("cost/FOLDER.cost_ratio_geomean")
// and of all of them ("cost/all.cost_ratio_geomean"). One benchmark's ratio
// varies too much from run to run to be guarded alone (benchmarks/README.md).
void collect_cost_geomeans(const CostRatios& costs, std::map<std::string, double>& m) {
  std::vector<double> all;
  for (const auto& [folder, ratios] : costs) {
    all.insert(all.end(), ratios.begin(), ratios.end());
    if (static_cast<int>(ratios.size()) >= kCostGeomeanMinimum)
      m["cost/" + (folder.empty() ? std::string(".") : folder) + ".cost_ratio_geomean"] = geometric_mean(ratios);
  }
  if (costs.size() > 1 && static_cast<int>(all.size()) >= kCostGeomeanMinimum)
    m["cost/all.cost_ratio_geomean"] = geometric_mean(all);
}

// A leg run's summary.json (one run: `values`; a scene with variants writes
// one summary per variant folder, plus a `variants` map that is skipped here).
void collect_leg_summary(const fs::path& f, const std::string& dir, std::map<std::string, double>& m) {
  const YAML::Node j = load_json(f, "leg summary");
  if (!j.IsMap() || !j["values"] || !j["status"]) return;
  if (j["status"].as<std::string>() != "complete") return;  // its baseline entries fail as missing
  const std::string folder = folder_key(f, dir);
  const std::string prefix = folder.empty() ? j["scene"].as<std::string>("leg") : folder;
  for (const auto& k : kGuardedLegValues) {
    double x = 0.0;
    if (finite_number(j["values"][k], x)) m[prefix + "." + k] = x;
  }
}

// The FEM verification rows of a suite manifest.
void collect_verification(const fs::path& f, std::map<std::string, double>& m) {
  const YAML::Node j = load_json(f, "suite manifest");
  const YAML::Node rows = j["verification"];
  if (!rows || !rows.IsSequence()) return;
  for (const auto& r : rows) {
    if (!r["name"]) throw msd::Error(f.string() + ": verification: a row without a name");
    const std::string name = "verification/" + r["name"].as<std::string>();
    for (const char* k : {"value", "rel_error"}) {
      double x = 0.0;
      if (finite_number(r[k], x)) m[name + "." + k] = x;
    }
  }
}

}  // namespace

std::map<std::string, double> collect_metrics(const std::string& dir) {
  if (!fs::is_directory(dir)) throw msd::Error(dir + ": no such folder");
  std::vector<fs::path> comparisons, summaries;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file()) continue;
    if (name.size() > 13 && ends_with(name, "_compare.json")) comparisons.push_back(e.path());
    if (name == "summary.json") summaries.push_back(e.path());
  }
  std::sort(comparisons.begin(), comparisons.end());
  std::sort(summaries.begin(), summaries.end());
  std::map<std::string, double> m;
  std::map<std::string, std::string> source;
  CostRatios costs;
  for (const auto& f : comparisons) collect_comparison(f, dir, m, source, costs);
  collect_cost_geomeans(costs, m);
  for (const auto& f : summaries) collect_leg_summary(f, dir, m);
  const fs::path manifest = fs::path(dir) / "suite.json";
  if (fs::is_regular_file(manifest)) collect_verification(manifest, m);
  if (comparisons.empty() && m.empty())
    throw msd::Error(dir + ": no *_compare.json files, leg summaries or suite verification (run the suite or "
                           "`run --solver both` first)");
  return m;
}

Baseline read_baseline(const std::string& path) {
  const YAML::Node root = load_yaml_file(path, "baseline");
  if (!root.IsMap()) throw msd::Error(path + ": a baseline is a mapping with 'tier' and 'metrics'");
  const Fields f(root, "", path);
  f.only({"tier", "metrics"});
  Baseline b;
  b.tier = f.text_or("tier", "");
  if (!f.has("metrics") || !root["metrics"].IsMap())
    throw msd::Error(f.where("metrics") + "required: a map of metrics (KEY: {value, tolerance})");
  if (root["metrics"].size() == 0)
    throw msd::Error(f.where("metrics") + "empty: a baseline that guards nothing is refused");
  for (const auto& kv : root["metrics"]) {
    // Shapes checked before use: bad input is refused with a message, never a
    // yaml-cpp exception (tests/fuzz/regressions/baseline/).
    if (!kv.first.IsScalar())
      throw msd::Error(path + ":" + std::to_string(kv.first.Mark().line + 1) + ": a metric's name must be a key");
    const std::string key = kv.first.Scalar();
    if (!kv.second.IsMap())
      throw msd::Error(Fields(root["metrics"], "metrics", path).where(key) + "expected {value, tolerance}");
    const Fields e(kv.second, "metrics." + key, path);
    e.only({"value", "tolerance", "relative", "basis"});
    GuardEntry g;
    g.value = e.number("value");          // required, finite
    g.tolerance = e.number("tolerance");  // required, finite
    if (g.tolerance < 0.0) throw msd::Error(e.where("tolerance") + "must be >= 0, got " + json_number(g.tolerance));
    g.relative = e.flag_or("relative", false);
    g.basis = e.text_or("basis", "");
    b.metrics[key] = g;
  }
  return b;
}

namespace {

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return q + "\"";
}

}  // namespace

void write_baseline(const Baseline& b, const std::string& path) {
  msd::write_file_atomically(path, [&](std::ostream& out) {
    out << "# tissuebench regression baseline - written by `tissuebench check --update` (from several runs:\n"
        << "# tolerances from their measured spread); edit tolerances by hand and say why in `basis`.\n"
        << "# Accuracy errors, FEM verification values and leg outcomes are deterministic (bit-identical run to\n"
        << "# run): 1 % relative. Speed: cost/*.cost_ratio_geomean, the geometric mean of the MSD/FEM CPU cost\n"
        << "# ratios measured in the same run, max(20 %, 2 x the measured spread). Rule and figures:\n"
        << "# benchmarks/README.md, \"The regression guard\".\n"
        << "tier: " << (b.tier.empty() ? "custom" : b.tier) << "\nmetrics:\n";
    for (const auto& [k, e] : b.metrics) {
      out << "  " << k << ": {value: " << json_number(e.value, 10) << ", tolerance: " << json_number(e.tolerance, 4)
          << (e.relative ? ", relative: true" : "");
      if (!e.basis.empty()) out << ", basis: " << quoted(e.basis);
      out << "}\n";
    }
  });
}

GuardEntry default_entry(const std::string& key, double value) {
  GuardEntry e;
  e.value = value;
  e.relative = true;
  if (is_cost_metric(key)) {
    e.tolerance = kCostToleranceFloor;
    e.basis = "cost, one run: the floor " + json_number(100.0 * kCostToleranceFloor, 3) + " %";
  } else {
    e.tolerance = kDeterministicTolerance;
    e.basis = "deterministic: " + json_number(100.0 * kDeterministicTolerance, 3) + " %";
  }
  return e;
}

namespace {

std::string describe(const GuardEntry& e) {
  std::ostringstream s;
  s << json_number(e.value, 4) << " ± " << (e.relative ? json_number(100.0 * e.tolerance, 3) + " %" : json_number(e.tolerance, 3));
  return s.str();
}

double allowed(const GuardEntry& e) { return e.relative ? e.tolerance * std::abs(e.value) : e.tolerance; }

}  // namespace

GuardReport check_metrics(const std::map<std::string, double>& metrics, const Baseline& baseline) {
  GuardReport r;
  r.total = static_cast<int>(baseline.metrics.size());
  for (const auto& [key, e] : baseline.metrics) {
    const auto it = metrics.find(key);
    if (it == metrics.end()) {
      r.failures.push_back(key + ": missing (baseline " + describe(e) + ")");
      continue;
    }
    ++r.checked;
    const double d = it->second - e.value;
    if (!(std::abs(d) <= allowed(e) * (1.0 + 1e-12)))
      r.failures.push_back(key + ": " + json_number(it->second, 4) + " against baseline " + describe(e) + " - moved " +
                           (d > 0 ? "+" : "") + json_number(d, 3) +
                           (e.value != 0.0 ? " (" + json_number(100.0 * d / std::abs(e.value), 3) + " %)" : ""));
  }
  for (const auto& [key, v] : metrics)
    if (!baseline.metrics.count(key)) r.notes.push_back(key + " = " + json_number(v, 4) + " is not in the baseline");
  return r;
}

Baseline updated_baseline(const std::map<std::string, double>& metrics, const Baseline& old,
                          std::vector<std::string>& changes) {
  Baseline b;
  b.tier = old.tier;
  for (const auto& [key, v] : metrics) {
    const auto it = old.metrics.find(key);
    GuardEntry e = default_entry(key, v);
    if (it != old.metrics.end()) {
      e.tolerance = it->second.tolerance;
      e.relative = it->second.relative;
      e.basis = it->second.basis;
      if (v != it->second.value)
        changes.push_back(key + ": " + json_number(it->second.value, 4) + " -> " + json_number(v, 4) +
                          (std::abs(v - it->second.value) > allowed(it->second) ? " (beyond the old tolerance)" : ""));
    } else {
      changes.push_back(key + ": added, " + describe(e));
    }
    b.metrics[key] = e;
  }
  for (const auto& [key, e] : old.metrics)
    if (!metrics.count(key)) changes.push_back(key + ": removed (was " + describe(e) + ")");
  return b;
}

double Spread::relative() const { return max == min ? 0.0 : (max - min) / std::abs(median); }

Baseline baseline_from_runs(const std::vector<std::map<std::string, double>>& runs, const std::string& tier,
                            std::vector<Spread>& spreads, std::vector<std::string>& changes) {
  if (runs.size() < 2) throw msd::Error("check --update: a spread needs at least two runs");
  Baseline b;
  b.tier = tier;
  const int n = static_cast<int>(runs.size());
  std::map<std::string, int> seen;
  for (const auto& r : runs)
    for (const auto& [k, v] : r) ++seen[k];
  for (const auto& [key, count] : seen) {
    if (count != n) {
      changes.push_back(key + ": left out (in " + std::to_string(count) + " of " + std::to_string(n) + " runs)");
      continue;
    }
    std::vector<double> v;
    for (const auto& r : runs) v.push_back(r.at(key));
    std::sort(v.begin(), v.end());
    Spread s;
    s.key = key;
    s.runs = n;
    s.min = v.front();
    s.max = v.back();
    s.median = v[v.size() / 2];  // a measured run's value (the upper median)
    spreads.push_back(s);
    const double rel = s.relative();
    const std::string measured = "measured over " + std::to_string(n) + " runs: ";
    GuardEntry e;
    e.value = s.median;
    e.relative = true;
    if (is_cost_metric(key)) {
      e.tolerance = std::max(kCostToleranceFloor, kCostSpreadFactor * rel);
      e.basis = "cost, " + measured + "spread " + json_number(100.0 * rel, 3) + " %; tolerance max(" +
                json_number(100.0 * kCostToleranceFloor, 3) + " %, " + json_number(kCostSpreadFactor, 3) + " x spread)";
    } else if (rel == 0.0) {
      e.tolerance = kDeterministicTolerance;
      e.basis = "deterministic, " + measured + "bit-identical; tolerance " +
                json_number(100.0 * kDeterministicTolerance, 3) + " %";
    } else {
      e.tolerance = std::max(kDeterministicTolerance, kCostSpreadFactor * rel);
      e.basis = "NOT deterministic, " + measured + "spread " + json_number(100.0 * rel, 3) + " %; tolerance max(" +
                json_number(100.0 * kDeterministicTolerance, 3) + " %, " + json_number(kCostSpreadFactor, 3) +
                " x spread)";
      changes.push_back(key + ": not deterministic (spread " + json_number(100.0 * rel, 3) + " %)");
    }
    b.metrics[key] = e;
  }
  return b;
}

}  // namespace bench
