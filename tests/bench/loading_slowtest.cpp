#include "bench/fem_runner.hpp"
#include "bench/loading.hpp"
#include "bench/loading_specs.hpp"
#include "bench/spec.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

using bench::Loading;
using loading_specs::expect_same_columns;
using loading_specs::spec_of;
using loading_specs::written_columns;

TEST(Loading, TheFemRunnerWritesTheTablesColumns) {
  testing_support::TempDir dir("loading_fem");
  for (Loading l : bench::kLoadings) {
    const std::string file = dir.file(std::string(bench::loading_name(l)) + ".h5");
    const bench::RunSummary s = bench::run_fem(bench::parse_spec(spec_of(l), "s.yaml"), file);
    ASSERT_TRUE(s.complete) << l << ": " << s.failure;
    EXPECT_EQ(s.loading, l);
    expect_same_columns(written_columns(file), bench::series_columns(l, bench::Solver::Fem), l);
  }
}
