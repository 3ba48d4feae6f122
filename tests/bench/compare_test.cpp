// bench::compare_results on hand-made results files whose errors are known:
// the load curve over the whole path and the working range, the volume ratio,
// the displacement field, the ring-down frequency and damping, the costs, and
// the refusals (wrong solver, incomplete run, different tests, specs or
// materials, non-finite samples).
#include "bench/compare.hpp"

#include "bench/shared_io.hpp"
#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>

namespace {

struct FileSpec {
  std::string solver = "msd";
  std::string test = "uniaxial (bonded platens)";
  std::string spec_name = "synthetic";
  std::vector<std::string> columns;
  std::vector<double> times;
  /// value of column c at time t
  std::function<double(const std::string&, double)> value;
  double wall_seconds = 1.0;
  double cpu_seconds = -1.0;  ///< recorded when >= 0
  std::map<std::string, double> metrics;
  bool finish = true;
  std::string spec_body;  ///< YAML after the name line of /meta/spec
  std::vector<std::pair<std::string, double>> material;
};

void write(const std::string& path, const FileSpec& s) {
  bench::RunMeta meta;
  meta.solver = s.solver;
  meta.spec_text = "name: " + s.spec_name + "\n" + s.spec_body;
  meta.material = s.material;
  meta.spec_path = s.spec_name + ".yaml";
  meta.spec_name = s.spec_name;
  meta.text = {{"test", s.test}};
  std::vector<bench::SeriesColumn> cols{{"time", "s"}};
  for (const auto& c : s.columns) cols.push_back({c, "-"});
  bench::ResultsWriter w(path, meta, cols);
  for (double t : s.times) {
    std::vector<double> row{t};
    for (const auto& c : s.columns) row.push_back(s.value(c, t));
    w.append(row);
  }
  w.set_timing(s.wall_seconds, static_cast<long>(s.times.size()), 1e-3, 1);
  if (s.cpu_seconds >= 0) w.set_timing_detail("cpu_seconds", s.cpu_seconds);
  for (const auto& [k, v] : s.metrics) w.set_metric(k, v);
  if (s.finish) w.finish();
}

std::vector<double> times(int n, double end) {
  std::vector<double> t;
  for (int i = 0; i <= n; ++i) t.push_back(end * i / n);
  return t;
}

// The thesis-like path: strain -0.5 ... +1.0 over one second.
double strain_at(double t) { return -0.5 + 1.5 * t; }

FileSpec uniaxial_fem() {
  FileSpec f;
  f.solver = "fem";
  f.columns = {"strain", "nominal_stress", "volume_ratio"};
  f.times = times(100, 1.0);
  f.value = [](const std::string& c, double t) {
    if (c == "strain") return strain_at(t);
    if (c == "nominal_stress") return 1000.0 * strain_at(t);
    return 1.0;
  };
  f.wall_seconds = 8.0;
  return f;
}

}  // namespace

TEST(Compare, LoadSeriesFollowTheLoading) {
  EXPECT_EQ(bench::load_series_name(bench::Loading::Uniaxial), "nominal_stress");
  EXPECT_EQ(bench::load_series_name(bench::Loading::SimpleShear), "shear_stress");
  EXPECT_EQ(bench::load_series_name(bench::Loading::Vibration), "tip_displacement");
  EXPECT_EQ(bench::load_series_name(bench::Loading::Indentation), "indentation_force");
  EXPECT_EQ(bench::load_series_name(bench::Loading::Static), "tip_displacement_z");
  EXPECT_EQ(bench::load_series_name(bench::Loading::CooksMembrane), "");
}

