#include "bench/loading.hpp"

#include "bench/loading_specs.hpp"
#include "bench/msd_runner.hpp"
#include "bench/spec.hpp"
#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <regex>

namespace {

using bench::Loading;
using loading_specs::expect_same_columns;
using loading_specs::spec_of;
using loading_specs::written_columns;

std::string error_of(const std::string& text) {
  try {
    bench::parse_spec(text, "s.yaml");
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Loading, EveryNameRoundTripsThroughTheParser) {
  for (Loading l : bench::kLoadings) {
    EXPECT_EQ(bench::find_loading(bench::loading_name(l)), l);
    EXPECT_EQ(bench::parse_spec(spec_of(l), "s.yaml").loading.type, l) << l;
    EXPECT_EQ(bench::loading_of_test_label(bench::test_label(l, "frictionless")), l);
  }
  EXPECT_FALSE(bench::find_loading("torsion"));
  EXPECT_FALSE(bench::loading_of_test_label("torsion"));
  EXPECT_EQ(bench::test_label(Loading::Uniaxial, "bonded"), "uniaxial (bonded platens)");
  EXPECT_EQ(bench::test_label(Loading::SimpleShear, "bonded"), "simple_shear");
}

TEST(Loading, AnUnknownNameIsAnErrorAtItsPlaceListingTheKnownOnes) {
  std::string text = spec_of(Loading::Uniaxial);
  text.replace(text.find("type: uniaxial"), 14, "type: torsion");
  const std::string e = error_of(text);
  EXPECT_TRUE(std::regex_search(e, std::regex("^s\\.yaml:[0-9]+:[0-9]+: loading\\.type: 'torsion' is not one of: ")))
      << e;
  EXPECT_NE(e.find(bench::loading_names()), std::string::npos) << e;
  EXPECT_EQ(bench::loading_names(), "uniaxial, simple_shear, cooks_membrane, vibration, static, indentation");
}

TEST(Loading, TheTableNamesColumnsItsSolversWrite) {
  for (Loading l : bench::kLoadings) {
    const bench::LoadingInfo& info = bench::loading_info(l);
    for (bench::Solver solver : {bench::Solver::Msd, bench::Solver::Fem}) {
      const std::vector<bench::SeriesColumn>& columns = bench::series_columns(l, solver);
      if (columns.empty()) continue;  // the solver does not run the loading
      EXPECT_EQ(columns.front().name, "time") << l;
      for (const char* name : {info.load_series, info.strain_column, info.stress_column})
        if (*name) {
          EXPECT_GE(bench::column_index(columns, name), 0) << l << ": " << name;
        }
      EXPECT_GE(bench::column_index(columns, "volume_ratio"), 0) << l;
    }
  }
  EXPECT_TRUE(bench::series_columns(Loading::CooksMembrane, bench::Solver::Msd).empty());
  EXPECT_FALSE(bench::series_columns(Loading::CooksMembrane, bench::Solver::Fem).empty());
}

TEST(Loading, ARowIsBuiltByNameInTheColumnsOrder) {
  const std::vector<bench::SeriesColumn> columns{{"time", "s"}, {"strain", "1"}, {"nominal_stress", "Pa"}};
  EXPECT_EQ(bench::series_row(columns, {{"nominal_stress", 3.0}, {"time", 1.0}, {"strain", 2.0}}),
            (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_THROW(bench::series_row(columns, {{"time", 1.0}, {"strain", 2.0}}), msd::Error);
  EXPECT_THROW(bench::series_row(columns, {{"time", 1.0}, {"strain", 2.0}, {"stress", 3.0}}), msd::Error);
  EXPECT_THROW(bench::series_row(columns, {{"time", 1.0}, {"time", 2.0}, {"strain", 3.0}}), msd::Error);
  EXPECT_EQ(bench::column_index(columns, "strain"), 1);
  EXPECT_EQ(bench::column_index(columns, "depth"), -1);
  EXPECT_EQ(bench::column_index(columns, ""), -1);
}

TEST(Loading, TheMsdRunnerWritesTheTablesColumns) {
  testing_support::TempDir dir("loading_msd");
  for (Loading l : bench::kLoadings) {
    if (bench::series_columns(l, bench::Solver::Msd).empty()) continue;
    const std::string file = dir.file(std::string(bench::loading_name(l)) + ".h5");
    const bench::RunSummary s = bench::run_msd(bench::parse_spec(spec_of(l), "s.yaml"), file);
    ASSERT_TRUE(s.complete) << l << ": " << s.failure;
    EXPECT_EQ(s.loading, l);
    expect_same_columns(written_columns(file), bench::series_columns(l, bench::Solver::Msd), l);
  }
}
