// The regression guard's pieces: metrics from comparison files, the check,
// baseline files and their update.
#include "bench/guard.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include "tbio/json.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

void write_compare(const std::string& file, const std::string& spec, double rel, double cost_ratio) {
  std::filesystem::create_directories(std::filesystem::path(file).parent_path());
  std::ofstream(file) << "{\n  \"spec\": \"" << spec << "\",\n  \"loading\": \"uniaxial\",\n  \"load_rel_rms\": " << rel
                      << ",\n  \"load_rel_rms_working\": null,\n  \"cost_ratio\": " << cost_ratio << "\n}\n";
}

}  // namespace

TEST(Guard, CollectsFiniteGuardedKeysFromEveryComparisonUnderTheFolder) {
  testing_support::TempDir d("guard");
  write_compare(d.file("a/uni_compare.json"), "uni", 0.25, 0.1);
  write_compare(d.file("b/c/shear_compare.json"), "shear", 0.05, 0.2);
  std::ofstream(d.file("other.json")) << "{}";  // not a comparison file name: ignored
  const auto m = bench::collect_metrics(d.path().string());
  ASSERT_EQ(m.size(), 2u);  // one comparison's cost_ratio is not guarded (too noisy alone)
  EXPECT_DOUBLE_EQ(m.at("a/uni.load_rel_rms"), 0.25);
  EXPECT_DOUBLE_EQ(m.at("b/c/shear.load_rel_rms"), 0.05);
  EXPECT_EQ(m.count("a/uni.load_rel_rms_working"), 0u);  // null: not applicable
  // The same spec in another folder is another entry (a suite's variants) ...
  write_compare(d.file("z/uni_compare.json"), "uni", 0.3, 0.1);
  EXPECT_DOUBLE_EQ(bench::collect_metrics(d.path().string()).at("z/uni.load_rel_rms"), 0.3);
  // ... twice in one folder it is ambiguous; an empty folder has nothing to check.
  write_compare(d.file("z/uni2_compare.json"), "uni", 0.3, 0.1);
  EXPECT_THROW(bench::collect_metrics(d.path().string()), msd::Error);
  testing_support::TempDir empty("guard");
  EXPECT_THROW(bench::collect_metrics(empty.path().string()), msd::Error);
}

TEST(Guard, SpeedIsTheGeometricMeanOfTheCostRatiosPerFolderAndOverAll) {
  testing_support::TempDir d("guard");
  write_compare(d.file("physical/a_compare.json"), "a", 0.1, 0.1);
  write_compare(d.file("physical/b_compare.json"), "b", 0.1, 0.2);
  write_compare(d.file("physical/c_compare.json"), "c", 0.1, 0.4);
  write_compare(d.file("thesis/a_compare.json"), "a", 0.1, 1.6);  // one comparison: no folder figure
  const auto m = bench::collect_metrics(d.path().string());
  EXPECT_NEAR(m.at("cost/physical.cost_ratio_geomean"), 0.2, 1e-12);
  EXPECT_EQ(m.count("cost/thesis.cost_ratio_geomean"), 0u);
  EXPECT_NEAR(m.at("cost/all.cost_ratio_geomean"), std::pow(0.1 * 0.2 * 0.4 * 1.6, 0.25), 1e-12);
  EXPECT_TRUE(bench::is_cost_metric("cost/all.cost_ratio_geomean"));
  EXPECT_FALSE(bench::is_cost_metric("physical/a.load_rel_rms"));
  // Every run of a folder 30 % slower moves its figure and the overall one by 30 %.
  for (const char* f : {"physical/a_compare.json", "physical/b_compare.json", "physical/c_compare.json"})
    write_compare(d.file(f), std::string(f).substr(9, 1), 0.1, 1.3 * (f[9] == 'a' ? 0.1 : f[9] == 'b' ? 0.2 : 0.4));
  const auto slow = bench::collect_metrics(d.path().string());
  EXPECT_NEAR(slow.at("cost/physical.cost_ratio_geomean"), 0.26, 1e-12);
}