TEST(Compare, UniformRelativeErrorVolumeErrorAndCostsOnAFinerMsdSampling) {
  testing_support::TempDir dir("compare");
  write(dir.file("fem.h5"), uniaxial_fem());
  FileSpec m;
  m.columns = {"strain", "nominal_stress", "volume_ratio"};
  m.times = times(200, 1.0);  // twice the FEM's rate: the MSD curve is interpolated
  m.value = [](const std::string& c, double t) {
    if (c == "strain") return strain_at(t);
    if (c == "nominal_stress") return 1100.0 * strain_at(t);  // 10 % everywhere
    return 1.0 - 0.05 * t;                                    // volume error 0.05 at the end
  };
  m.wall_seconds = 2.0;
  write(dir.file("msd.h5"), m);

  const bench::Comparison c = bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5"));
  EXPECT_EQ(c.spec, "synthetic");
  EXPECT_EQ(c.loading, bench::Loading::Uniaxial);
  EXPECT_EQ(c.load_series, "nominal_stress");
  EXPECT_EQ(c.units, "Pa");
  EXPECT_EQ(c.points, 101);
  EXPECT_NEAR(c.load_rel_rms, 0.10, 1e-12);
  EXPECT_NEAR(c.load_rel_rms_working, 0.10, 1e-12);
  EXPECT_NEAR(c.load_max_abs_error, 100.0, 1e-9);  // 10 % of 1000 Pa at strain 1.0
  EXPECT_NEAR(c.volume_ratio_max_error, 0.05, 1e-12);
  EXPECT_NEAR(c.msd_cost, 2.0, 1e-12);
  EXPECT_NEAR(c.fem_cost, 8.0, 1e-12);
  EXPECT_NEAR(c.cost_ratio, 0.25, 1e-12);  // no CPU times recorded: the wall-time ratio
  EXPECT_TRUE(std::isnan(c.msd_cpu_cost));
  // No field data, no vibration: those metrics stay undefined, not zero.
  EXPECT_TRUE(std::isnan(c.displacement_rel_rms));
  EXPECT_TRUE(std::isnan(c.frequency_rel_error));
  // The table prints the figures.
  const std::string table = bench::format_comparison(c);
  EXPECT_NE(table.find("relative RMS error"), std::string::npos) << table;
  EXPECT_NE(table.find("10 %"), std::string::npos) << table;
}

TEST(Compare, CostRatioIsInCpuTimeWhenBothRunsRecordIt) {
  // The MSD run shared its core with another job: wall time doubled, CPU time did not.
  testing_support::TempDir dir("compare");
  FileSpec f = uniaxial_fem();
  f.cpu_seconds = 7.5;
  write(dir.file("fem.h5"), f);
  FileSpec m = uniaxial_fem();
  m.solver = "msd";
  m.wall_seconds = 4.0;
  m.cpu_seconds = 1.5;
  write(dir.file("msd.h5"), m);
  const bench::Comparison c = bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5"));
  EXPECT_NEAR(c.msd_cost, 4.0, 1e-12);
  EXPECT_NEAR(c.msd_cpu_cost, 1.5, 1e-12);
  EXPECT_NEAR(c.fem_cpu_cost, 7.5, 1e-12);
  EXPECT_NEAR(c.cost_ratio, 0.2, 1e-12);
  EXPECT_NE(bench::format_comparison(c).find("in CPU time"), std::string::npos);
}

TEST(Compare, WorkingRangeKeepsOnlyStrainsWithinPointFour) {
  testing_support::TempDir dir("compare");
  const FileSpec f = uniaxial_fem();
  write(dir.file("fem.h5"), f);
  // Exact inside |strain| <= 0.4 (classified at the FEM's own samples), 500 Pa off outside.
  auto outside = [](double t) {
    const double s = strain_at(std::round(t * 100.0) / 100.0);
    return std::abs(s) > 0.4 + 1e-12;
  };
  FileSpec m;
  m.columns = {"strain", "nominal_stress", "volume_ratio"};
  m.times = times(100, 1.0);
  m.value = [&](const std::string& c, double t) {
    if (c == "strain") return strain_at(t);
    if (c == "nominal_stress") return 1000.0 * strain_at(t) + (outside(t) ? 500.0 : 0.0);
    return 1.0;
  };
  write(dir.file("msd.h5"), m);
  double sum_d = 0, sum_f = 0;
  int n_out = 0;
  for (double t : f.times) {
    const double y = 1000.0 * strain_at(t);
    sum_f += y * y;
    if (outside(t)) {
      sum_d += 500.0 * 500.0;
      ++n_out;
    }
  }
  ASSERT_GT(n_out, 10);
  const bench::Comparison c = bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5"));
  EXPECT_NEAR(c.load_rel_rms_working, 0.0, 1e-12);
  EXPECT_NEAR(c.load_rel_rms, std::sqrt(sum_d / sum_f), 1e-12);
  EXPECT_NEAR(c.volume_ratio_max_error, 0.0, 1e-15);
}

