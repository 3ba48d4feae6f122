#include "tbio/results_file.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <fstream>

namespace {

tbio::RunMeta meta() {
  tbio::RunMeta m;
  m.solver = "msd";
  m.spec_text = "name: t\n";
  m.spec_path = "t.yaml";
  m.spec_name = "t";
  m.material = {{"k_s", 10.75}, {"density", 920}};
  m.text = {{"terms", "springs"}};
  return m;
}

}  // namespace

TEST(ResultsFile, WriteReadRoundTrip) {
  testing_support::TempDir dir("results");
  {
    tbio::ResultsWriter w(dir.file("r.h5"), meta(), {{"time", "s"}, {"nominal_stress", "Pa"}});
    for (int i = 0; i < 1500; ++i) w.append({0.01 * i, -2.0 * i});
    w.set_timing(1.25, 1500, 1e-4, 1);
    w.finish();
  }
  const tbio::Results r = tbio::read_results(dir.file("r.h5"));
  EXPECT_EQ(r.status(), "complete");
  EXPECT_EQ(r.meta.at("solver"), "msd");
  EXPECT_EQ(r.meta.at("spec"), "name: t\n");
  EXPECT_EQ(r.meta.at("terms"), "springs");
  EXPECT_FALSE(r.meta.at("git_revision").empty());
  EXPECT_FALSE(r.meta.at("created").empty());
  EXPECT_DOUBLE_EQ(r.material.at("k_s"), 10.75);
  ASSERT_EQ(r.series.at("time").size(), 1500u);
  EXPECT_DOUBLE_EQ(r.series.at("nominal_stress")[1499], -2998.0);
  EXPECT_EQ(r.units.at("nominal_stress"), "Pa");
  EXPECT_DOUBLE_EQ(r.timing.at("wall_seconds"), 1.25);
  EXPECT_DOUBLE_EQ(r.timing.at("steps"), 1500);
  // The CSV twin holds the same rows.
  std::ifstream csv(dir.file("r.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "time,nominal_stress");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 1500);
}

TEST(ResultsFile, FailedRunKeepsRowsAndSaysWhy) {
  testing_support::TempDir dir("results");
  {
    tbio::ResultsWriter w(dir.file("f.h5"), meta(), {{"time", "s"}});
    w.append({0.0});
    w.append({0.1});
    w.fail("blow-up at t = 0.1 s (step 1000), node 3");
  }
  const tbio::Results r = tbio::read_results(dir.file("f.h5"));
  EXPECT_EQ(r.status(), "failed");
  EXPECT_EQ(r.meta.at("failure"), "blow-up at t = 0.1 s (step 1000), node 3");
  EXPECT_EQ(r.series.at("time").size(), 2u);
}

TEST(ResultsFile, InterruptedRunIsReadableAndMarkedIncomplete) {
  testing_support::TempDir dir("results");
  const std::string path = dir.file("i.h5");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // The child writes, flushes by time, and dies without finishing.
    tbio::ResultsWriter w(path, meta(), {{"time", "s"}});
    for (int i = 0; i < 100; ++i) w.append({double(i)});
    usleep(600 * 1000);
    w.append({100.0});  // triggers a time-based flush
    _exit(0);           // no destructor, no finish
  }
  int status = 0;
  waitpid(pid, &status, 0);
  const tbio::Results r = tbio::read_results(path);
  EXPECT_EQ(r.status(), "incomplete");
  EXPECT_EQ(r.series.at("time").size(), 101u);
}

TEST(ResultsFile, ReadingSomethingElseFailsClearly) {
  testing_support::TempDir dir("results");
  EXPECT_THROW(tbio::read_results(dir.file("missing.h5")), msd::Error);
  std::ofstream(dir.file("text.h5")) << "not hdf5";
  EXPECT_THROW(tbio::read_results(dir.file("text.h5")), msd::Error);
}

TEST(ResultsFile, RowWidthIsChecked) {
  testing_support::TempDir dir("results");
  tbio::ResultsWriter w(dir.file("w.h5"), meta(), {{"a", "1"}, {"b", "1"}});
  EXPECT_THROW(w.append({1.0}), msd::Error);
}