TEST(Guard, ChecksAbsoluteAndRelativeTolerancesAndMissingMetrics) {
  bench::Baseline b;
  b.metrics["uni.load_rel_rms"] = {0.25, 0.02, false, ""};
  b.metrics["uni.cost_ratio"] = {0.1, 0.5, true, ""};
  EXPECT_TRUE(bench::check_metrics({{"uni.load_rel_rms", 0.265}, {"uni.cost_ratio", 0.149}}, b).ok());
  bench::GuardReport r = bench::check_metrics({{"uni.load_rel_rms", 0.28}, {"uni.cost_ratio", 0.16}}, b);
  ASSERT_EQ(r.failures.size(), 2u);
  EXPECT_NE(r.failures[0].find("uni.cost_ratio: 0.16 against baseline 0.1"), std::string::npos) << r.failures[0];
  EXPECT_NE(r.failures[1].find("uni.load_rel_rms: 0.28"), std::string::npos) << r.failures[1];
  EXPECT_NE(r.failures[1].find("moved +0.03"), std::string::npos) << r.failures[1];
  // Improvements beyond the tolerance also fail: the baseline must be updated deliberately.
  EXPECT_FALSE(bench::check_metrics({{"uni.load_rel_rms", 0.2}, {"uni.cost_ratio", 0.1}}, b).ok());
  r = bench::check_metrics({{"uni.cost_ratio", 0.1}, {"new.load_rel_rms", 0.5}}, b);
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("missing"), std::string::npos);
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_EQ(r.total, 2);
}

TEST(Guard, BaselineRoundTripsAndUpdateKeepsTolerancesAndListsChanges) {
  testing_support::TempDir d("guard");
  bench::Baseline b;
  b.tier = "quick";
  b.metrics["uni.load_rel_rms"] = {0.25, 0.03, false, ""};
  b.metrics["gone.load_rel_rms"] = {0.1, 0.01, false, ""};
  bench::write_baseline(b, d.file("base.yaml"));
  const bench::Baseline r = bench::read_baseline(d.file("base.yaml"));
  EXPECT_EQ(r.tier, "quick");
  ASSERT_EQ(r.metrics.size(), 2u);
  EXPECT_DOUBLE_EQ(r.metrics.at("uni.load_rel_rms").tolerance, 0.03);
  std::vector<std::string> changes;
  const bench::Baseline u =
      bench::updated_baseline({{"uni.load_rel_rms", 0.3}, {"uni.cost_ratio", 0.2}}, r, changes);
  EXPECT_DOUBLE_EQ(u.metrics.at("uni.load_rel_rms").value, 0.3);
  EXPECT_DOUBLE_EQ(u.metrics.at("uni.load_rel_rms").tolerance, 0.03);  // kept
  EXPECT_TRUE(u.metrics.at("uni.cost_ratio").relative);                // speed: relative by default
  EXPECT_DOUBLE_EQ(u.metrics.at("uni.cost_ratio").tolerance, bench::kCostToleranceFloor);
  EXPECT_EQ(u.metrics.count("gone.load_rel_rms"), 0u);
  ASSERT_EQ(changes.size(), 3u);
  std::string all;
  for (const auto& c : changes) all += c + "\n";
  EXPECT_NE(all.find("uni.load_rel_rms: 0.25 -> 0.3 (beyond the old tolerance)"), std::string::npos) << all;
  EXPECT_NE(all.find("uni.cost_ratio: added"), std::string::npos) << all;
  EXPECT_NE(all.find("gone.load_rel_rms: removed"), std::string::npos) << all;
  // A broken entry is named with its line.
  std::ofstream(d.file("bad.yaml")) << "metrics:\n  uni.load_rel_rms: {value: 0.2}\n";
  try {
    bench::read_baseline(d.file("bad.yaml"));
    FAIL() << "accepted an entry without a tolerance";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:2:21: metrics.uni.load_rel_rms.tolerance: required field is missing"),
              std::string::npos)
        << e.what();
  }
}