TEST(Compare, ShearUsesShearStrainAndIndentationHasNoWorkingRange) {
  testing_support::TempDir dir("compare");
  for (const std::string loading : {"simple_shear", "indentation"}) {
    const bool shear = loading == "simple_shear";
    const std::string y = shear ? "shear_stress" : "indentation_force";
    const std::string x = shear ? "shear_strain" : "depth";
    FileSpec f;
    f.solver = "fem";
    f.test = loading;
    f.columns = {x, y};
    f.times = times(50, 1.0);
    f.value = [&](const std::string& c, double t) { return c == x ? t : 2.0 * t + 0.5; };
    FileSpec m = f;
    m.solver = "msd";
    m.value = [&](const std::string& c, double t) { return c == x ? t : 0.8 * (2.0 * t + 0.5); };
    write(dir.file(loading + "_fem.h5"), f);
    write(dir.file(loading + "_msd.h5"), m);
    const bench::Comparison c =
        bench::compare_results(dir.file(loading + "_msd.h5"), dir.file(loading + "_fem.h5"));
    EXPECT_EQ(c.load_series, y);
    EXPECT_NEAR(c.load_rel_rms, 0.2, 1e-12) << loading;
    if (shear) {
      EXPECT_EQ(c.units, "Pa");
      EXPECT_NEAR(c.load_rel_rms_working, 0.2, 1e-12);
    } else {
      EXPECT_EQ(c.units, "N");
      EXPECT_TRUE(std::isnan(c.load_rel_rms_working)) << "indentation has no strain working range";
    }
    // No volume series in either file: the volume metric stays undefined.
    EXPECT_TRUE(std::isnan(c.volume_ratio_max_error));
  }
}

TEST(Compare, StaticLoadingJudgesTheTipComponentTheFemMovesMost) {
  testing_support::TempDir dir("compare");
  FileSpec f;
  f.solver = "fem";
  f.test = "static";
  f.columns = {"load_factor", "tip_displacement_x", "tip_displacement_y", "tip_displacement_z"};
  f.times = times(10, 1.0);
  f.value = [](const std::string& c, double t) {
    if (c == "load_factor") return t;
    if (c == "tip_displacement_y") return -0.03 * t;  // the largest
    return 0.001 * t;
  };
  FileSpec m = f;
  m.solver = "msd";
  m.value = [](const std::string& c, double t) {
    if (c == "load_factor") return t;
    if (c == "tip_displacement_y") return -0.033 * t;
    return 0.5 * t;  // wildly off in x and z, which are not judged
  };
  write(dir.file("fem.h5"), f);
  write(dir.file("msd.h5"), m);
  const bench::Comparison c = bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5"));
  EXPECT_EQ(c.load_series, "tip_displacement_y");
  EXPECT_EQ(c.units, "m");
  EXPECT_NEAR(c.load_rel_rms, 0.1, 1e-12);
}

TEST(Compare, VibrationFrequencyAndDampingErrorsComeFromTheMetrics) {
  testing_support::TempDir dir("compare");
  FileSpec f;
  f.solver = "fem";
  f.test = "vibration";
  f.columns = {"tip_displacement"};
  f.times = times(100, 1.0);
  f.value = [](const std::string&, double t) { return 0.01 * std::exp(-t) * std::cos(20.0 * t); };
  f.metrics = {{"first_frequency", 4.0}, {"damping_ratio", 0.05}};
  FileSpec m = f;
  m.solver = "msd";
  m.metrics = {{"first_frequency", 4.4}, {"damping_ratio", 0.02}};
  write(dir.file("fem.h5"), f);
  write(dir.file("msd.h5"), m);
  const bench::Comparison c = bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5"));
  EXPECT_NEAR(c.load_rel_rms, 0.0, 1e-15);
  EXPECT_NEAR(c.frequency_rel_error, 0.1, 1e-12);
  EXPECT_NEAR(c.damping_ratio_abs_error, -0.03, 1e-12);
}

