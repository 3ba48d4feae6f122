// One leg scene run whole from its shipped file, for the scene tests
// (scenes_slowtest.cpp: the thesis' tuned scenes; physiological_slowtest.cpp:
// the physiological leg's): its summaries, its first run's leg.h5, and the
// series' values and extremes over a time window.
#pragma once

#include "leg/run.hpp"
#include "leg/scene.hpp"
#include "tbio/results_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace testing_support {

struct SceneRun {
  leg::LegScene scene;
  std::vector<leg::LegRunSummary> runs;
  tbio::Results results;  ///< the first run's leg.h5
  const leg::LegRunSummary& summary() const { return runs.front(); }
  double value(const std::string& key) const {
    const auto it = summary().values.find(key);
    if (it == summary().values.end()) throw std::runtime_error("no summary value " + key);
    return it->second;
  }
  const std::vector<double>& series(const std::string& name) const { return results.series.at(name); }
  /// The series' value at time t (the frame closest to it).
  double at(const std::string& name, double t) const {
    const auto& time = series("time");
    const size_t k = static_cast<size_t>(std::min_element(time.begin(), time.end(),
                                                          [&](double a, double b) {
                                                            return std::abs(a - t) < std::abs(b - t);
                                                          }) -
                                         time.begin());
    return series(name)[k];
  }
  /// Extremes of a series over [t0, t1].
  std::pair<double, double> range(const std::string& name, double t0, double t1) const {
    double lo = 1e300, hi = -1e300;
    const auto& time = series("time");
    for (size_t k = 0; k < time.size(); ++k)
      if (time[k] >= t0 - 1e-9 && time[k] <= t1 + 1e-9) {
        lo = std::min(lo, series(name)[k]);
        hi = std::max(hi, series(name)[k]);
      }
    return {lo, hi};
  }
};

/// Runs msd/data/FOLDER/NAME.yaml whole into build/tests' OUT/NAME (no OBJ
/// frames: the fast suite checks those), expects every run complete, and
/// prints the first run's summary. `threads` > 0 replaces the file's thread
/// count (the results are bit-identical for every count).
inline SceneRun run_scene(const std::string& folder, const std::string& name, const std::string& out,
                          int threads = 0) {
  namespace fs = std::filesystem;
  SceneRun r;
  r.scene = leg::read_leg_scene(std::string(TISSUEBENCH_DATA_DIR) + "/" + folder + "/" + name + ".yaml");
  r.scene.obj_every = 0;
  if (threads > 0) r.scene.model.threads = threads;
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / out / name).string();
  r.runs = leg::run_leg_scene(r.scene, dir);
  for (const auto& s : r.runs) EXPECT_EQ(s.status, "complete") << s.failure;
  r.results = tbio::read_results((fs::path(r.runs.front().dir) / "leg.h5").string());
  EXPECT_EQ(r.results.status(), "complete");
  std::printf("%s", leg::format_leg_summary(r.summary()).c_str());
  return r;
}

}  // namespace testing_support