namespace {

// The message of read_baseline on FILE holding `text`, or "" if it was accepted.
std::string baseline_refusal(const testing_support::TempDir& d, const std::string& text) {
  std::ofstream(d.file("b.yaml")) << text;
  try {
    bench::read_baseline(d.file("b.yaml"));
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Guard, RefusesInfiniteNanNegativeOrMissingTolerancesAndAnEmptyBaselineNamingFileAndField) {
  testing_support::TempDir d("guard");
  const std::string head = "tier: t\nmetrics:\n  uni.load_rel_rms: ";
  struct Case {
    std::string entry, expect;
  };
  for (const Case& c : std::vector<Case>{{"{value: 0.2, tolerance: .inf}", "metrics.uni.load_rel_rms.tolerance: must be finite"},
                                         {"{value: 0.2, tolerance: -.inf}", "metrics.uni.load_rel_rms.tolerance: must be finite"},
                                         {"{value: 0.2, tolerance: .nan}", "metrics.uni.load_rel_rms.tolerance: must be finite"},
                                         {"{value: 0.2, tolerance: -0.01}", "metrics.uni.load_rel_rms.tolerance: must be >= 0"},
                                         {"{value: 0.2}", "metrics.uni.load_rel_rms.tolerance: required field is missing"},
                                         {"{value: 0.2, tolerance: wide}", "metrics.uni.load_rel_rms.tolerance: expected a number"},
                                         {"{tolerance: 0.1}", "metrics.uni.load_rel_rms.value: required field is missing"},
                                         {"{value: .nan, tolerance: 0.1}", "metrics.uni.load_rel_rms.value: must be finite"},
                                         {"{value: 0.2, tolerance: 0.1, relative: maybe}", "metrics.uni.load_rel_rms.relative"},
                                         {"{value: 0.2, tolerence: 0.1}", "metrics.uni.load_rel_rms.tolerence: unknown field"},
                                         {"0.2", "metrics.uni.load_rel_rms: expected {value, tolerance}"}}) {
    const std::string m = baseline_refusal(d, head + c.entry + "\n");
    EXPECT_NE(m.find(d.file("b.yaml") + ":3:"), std::string::npos) << c.entry << " -> " << m;
    EXPECT_NE(m.find(c.expect), std::string::npos) << c.entry << " -> " << m;
  }
  // A baseline that guards nothing.
  std::string m = baseline_refusal(d, "tier: t\nmetrics: {}\n");
  EXPECT_NE(m.find(d.file("b.yaml") + ":2:"), std::string::npos) << m;
  EXPECT_NE(m.find("metrics: empty"), std::string::npos) << m;
  m = baseline_refusal(d, "tier: t\n");
  EXPECT_NE(m.find("metrics: required"), std::string::npos) << m;
  m = baseline_refusal(d, "tier: t\nmetrics: []\n");
  EXPECT_NE(m.find("metrics: required"), std::string::npos) << m;
  m = baseline_refusal(d, "tier: t\nthreshold: 1\nmetrics:\n  a.cost_ratio: {value: 1, tolerance: 0.1}\n");
  EXPECT_NE(m.find("threshold: unknown field"), std::string::npos) << m;
  // A zero tolerance is legal (exactly this value), and the basis is kept.
  EXPECT_EQ(baseline_refusal(d, head + "{value: 0.2, tolerance: 0, relative: true, basis: \"by hand\"}\n"), "");
  EXPECT_EQ(bench::read_baseline(d.file("b.yaml")).metrics.at("uni.load_rel_rms").basis, "by hand");
}

TEST(Guard, CollectsFemVerificationValuesAndLegOutcomesBesideTheComparisons) {
  testing_support::TempDir d("guard");
  std::ofstream(d.file("suite.json"))
      << R"({"tier": "t", "verification": [{"name": "verify_bar", "quantity": "sag", "value": 0.0021, "reference": 0.002, "rel_error": 0.05},
           {"name": "verify_shear", "value": 1e-9, "reference": 500, "rel_error": null}]})";
  std::filesystem::create_directories(d.file("leg/drop"));
  std::ofstream(d.file("leg/drop/summary.json"))
      << R"({"scene": "drop", "status": "complete", "wall_seconds": 12.5, "values": {"drop_swing_period_s": 1.1,
           "knee_angle_max_deg": 60.5, "contact_area_max_m2": 0.01, "drop_damping_ratio": null}})";
  std::filesystem::create_directories(d.file("leg/ham"));
  std::ofstream(d.file("leg/ham/summary.json"))
      << R"({"scene": "ham", "status": "failed", "values": {"knee_angle_max_deg": 90}})";
  const auto m = bench::collect_metrics(d.path().string());
  EXPECT_DOUBLE_EQ(m.at("verification/verify_bar.value"), 0.0021);
  EXPECT_DOUBLE_EQ(m.at("verification/verify_bar.rel_error"), 0.05);
  EXPECT_DOUBLE_EQ(m.at("verification/verify_shear.value"), 1e-9);
  EXPECT_EQ(m.count("verification/verify_shear.rel_error"), 0u);  // null: nothing to guard
  EXPECT_DOUBLE_EQ(m.at("leg/drop.drop_swing_period_s"), 1.1);
  EXPECT_DOUBLE_EQ(m.at("leg/drop.knee_angle_max_deg"), 60.5);
  EXPECT_EQ(m.count("leg/drop.contact_area_max_m2"), 0u);  // not a guarded outcome
  EXPECT_EQ(m.count("leg/drop.wall_seconds"), 0u);         // timing is never guarded absolutely
  EXPECT_EQ(m.count("leg/ham.knee_angle_max_deg"), 0u);    // a failed run: its entries fail as missing
  EXPECT_EQ(m.size(), 5u);
  bench::Baseline b;
  b.metrics["leg/ham.knee_angle_max_deg"] = {90, 0.01, true, ""};
  const bench::GuardReport r = bench::check_metrics(m, b);
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("leg/ham.knee_angle_max_deg: missing"), std::string::npos) << r.failures[0];
}