TEST(Compare, DisplacementFieldRelativeToTheLargestFemDisplacementSkippingProbesOutside) {
  testing_support::TempDir dir("compare");
  const std::vector<std::array<double, 3>> points{{0, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 0.01}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // FEM: two frames; the last probe lies outside the FEM mesh (NaN).
  const std::vector<std::vector<std::array<double, 3>>> uf{
      {{0, 0, 0.001}, {0, 0, 0.002}, {0, 0, 0.001}, {nan, nan, nan}},
      {{0, 0, 0.002}, {0, 0, 0.004}, {0, 0, 0.002}, {nan, nan, nan}}};
  // MSD: off by 0.0003 m in x at every compared node of the second frame only.
  std::vector<std::vector<std::array<double, 3>>> um = uf;
  for (auto& u : um[0]) u = {u[0] == u[0] ? u[0] : 0.0, u[1] == u[1] ? u[1] : 0.0, u[2] == u[2] ? u[2] : 0.0};
  for (auto& u : um[1]) u = {0.0003, 0.0, u[2] == u[2] ? u[2] : 0.0};
  // An MSD frame at a time the FEM did not record is ignored.
  const std::vector<double> tm{0.5, 0.75, 1.0}, tf{0.5, 1.0};
  // Both files: the same three rows of a uni-axial run, then the field set.
  auto start = [&](const std::string& solver, const std::vector<double>& times) {
    bench::RunMeta meta;
    meta.solver = solver;
    meta.spec_name = "synthetic";
    meta.text = {{"test", "uniaxial (bonded platens)"}};
    auto w = std::make_unique<bench::ResultsWriter>(dir.file(solver + ".h5"), meta,
                                                    std::vector<bench::SeriesColumn>{{"time", "s"}, {"strain", "-"}, {"nominal_stress", "Pa"}});
    for (double t : times) w->append({t, 0.1 * t, 100.0 * t});
    w->set_timing(1.0, static_cast<long>(times.size()), 1e-3, 1);
    return w;
  };
  {
    auto w = start("fem", tf);
    w->add_point_set("probes", points);
    for (size_t k = 0; k < tf.size(); ++k) w->append_frame("probes", tf[k], uf[k]);
    w->finish();
  }
  {
    auto w = start("msd", tm);
    w->add_point_set("nodes", points, {{0, 1, 2, 3}});
    w->append_frame("nodes", 0.5, um[0]);
    w->append_frame("nodes", 0.75, {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}});
    w->append_frame("nodes", 1.0, um[1]);
    w->finish();
  }
  const bench::Comparison c = bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5"));
  EXPECT_EQ(c.frames_compared, 2);
  EXPECT_EQ(c.nodes_compared, 3);
  EXPECT_EQ(c.nodes_outside, 1);
  // 6 node-frames, 3 of them off by 0.0003 m; the largest FEM displacement is 0.004 m.
  EXPECT_NEAR(c.displacement_rel_rms, std::sqrt(3 * 0.0003 * 0.0003 / 6) / 0.004, 1e-12);
  EXPECT_NEAR(c.displacement_rel_max, 0.0003 / 0.004, 1e-12);
  // Skipping the field (an MSD run on another mesh) leaves it undefined.
  EXPECT_TRUE(std::isnan(bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5"), false).displacement_rel_rms));
}

TEST(Compare, RefusesSwappedSolversIncompleteRunsAndDifferentTests) {
  testing_support::TempDir dir("compare");
  write(dir.file("fem.h5"), uniaxial_fem());
  FileSpec m = uniaxial_fem();
  m.solver = "msd";
  write(dir.file("msd.h5"), m);
  auto message = [&](const std::string& a, const std::string& b) -> std::string {
    try {
      bench::compare_results(dir.file(a), dir.file(b));
    } catch (const msd::Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message("fem.h5", "msd.h5").find("expected a results file of the msd solver"), std::string::npos);
  EXPECT_NE(message("missing.h5", "fem.h5").find("missing.h5"), std::string::npos);

  FileSpec running = m;
  running.finish = false;
  write(dir.file("running.h5"), running);
  EXPECT_NE(message("running.h5", "fem.h5").find("not complete"), std::string::npos) << message("running.h5", "fem.h5");

  FileSpec shear = m;
  shear.test = "simple_shear";
  write(dir.file("shear.h5"), shear);
  EXPECT_NE(message("shear.h5", "fem.h5").find("not the same test"), std::string::npos);

  FileSpec other = m;
  other.spec_name = "another";
  write(dir.file("other.h5"), other);
  EXPECT_NE(message("other.h5", "fem.h5").find("different specs"), std::string::npos);
}

TEST(Compare, JsonHoldsEveryDocumentedKeyWithNullForUndefined) {
  testing_support::TempDir dir("compare");
  bench::Comparison c;
  c.spec = "s";
  c.loading = bench::Loading::Uniaxial;
  c.load_rel_rms = 0.25;
  write_comparison_json(c, dir.file("c.json"));
  std::ifstream in(dir.file("c.json"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string j = text.str();
  for (const char* key :
       {"spec", "loading", "load_series", "units", "points", "load_rms_fem", "load_rel_rms", "load_rel_rms_working",
        "load_max_abs_error", "volume_ratio_max_error", "displacement_rel_rms", "displacement_rel_max",
        "nodes_compared", "nodes_outside", "frames_compared", "frequency_msd", "frequency_fem", "frequency_rel_error",
        "damping_ratio_msd", "damping_ratio_fem", "damping_ratio_abs_error", "msd_cost", "fem_cost", "msd_cpu_cost",
        "fem_cpu_cost", "cost_ratio"})
    EXPECT_NE(j.find("\"" + std::string(key) + "\":"), std::string::npos) << key;
  EXPECT_NE(j.find("\"load_rel_rms\": 0.25"), std::string::npos) << j;
  EXPECT_NE(j.find("\"load_rel_rms_working\": null"), std::string::npos) << j;
}

namespace {

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  if (at == std::string::npos) throw std::runtime_error("replaced: no '" + from + "'");
  return s.replace(at, from.size(), to);
}

std::string refusal(const std::string& msd, const std::string& fem) {
  try {
    bench::compare_results(msd, fem);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Compare, RefusesFilesOfDifferentSpecSectionsOrMaterials) {
  testing_support::TempDir dir("compare");
  FileSpec f = uniaxial_fem();
  f.spec_body = "geometry: {shape: box, size: [0.1, 0.1, 0.1]}\nmaterial: {library: non_muscular_tissue}\n"
                "loading: {type: uniaxial, path: thesis_cycle}\nfem: {degree: 2}\n";
  f.material = {{"density", 1000.0}, {"youngs_modulus", 5000.0}, {"shear_modulus", 1700.0}};
  write(dir.file("fem.h5"), f);
  FileSpec m = f;
  m.solver = "msd";
  // Another style, other msd/fem sections and extra MSD-only constants: the same test.
  m.spec_body = "geometry:\n  shape: box\n  size: [0.10, 0.1, 1.0e-1]\nmaterial:\n  library: non_muscular_tissue\n"
                "loading: {path: thesis_cycle, type: uniaxial}\nmsd: {constants: raw}\n";
  m.material = {{"density", 1000.0}, {"youngs_modulus", 5000.0}, {"k_s", 10.75}};
  write(dir.file("msd.h5"), m);
  EXPECT_EQ(refusal(dir.file("msd.h5"), dir.file("fem.h5")), "");

  FileSpec other = m;
  other.spec_body = replaced(m.spec_body, "non_muscular_tissue", "passive_muscle");
  write(dir.file("other_material.h5"), other);
  std::string e = refusal(dir.file("other_material.h5"), dir.file("fem.h5"));
  EXPECT_NE(e.find("different specs"), std::string::npos) << e;
  EXPECT_NE(e.find("'material'"), std::string::npos) << e;
  EXPECT_NE(e.find(dir.file("other_material.h5")), std::string::npos) << e;

  other = m;
  other.spec_body = replaced(m.spec_body, "thesis_cycle", "[[0, 0], [1, 0.4]]");
  write(dir.file("other_loading.h5"), other);
  e = refusal(dir.file("other_loading.h5"), dir.file("fem.h5"));
  EXPECT_NE(e.find("'loading'"), std::string::npos) << e;

  other = m;
  other.spec_body = replaced(m.spec_body, "1.0e-1]", "0.2]");
  write(dir.file("other_geometry.h5"), other);
  EXPECT_NE(refusal(dir.file("other_geometry.h5"), dir.file("fem.h5")).find("'geometry'"), std::string::npos);

  other = m;
  other.material = {{"density", 1000.0}, {"youngs_modulus", 5200.0}};
  write(dir.file("other_constants.h5"), other);
  e = refusal(dir.file("other_constants.h5"), dir.file("fem.h5"));
  EXPECT_NE(e.find("different materials: /meta/material/youngs_modulus 5200 against 5000"), std::string::npos) << e;
}

TEST(Compare, RefusesNonFiniteSamplesInsteadOfDroppingThem) {
  // A NaN dropped from the sums would lower the error; a complete run holds none.
  testing_support::TempDir dir("compare");
  write(dir.file("fem.h5"), uniaxial_fem());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  FileSpec m = uniaxial_fem();
  m.solver = "msd";
  write(dir.file("msd.h5"), m);
  EXPECT_EQ(refusal(dir.file("msd.h5"), dir.file("fem.h5")), "");
  for (const std::string column : {"nominal_stress", "volume_ratio"}) {
    FileSpec bad = m;
    bad.value = [&, column](const std::string& c, double t) {
      return c == column && std::abs(t - 0.5) < 1e-9 ? nan : uniaxial_fem().value(c, t);
    };
    write(dir.file("bad.h5"), bad);
    const std::string e = refusal(dir.file("bad.h5"), dir.file("fem.h5"));
    EXPECT_NE(e.find(dir.file("bad.h5") + ": /series/" + column + " row 51 (t = 0.5 s) is not finite"), std::string::npos)
        << e;
    FileSpec bad_fem = uniaxial_fem();
    bad_fem.value = bad.value;
    write(dir.file("bad_fem.h5"), bad_fem);
    EXPECT_NE(refusal(dir.file("msd.h5"), dir.file("bad_fem.h5")).find("/series/" + column), std::string::npos);
  }
  FileSpec inf = m;
  inf.value = [](const std::string& c, double t) {
    return c == "strain" && t > 0.99 ? std::numeric_limits<double>::infinity() : uniaxial_fem().value(c, t);
  };
  write(dir.file("inf_fem.h5"), [&] { FileSpec f = inf; f.solver = "fem"; return f; }());
  EXPECT_NE(refusal(dir.file("msd.h5"), dir.file("inf_fem.h5")).find("/series/strain row 101"), std::string::npos);
}

TEST(Compare, RefusesAProbeNonFiniteInSomeComponentsOnlyOrANonFiniteMsdNode) {
  testing_support::TempDir dir("compare");
  const std::vector<std::array<double, 3>> points{{0, 0, 0}, {0.01, 0, 0}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto make = [&](const std::string& file, const std::string& solver, const std::string& set,
                  const std::array<double, 3>& second) {
    bench::RunMeta meta;
    meta.solver = solver;
    meta.spec_name = "synthetic";
    meta.text = {{"test", "uniaxial (bonded platens)"}};
    bench::ResultsWriter w(dir.file(file), meta, {{"time", "s"}, {"strain", "-"}, {"nominal_stress", "Pa"}});
    for (double t : {0.5, 1.0}) w.append({t, 0.1 * t, 100.0 * t});
    w.set_timing(1.0, 2, 1e-3, 1);
    w.add_point_set(set, points);
    for (double t : {0.5, 1.0}) w.append_frame(set, t, {{0, 0, 0.001}, second});
    w.finish();
  };
  make("fem.h5", "fem", "probes", {nan, nan, nan});  // outside the mesh: skipped
  make("msd.h5", "msd", "nodes", {0, 0, 0.001});
  EXPECT_EQ(bench::compare_results(dir.file("msd.h5"), dir.file("fem.h5")).nodes_outside, 1);
  make("half.h5", "fem", "probes", {0.0, nan, 0.001});
  EXPECT_NE(refusal(dir.file("msd.h5"), dir.file("half.h5")).find("in some components only"), std::string::npos);
  make("fem_ok.h5", "fem", "probes", {0, 0, 0.001});
  make("msd_nan.h5", "msd", "nodes", {0, nan, 0.001});
  const std::string e = refusal(dir.file("msd_nan.h5"), dir.file("fem_ok.h5"));
  EXPECT_NE(e.find(dir.file("msd_nan.h5") + ": /fields/nodes_displacement frame 1, node 2 is not finite"),
            std::string::npos)
      << e;
}
