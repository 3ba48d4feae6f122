#include "tbio/results_file.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>

#include <csignal>
#include <filesystem>
#include <iterator>
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

TEST(ResultsFile, AKilledRunLeavesTheRealNameUntouchedAndItsTemporaryReadableAndIncomplete) {
  testing_support::TempDir dir("results");
  const std::string path = dir.file("i.h5");
  std::ofstream(path) << "an earlier run";
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
  EXPECT_EQ(testing_support::read_text(path), "an earlier run");
  const std::string tmp = path + ".partial-" + std::to_string(pid);
  const tbio::Results r = tbio::read_results(tmp);
  EXPECT_EQ(r.status(), "incomplete");
  EXPECT_EQ(r.series.at("time").size(), 101u);
}

TEST(ResultsFile, NothingAppearsUnderTheRealNameBeforeTheEnd) {
  testing_support::TempDir dir("results");
  const std::string path = dir.file("p.h5");
  {
    tbio::ResultsWriter w(path, meta(), {{"time", "s"}});
    w.append({0.0});
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(dir.file("p.csv")));
    EXPECT_TRUE(std::filesystem::exists(w.temporary_path()));
    EXPECT_TRUE(std::filesystem::exists(path + ".lock"));
    w.finish();
    EXPECT_FALSE(std::filesystem::exists(w.temporary_path()));
  }
  EXPECT_FALSE(std::filesystem::exists(path + ".lock"));
  EXPECT_EQ(tbio::read_results(path).status(), "complete");
}

TEST(ResultsFile, AWriterLeftWithoutAnEndKeepsItsRowsMarkedFailed) {
  testing_support::TempDir dir("results");
  {
    tbio::ResultsWriter w(dir.file("e.h5"), meta(), {{"time", "s"}});
    w.append({0.0});
  }
  const tbio::Results r = tbio::read_results(dir.file("e.h5"));
  EXPECT_EQ(r.status(), "failed");
  EXPECT_EQ(r.series.at("time").size(), 1u);
}

TEST(ResultsFile, ASecondWriterIsRefusedAndTheExistingFileIsUntouched) {
  testing_support::TempDir dir("results");
  const std::string path = dir.file("c.h5");
  std::ofstream(path) << "the first run's file";
  tbio::ResultsWriter first(path, meta(), {{"time", "s"}});
  const pid_t pid = fork();
  if (pid == 0) {
    try {
      tbio::ResultsWriter second(path, meta(), {{"time", "s"}});
      _exit(0);
    } catch (const msd::Error& e) {
      _exit(std::string(e.what()).find("another run is writing it") != std::string::npos ? 7 : 8);
    }
  }
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_EQ(WEXITSTATUS(status), 7);
  EXPECT_EQ(testing_support::read_text(path), "the first run's file");
  first.append({1.0});
  first.finish();
  EXPECT_EQ(tbio::read_results(path).series.at("time").size(), 1u);
}

TEST(ResultsFile, AFileHeldOpenByAnotherProgramIsNotDestroyed) {
  testing_support::TempDir dir("results");
  const std::string path = dir.file("o.h5");
  {
    tbio::ResultsWriter w(path, meta(), {{"time", "s"}});
    w.append({1.0});
    w.finish();
  }
  const std::string before = testing_support::read_text(path);
  std::ifstream held(path, std::ios::binary);  // another program reading it
  {
    tbio::ResultsWriter w(path, meta(), {{"time", "s"}});
    w.append({2.0});
    w.append({3.0});
    w.finish();
  }
  std::string still((std::istreambuf_iterator<char>(held)), std::istreambuf_iterator<char>());
  EXPECT_EQ(still, before);  // the holder reads the old file whole
  EXPECT_EQ(tbio::read_results(path).series.at("time").size(), 2u);
}

TEST(ResultsFile, AFullDiskNeverCrashesAndLeavesAFailedFileOrNothing) {
  // A file size limit (writes fail with EFBIG, as on a full disk with ENOSPC).
  testing_support::TempDir dir("results");
  const std::string path = dir.file("full.h5");
  std::ofstream(path) << "an earlier run";
  for (rlim_t limit : {rlim_t(2000), rlim_t(40000), rlim_t(400000)}) {
    const pid_t pid = fork();
    if (pid == 0) {
      signal(SIGXFSZ, SIG_IGN);
      struct rlimit r {};
      getrlimit(RLIMIT_FSIZE, &r);
      r.rlim_cur = limit;
      setrlimit(RLIMIT_FSIZE, &r);
      try {
        tbio::ResultsWriter w(path, meta(), {{"time", "s"}, {"x", "m"}});
        w.add_point_set("nodes", std::vector<std::array<double, 3>>(100, {{0, 0, 0}}));
        for (int i = 0; i < 100000; ++i) {
          w.append({double(i), 1.0});
          if (i % 100 == 0) w.append_frame("nodes", i, std::vector<std::array<double, 3>>(100, {{1, 2, 3}}));
        }
        w.finish();
        _exit(0);
      } catch (const tbio::WriteError& e) {
        _exit(5);  // fail() was called by the destructor
      } catch (const msd::Error& e) {
        _exit(6);
      }
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status)) << "crashed with signal " << WTERMSIG(status) << " at limit " << limit;
    EXPECT_EQ(WEXITSTATUS(status), 5) << limit;
    // Either the earlier file untouched, or a readable file marked failed.
    const std::string text = testing_support::read_text(path);
    if (text != "an earlier run") {
      const tbio::Results r = tbio::read_results(path);
      EXPECT_EQ(r.status(), "failed") << limit;
    }
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
      EXPECT_EQ(e.path().string().find(".partial-"), std::string::npos) << e.path();
  }
}

TEST(ResultsFile, ASnapshotRestoredIntoANewWriterGivesTheSameFile) {
  testing_support::TempDir dir("results");
  tbio::ResultsSnapshot snap;
  {
    tbio::ResultsWriter w(dir.file("a.h5"), meta(), {{"time", "s"}, {"x", "m"}});
    w.add_point_set("nodes", {{{0, 0, 0}}, {{1, 0, 0}}}, {});
    for (int i = 0; i < 5; ++i) {
      w.append({0.1 * i, 1.0 / (i + 3)});
      w.append_frame("nodes", 0.1 * i, {{{0.01 * i, 0, 1.0 / 3}}, {{0, 0.02 * i, 0}}});
    }
    snap = w.snapshot();
    w.finish();
  }
  {
    tbio::ResultsWriter w(dir.file("b.h5"), meta(), {{"time", "s"}, {"x", "m"}});
    w.add_point_set("nodes", {{{0, 0, 0}}, {{1, 0, 0}}}, {});
    w.restore(snap);
    w.finish();
  }
  const tbio::Results a = tbio::read_results(dir.file("a.h5")), b = tbio::read_results(dir.file("b.h5"));
  EXPECT_EQ(a.series, b.series);
  const tbio::PointSetData fa = tbio::read_point_set(dir.file("a.h5"), "nodes"),
                           fb = tbio::read_point_set(dir.file("b.h5"), "nodes");
  EXPECT_EQ(fa.time, fb.time);
  EXPECT_EQ(fa.displacement, fb.displacement);
  EXPECT_EQ(testing_support::read_text(dir.file("a.csv")), testing_support::read_text(dir.file("b.csv")));
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