TEST(Guard, ABaselineFromRepeatedRunsDerivesEachToleranceFromItsMeasuredSpread) {
  const std::vector<std::map<std::string, double>> runs{
      {{"a.load_rel_rms", 0.2}, {"a.cost_ratio", 0.10}, {"b.cost_ratio", 1.0}, {"c.load_rel_rms", 0.3}, {"only.load_rel_rms", 1}},
      {{"a.load_rel_rms", 0.2}, {"a.cost_ratio", 0.12}, {"b.cost_ratio", 1.01}, {"c.load_rel_rms", 0.33}},
      {{"a.load_rel_rms", 0.2}, {"a.cost_ratio", 0.11}, {"b.cost_ratio", 1.02}, {"c.load_rel_rms", 0.3}}};
  std::vector<bench::Spread> spreads;
  std::vector<std::string> changes;
  const bench::Baseline b = bench::baseline_from_runs(runs, "t", spreads, changes);
  ASSERT_EQ(b.metrics.size(), 4u);
  ASSERT_EQ(spreads.size(), 4u);
  // Bit-identical: the deterministic tolerance.
  EXPECT_DOUBLE_EQ(b.metrics.at("a.load_rel_rms").tolerance, bench::kDeterministicTolerance);
  EXPECT_NE(b.metrics.at("a.load_rel_rms").basis.find("bit-identical"), std::string::npos);
  // Cost: spread (0.12 - 0.10) / 0.11 = 18 %, tolerance twice that; a small spread gets the floor.
  EXPECT_DOUBLE_EQ(b.metrics.at("a.cost_ratio").value, 0.11);
  EXPECT_NEAR(b.metrics.at("a.cost_ratio").tolerance, bench::kCostSpreadFactor * 0.02 / 0.11, 1e-12);
  EXPECT_TRUE(b.metrics.at("a.cost_ratio").relative);
  EXPECT_NE(b.metrics.at("a.cost_ratio").basis.find("spread 18.2 %"), std::string::npos) << b.metrics.at("a.cost_ratio").basis;
  EXPECT_DOUBLE_EQ(b.metrics.at("b.cost_ratio").tolerance, bench::kCostToleranceFloor);
  // An accuracy metric that varies is named, not hidden.
  EXPECT_NE(b.metrics.at("c.load_rel_rms").basis.find("NOT deterministic"), std::string::npos);
  std::string all;
  for (const auto& c : changes) all += c + "\n";
  EXPECT_NE(all.find("c.load_rel_rms: not deterministic"), std::string::npos) << all;
  EXPECT_NE(all.find("only.load_rel_rms: left out (in 1 of 3 runs)"), std::string::npos) << all;
  EXPECT_THROW(bench::baseline_from_runs({runs[0]}, "t", spreads, changes), msd::Error);
}

