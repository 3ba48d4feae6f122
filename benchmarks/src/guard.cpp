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
                                            "frequency_rel_error",    "damping_ratio_abs_error",
                                            "cost_ratio"};

std::map<std::string, double> collect_metrics(const std::string& dir) {
  if (!fs::is_directory(dir)) throw msd::Error(dir + ": no such folder");
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.size() > 13 && name.compare(name.size() - 13, 13, "_compare.json") == 0)
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::map<std::string, double> m;
  std::map<std::string, std::string> source;
  for (const auto& f : files) {
    YAML::Node j;
    try {
      j = YAML::LoadFile(f.string());
    } catch (const YAML::Exception& e) {
      throw msd::Error(f.string() + ": not a comparison file (" + e.msg + ")");
    }
    if (!j["spec"] || !j["load_rel_rms"]) throw msd::Error(f.string() + ": not a comparison file (no spec / load_rel_rms)");
    // Keyed by the file's folder under `dir` (a suite's variant) and the spec.
    const std::string rel = fs::relative(f.parent_path(), dir).generic_string();
    const std::string spec = (rel.empty() || rel == "." ? "" : rel + "/") + j["spec"].as<std::string>();
    if (source.count(spec))
      throw msd::Error(f.string() + ": spec '" + spec + "' is compared twice (also in " + source[spec] + ")");
    source[spec] = f.string();
    for (const auto& k : kGuardedKeys) {
      const YAML::Node v = j[k];
      if (!v || v.IsNull()) continue;
      double x = 0.0;
      try {
        x = v.as<double>();
      } catch (const YAML::Exception&) {
        continue;
      }
      if (std::isfinite(x)) m[spec + "." + k] = x;
    }
  }
  if (files.empty()) throw msd::Error(dir + ": no *_compare.json files (run the suite or `run --solver both` first)");
  return m;
}

Baseline read_baseline(const std::string& path) {
  const YAML::Node root = load_yaml_file(path, "baseline");
  // Shapes checked before use, so bad input is refused with a message, never a
  // yaml-cpp exception (tests/fuzz/regressions/baseline/).
  if (!root.IsMap()) throw msd::Error(path + ": the baseline must be a YAML mapping");
  Baseline b;
  if (const YAML::Node tier = root["tier"]) {
    if (!tier.IsScalar()) throw msd::Error(path + ":" + std::to_string(tier.Mark().line + 1) + ": tier must be a name");
    b.tier = tier.Scalar();
  }
  const YAML::Node m = root["metrics"];
  if (!m || !m.IsMap()) throw msd::Error(path + ": no 'metrics' map");
  for (const auto& kv : m) {
    if (!kv.first.IsScalar())
      throw msd::Error(path + ":" + std::to_string(kv.first.Mark().line + 1) + ": a metric's name must be a key");
    const std::string key = kv.first.Scalar();
    const YAML::Node e = kv.second;
    const std::string where = path + ":" + std::to_string(e.Mark().line + 1) + ": metrics." + key;
    GuardEntry g;
    try {
      if (!e.IsMap() || !e["value"] || !e["tolerance"]) throw msd::Error(where + ": needs value and tolerance");
      g.value = e["value"].as<double>();
      g.tolerance = e["tolerance"].as<double>();
      g.relative = e["relative"] && e["relative"].as<bool>();
    } catch (const YAML::Exception&) {
      throw msd::Error(where + ": value and tolerance must be numbers, relative true or false");
    }
    if (!std::isfinite(g.value) || !(g.tolerance >= 0.0)) throw msd::Error(where + ": bad value or tolerance");
    b.metrics[key] = g;
  }
  return b;
}

void write_baseline(const Baseline& b, const std::string& path) {
  msd::write_file_atomically(path, [&](std::ostream& out) {
    out << "# tissuebench regression baseline - written by `tissuebench check --update`; edit tolerances by hand.\n"
        << "# Accuracy metrics: absolute tolerances on the error fractions; cost_ratio (msd/fem cost\n"
        << "# measured in the same run): relative. Keys: SPEC.KEY of the *_compare.json files.\n"
        << "tier: " << (b.tier.empty() ? "custom" : b.tier) << "\nmetrics:\n";
    for (const auto& [k, e] : b.metrics)
      out << "  " << k << ": {value: " << json_number(e.value, 6) << ", tolerance: " << json_number(e.tolerance, 4)
          << (e.relative ? ", relative: true" : "") << "}\n";
  });
}

GuardEntry default_entry(const std::string& key, double value) {
  GuardEntry e;
  e.value = value;
  const bool speed = key.size() >= 10 && key.compare(key.size() - 10, 10, "cost_ratio") == 0;
  if (speed) {
    e.tolerance = 1.0;
    e.relative = true;
  } else {
    e.tolerance = std::max(0.005, 0.1 * std::abs(value));
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
    if (std::abs(d) > allowed(e) * (1.0 + 1e-12))
      r.failures.push_back(key + ": " + json_number(it->second, 4) + " against baseline " + describe(e) + " - moved " +
                           (d > 0 ? "+" : "") + json_number(d, 3) + (e.relative ? " (" + json_number(100.0 * d / e.value, 3) + " %)" : ""));
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

}  // namespace bench
