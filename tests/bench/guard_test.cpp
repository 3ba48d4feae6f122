// The regression guard's pieces: metrics from comparison files, the check,
// baseline files and their update.
#include "bench/guard.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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
  ASSERT_EQ(m.size(), 4u);
  EXPECT_DOUBLE_EQ(m.at("a/uni.load_rel_rms"), 0.25);
  EXPECT_DOUBLE_EQ(m.at("b/c/shear.cost_ratio"), 0.2);
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

TEST(Guard, ChecksAbsoluteAndRelativeTolerancesAndMissingMetrics) {
  bench::Baseline b;
  b.metrics["uni.load_rel_rms"] = {0.25, 0.02, false};
  b.metrics["uni.cost_ratio"] = {0.1, 0.5, true};
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
  b.metrics["uni.load_rel_rms"] = {0.25, 0.03, false};
  b.metrics["gone.load_rel_rms"] = {0.1, 0.01, false};
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
    EXPECT_NE(std::string(e.what()).find("bad.yaml:2: metrics.uni.load_rel_rms"), std::string::npos) << e.what();
  }
}