// ---- The shipped quick baseline against a real quick-tier run ----------------
//
// tests/bench/data/quick_run holds the guard's inputs of one of the quick-tier
// runs the shipped baseline was derived from (its *_compare.json files,
// suite.json and leg summaries; benchmarks/README.md, "The regression guard").

namespace {

const std::string kQuickBaseline = std::string(TISSUEBENCH_SOURCE_DIR) + "/reports/baselines/quick.yaml";
const std::string kQuickRun = std::string(TISSUEBENCH_SOURCE_DIR) + "/tests/bench/data/quick_run";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Multiplies the value behind guard key KEY in the result folder DIR by
// `factor`, in the file the guard reads it from; returns the files and their
// old text. A speed figure: every comparison's cost_ratio in its folder (or
// all of them), i.e. every MSD run of the folder `factor` times slower.
std::vector<std::pair<std::string, std::string>> perturb(const std::string& dir, const std::string& key, double factor) {
  std::vector<std::pair<std::string, std::string>> changed;
  auto scale = [&](const std::string& file, const std::function<tbio::Json&(tbio::Json&)>& at) {
    const std::string old = read_text(file);
    tbio::Json j = tbio::Json::parse(old);
    tbio::Json& v = at(j);
    if (!v.is_number()) throw std::runtime_error(file + ": " + key + " is not a number");
    v = v.get<double>() * factor;
    std::ofstream(file) << j.dump(2);
    changed.emplace_back(file, old);
  };
  if (bench::is_cost_metric(key)) {
    const std::string folder = key.substr(5, key.find('.') - 5);  // cost/FOLDER.cost_ratio_geomean
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
      const std::string f = e.path().string();
      if (f.size() > 13 && f.compare(f.size() - 13, 13, "_compare.json") == 0 &&
          (folder == "all" || e.path().parent_path().filename() == folder))
        scale(f, [](tbio::Json& j) -> tbio::Json& { return j["cost_ratio"]; });
    }
    if (changed.empty()) throw std::runtime_error("no comparison for " + key);
    return changed;
  }
  const size_t dot = key.rfind('.');
  const std::string prefix = key.substr(0, dot), name = key.substr(dot + 1);
  std::string file;
  std::function<tbio::Json&(tbio::Json&)> at;
  if (prefix.rfind("verification/", 0) == 0) {
    file = dir + "/suite.json";
    const std::string row = prefix.substr(13);
    at = [row, name](tbio::Json& j) -> tbio::Json& {
      for (auto& r : j["verification"])
        if (r["name"] == row) return r[name];
      throw std::runtime_error("no verification row " + row);
    };
  } else if (std::filesystem::exists(dir + "/" + prefix + "/summary.json")) {
    file = dir + "/" + prefix + "/summary.json";
    at = [name](tbio::Json& j) -> tbio::Json& { return j["values"][name]; };
  } else {
    file = dir + "/" + prefix + "_compare.json";
    at = [name](tbio::Json& j) -> tbio::Json& { return j[name]; };
  }
  scale(file, at);
  return changed;
}

}  // namespace

