// Tests for benchmarks/src/spec_parameters.cpp: every spec field declared
// once, the specs README's table generated from the declarations, the reader
// using them, every shipped spec still read.
#include "bench/spec.hpp"

#include "msd/core/types.hpp"
#include "parameter_checks.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace {

std::string error_of(const std::string& text, const std::string& source) {
  try {
    bench::parse_spec(text, source);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

const char* kSpec = R"(name: t
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {density: 1000, youngs_modulus: 5000}
msd: {constants: physical, dt: 1.0e-4}
fem: {degree: 1}
loading: {type: uniaxial, path: [[0, 0], [1, 0.1]]}
output: {interval: 0.05}
)";

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return s.replace(p, from.size(), to);
}

}  // namespace

TEST(SpecParameters, EachPathIsDeclaredOnceWithADocAndADefaultInItsRange) {
  EXPECT_GE(testing_support::expect_well_declared(bench::spec_parameters()), 70u);
  EXPECT_THROW(bench::spec_parameter("msd.dtt"), std::logic_error);
}

TEST(SpecParameters, DefaultsAreTheSpecStructs) {
  // A spec giving only the required fields reads every default from the declarations.
  const bench::Spec s = bench::parse_spec(kSpec, "s.yaml");
  const auto fallback = [](const char* path) { return *bench::spec_parameter(path).fallback; };
  EXPECT_EQ(s.msd->repulsion_floor, fallback("msd.repulsion_floor"));
  EXPECT_EQ(s.msd->stiffness_scale, fallback("msd.stiffness_scale"));
  EXPECT_EQ(s.fem.max_iterations, fallback("fem.max_iterations"));
  EXPECT_EQ(s.fem.contact_penalty, fallback("fem.contact_penalty"));
  EXPECT_EQ(s.mesh->max_cubes, fallback("mesh.max_cubes"));
  EXPECT_EQ(s.mesh->rule, bench::spec_parameter("mesh.rule").default_text);
  EXPECT_EQ(s.msd->integrator, bench::spec_parameter("msd.integrator").default_text);
  EXPECT_EQ(s.loading.gravity, bench::spec_parameter("loading.gravity").fallback3);
  EXPECT_TRUE(s.fem.vtu);
}

TEST(SpecParameters, TheReadmeFieldTableIsTheGeneratedOne) {
  testing_support::expect_docs_table("benchmarks/specs/README.md", "benchmarks/src/spec_parameters.cpp",
                                     bench::spec_parameters(), "spec_fields.md");
}

TEST(SpecParameters, AValueOutsideItsDeclaredRangeNamesFileLineFieldRangeAndUnit) {
  std::string e = error_of(replace(kSpec, "dt: 1.0e-4", "dt: -1.0e-4"), "specs/s.yaml");
  EXPECT_NE(e.find("specs/s.yaml:5:32: msd.dt: must lie in (0, inf) s, got -0.0001"), std::string::npos) << e;
  e = error_of(replace(kSpec, "degree: 1", "degree: 4"), "s.yaml");
  EXPECT_NE(e.find("s.yaml:6:15: fem.degree: must lie in [1, 3], got 4"), std::string::npos) << e;
  e = error_of(replace(kSpec, "interval: 0.05", "interval: 0, fields_interval: -1"), "s.yaml");
  EXPECT_NE(e.find("s.yaml:8:20: output.interval: must lie in (0, inf) s, got 0"), std::string::npos) << e;
  e = error_of(replace(kSpec, "dt: 1.0e-4", "dt: 1.0e-4, repulsion_floor: 1"), "s.yaml");
  EXPECT_NE(e.find("msd.repulsion_floor: must lie in (0, 1), got 1"), std::string::npos) << e;
  e = error_of(replace(kSpec, "dt: 1.0e-4", "dt: 1.0e-4, nonlinear_threshold: 1.5"), "s.yaml");
  EXPECT_NE(e.find("msd.nonlinear_threshold: must lie in (0, 1], got 1.5"), std::string::npos) << e;
  // The special words stay: off is 0.
  EXPECT_EQ(bench::parse_spec(replace(kSpec, "dt: 1.0e-4", "dt: 1.0e-4, nonlinear_threshold: off"), "s.yaml")
                .msd->nonlinear_threshold,
            0.0);
  // fem.vtu takes only the words true and false, as before the declarations.
  EXPECT_NE(error_of(replace(kSpec, "degree: 1", "vtu: yes"), "s.yaml").find("fem.vtu: expected true or false"),
            std::string::npos);
  EXPECT_FALSE(bench::parse_spec(replace(kSpec, "degree: 1", "vtu: false"), "s.yaml").fem.vtu);
}

TEST(SpecParameters, EveryShippedSpecStillParses) {
  int specs = 0;
  for (const std::string& dir : {std::string(TISSUEBENCH_SPECS_DIR), std::string(TISSUEBENCH_SOURCE_DIR) + "/tests/report"})
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
      if (e.path().extension() != ".yaml") continue;
      if (YAML::LoadFile(e.path().string())["tier"]) continue;  // a suite (tests/report/tiny.yaml), not a spec
      EXPECT_NO_THROW(bench::load_spec(e.path().string())) << e.path();
      ++specs;
    }
  EXPECT_GE(specs, 23);
}