TEST(GuardQuickBaseline, EveryToleranceIsFiniteExplainedAndTighterThanTheRegressionsItMustCatch) {
  const bench::Baseline b = bench::read_baseline(kQuickBaseline);
  EXPECT_EQ(b.tier, "quick");
  int cost = 0;
  for (const auto& [key, e] : b.metrics) {
    EXPECT_TRUE(e.relative) << key;
    EXPECT_FALSE(e.basis.empty()) << key << ": the baseline says how each tolerance was chosen";
    if (bench::is_cost_metric(key)) {
      ++cost;
      EXPECT_LT(e.tolerance, 0.3) << key << ": a 30 % slowdown must fail";
    } else {
      EXPECT_LT(e.tolerance, 0.05) << key << ": a 5 % change must fail";
      EXPECT_NE(e.basis.find("bit-identical"), std::string::npos) << key << ": " << e.basis;
    }
  }
  EXPECT_GT(cost, 0);
  // What the quick tier guards beyond the comparison benchmarks' own specs: the
  // shipped uni-axial benchmark, the FEM verification values and the leg scenes' outcomes.
  for (const char* key : {"physical/uniaxial.load_rel_rms", "calibrated/uniaxial.load_rel_rms_working",
                          "cost/physical.cost_ratio_geomean", "cost/calibrated.cost_ratio_geomean",
                          "cost/all.cost_ratio_geomean", "verification/verify_hanging_bar.value",
                          "verification/verify_cooks_membrane.rel_error", "verification/verify_simple_shear.value",
                          "verification/verify_uniaxial_roller.value", "leg/drop.drop_swing_period_s",
                          "leg/drop.drop_damping_ratio", "leg/hamstrings.lower_leg_highest_below_horizontal_deg",
                          "leg/hamstrings.knee_angle_max_deg"})
    EXPECT_EQ(b.metrics.count(key), 1u) << key;
}

TEST(GuardQuickBaseline, ARealQuickRunHoldsAndAFivePercentChangeOfAnyAccuracyMetricOrA30PercentSlowdownFails) {
  const bench::Baseline b = bench::read_baseline(kQuickBaseline);
  testing_support::TempDir d("guard_quick");
  std::filesystem::copy(kQuickRun, d.path(), std::filesystem::copy_options::recursive);
  const std::string dir = d.path().string();
  const bench::GuardReport clean = bench::check_metrics(bench::collect_metrics(dir), b);
  std::string failures;
  for (const auto& f : clean.failures) failures += f + "\n";
  ASSERT_TRUE(clean.ok()) << "the recorded run no longer matches reports/baselines/quick.yaml (regenerated? "
                             "copy one of its runs into tests/bench/data/quick_run):\n" << failures;
  EXPECT_EQ(clean.checked, static_cast<int>(b.metrics.size()));
  int perturbed = 0;
  for (const auto& [key, e] : b.metrics) {
    // Accuracy: 5 % either way; cost: 30 % slower (and 30 % faster: an unexplained
    // speed-up also needs a deliberate update).
    const std::vector<double> factors =
        bench::is_cost_metric(key) ? std::vector<double>{1.3, 0.7} : std::vector<double>{1.05, 0.95};
    for (double f : factors) {
      const auto changed = perturb(dir, key, f);
      const bench::GuardReport r = bench::check_metrics(bench::collect_metrics(dir), b);
      for (const auto& [file, old] : changed) std::ofstream(file) << old;
      ++perturbed;
      std::string all;
      bool named = false;
      for (const auto& x : r.failures) {
        all += x + "\n";
        named = named || x.rfind(key + ": ", 0) == 0;
        // Only this metric moves - or, for a slowdown, only speed figures.
        EXPECT_TRUE(x.rfind(key + ": ", 0) == 0 || (bench::is_cost_metric(key) && bench::is_cost_metric(x.substr(0, x.find(": ")))))
            << key << " x " << f << ": " << x;
      }
      EXPECT_TRUE(named) << key << " x " << f << " passed the check:\n" << all;
    }
  }
  EXPECT_EQ(perturbed, 2 * static_cast<int>(b.metrics.size()));
  EXPECT_TRUE(bench::check_metrics(bench::collect_metrics(dir), b).ok());  // restored
}
