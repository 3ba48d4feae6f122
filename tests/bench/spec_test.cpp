#include "bench/spec.hpp"

#include "msd/core/types.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace {

const char* kGood = R"(name: t
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {density: 1000, youngs_modulus: 5000}
msd: {constants: physical, dt: 1.0e-4}
loading: {type: uniaxial, path: [[0, 0], [1, 0.1]]}
)";

std::string error_of(const std::string& text) {
  try {
    bench::parse_spec(text, "s.yaml");
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return s.replace(p, from.size(), to);
}

}  // namespace

TEST(Spec, ParsesAMinimalSpecWithDefaults) {
  const bench::Spec s = bench::parse_spec(kGood, "s.yaml");
  EXPECT_EQ(s.name, "t");
  EXPECT_EQ(s.geometry.shape, "box");
  EXPECT_DOUBLE_EQ(s.mesh->spacing, 0.01);
  EXPECT_EQ(s.mesh->rule, "centre");
  EXPECT_EQ(*s.material.youngs_modulus, 5000);
  EXPECT_EQ(s.msd->integrator, "symplectic_euler");
  EXPECT_EQ(s.msd->terms.size(), 4u);
  EXPECT_EQ(s.msd->nonlinear_threshold, 0.0);
  EXPECT_EQ(s.loading.platens, "bonded");
  EXPECT_DOUBLE_EQ(s.output.interval, 0.01);
  EXPECT_EQ(s.text, kGood);
}

TEST(Spec, ThesisCycleAndThreshold) {
  std::string t = replace(kGood, "path: [[0, 0], [1, 0.1]]", "path: thesis_cycle");
  t = replace(t, "dt: 1.0e-4", "dt: 1.0e-4, nonlinear_threshold: 0.7");
  const bench::Spec s = bench::parse_spec(t, "s.yaml");
  EXPECT_EQ(s.loading.path.size(), 5u);
  EXPECT_DOUBLE_EQ(s.loading.path.back().first, 12.0);
  EXPECT_DOUBLE_EQ(s.msd->nonlinear_threshold, 0.7);
}

TEST(Spec, UnknownFieldNamesFileLineAndPath) {
  const std::string e = error_of(replace(kGood, "spacing: 0.01", "spacing: 0.01, spasing: 2"));
  EXPECT_NE(e.find("s.yaml:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("mesh.spasing: unknown field"), std::string::npos) << e;
}

TEST(Spec, WrongTypesAndValuesAreNamed) {
  EXPECT_NE(error_of(replace(kGood, "density: 1000", "density: heavy")).find("material.density: expected a number"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "density: 1000", "density: -1")).find("s.yaml:4:21: material.density: must lie in (0, inf) kg/m^3, got -1"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "dt: 1.0e-4", "dt: 0")).find("msd.dt"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "type: uniaxial", "type: torsion")).find("loading.type"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "spacing: 0.01", "spacing: -0.01")).find("mesh.spacing"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "youngs_modulus: 5000", "youngs_modulus: 5000, poisson_ratio: 0.5"))
                .find("material.poisson_ratio"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "[1, 0.1]", "[1, -1.5]")).find("loading.path"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "[[0, 0], [1, 0.1]]", "[[0, 0], [0, 0.1]]")).find("increase"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "shape: box, size: [0.02, 0.02, 0.04]", "shape: sphere")).find("geometry.shape"),
            std::string::npos);
}

TEST(Spec, MissingFieldsAndInconsistentConstants) {
  // The mesh section is optional for other solvers but required by msd.
  EXPECT_NE(error_of(replace(kGood, "mesh: {spacing: 0.01}\n", "")).find("the msd solver needs a 'mesh' section"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "loading: {", "loadin: {")).find("loadin: unknown field"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, ", youngs_modulus: 5000", "")).find("youngs_modulus is required"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "constants: physical", "constants: physical, k_s: 3")).find("msd.k_s"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "constants: physical", "constants: raw")).find("msd.k_s: required"),
            std::string::npos);
}

TEST(Spec, YamlSyntaxErrorHasLine) {
  const std::string e = error_of("name: x\ngeometry: {shape: box\n");
  EXPECT_NE(e.find("s.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("YAML syntax error"), std::string::npos) << e;
  EXPECT_NE(error_of("").find("empty"), std::string::npos);
}

TEST(Spec, ObjPathIsResolvedAgainstTheSpecFolder) {
  const std::string t = replace(kGood, "shape: box, size: [0.02, 0.02, 0.04]", "shape: obj, file: leg.obj");
  EXPECT_EQ(bench::parse_spec(t, "/data/specs/s.yaml").geometry.file, "/data/specs/leg.obj");
}

TEST(Spec, ShippedSpecsAllParse) {
  // Every spec shipped in benchmarks/specs (the README lists them).
  int specs = 0;
  for (const auto& e : std::filesystem::directory_iterator(TISSUEBENCH_SPECS_DIR)) {
    if (e.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(bench::load_spec(e.path().string())) << e.path();
    ++specs;
  }
  EXPECT_GE(specs, 21);
  EXPECT_THROW(bench::load_spec("/nonexistent/spec.yaml"), msd::Error);
}

namespace {

const char* kIndentation = R"(name: ind
geometry: {shape: box, size: [0.04, 0.01, 0.02]}
mesh: {spacing: 0.005}
material: {density: 1000, youngs_modulus: 3000, poisson_ratio: 0.45}
msd: {constants: physical, dt: 2.0e-4}
fem: {degree: 1, contact_penalty: 50}
loading:
  type: indentation
  indenter: {shape: cylinder, radius: 0.01, axis: y, depth: 0.004}
  path: [[0, 0], [0.5, 1]]
output: {interval: 0.05}
)";

}  // namespace

TEST(Spec, IndentationFieldsAreReadAndCheckedByName) {
  const bench::Spec s = bench::parse_spec(kIndentation, "ind.yaml");
  EXPECT_EQ(s.loading.type, bench::Loading::Indentation);
  EXPECT_DOUBLE_EQ(s.loading.indenter_radius, 0.01);
  EXPECT_DOUBLE_EQ(s.loading.indenter_depth, 0.004);
  EXPECT_EQ(s.loading.indenter_axis, "y");
  EXPECT_EQ(s.loading.indenter_response, "stick");
  EXPECT_DOUBLE_EQ(s.fem.contact_penalty, 50.0);
  auto err = [](const std::string& text) {
    try {
      bench::parse_spec(text, "ind.yaml");
    } catch (const msd::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err(replace(kIndentation, "depth: 0.004", "depth: 0.02")).find("loading.indenter.depth: must be less than"),
            std::string::npos);
  EXPECT_NE(err(replace(kIndentation, "radius: 0.01,", "radius: -0.01,")).find("loading.indenter.radius"),
            std::string::npos);
  EXPECT_NE(err(replace(kIndentation, "axis: y", "axis: z")).find("loading.indenter.axis"), std::string::npos);
  EXPECT_NE(err(replace(kIndentation, "depth: 0.004}", "depth: 0.004, response: glue}")).find("loading.indenter.response"),
            std::string::npos);
  EXPECT_NE(err(replace(kIndentation, "[0.5, 1]", "[0.5, 1.5]")).find("loading.path: depth factors"), std::string::npos);
  EXPECT_NE(err(replace(kIndentation, "shape: box, size: [0.04, 0.01, 0.02]", "shape: cylinder, radius: 0.01, height: 0.02"))
                .find("indentation needs a box"),
            std::string::npos);
  EXPECT_NE(err(replace(kIndentation, "contact_penalty: 50", "contact_penalty: 0")).find("fem.contact_penalty"),
            std::string::npos);
}

TEST(Spec, MsdDampingTimeOverridesTheMaterialsForTheMsdOnly) {
  const std::string t = replace(kGood, "dt: 1.0e-4", "dt: 1.0e-4, damping_time: 0.01");
  const bench::Spec s = bench::parse_spec(t, "s.yaml");
  ASSERT_TRUE(s.msd->damping_time);
  EXPECT_DOUBLE_EQ(*s.msd->damping_time, 0.01);
  EXPECT_FALSE(s.material.damping_time);  // the FEM's Rayleigh constant is the material's, untouched
  EXPECT_FALSE(bench::parse_spec(kGood, "s.yaml").msd->damping_time);
  EXPECT_NE(error_of(replace(kGood, "dt: 1.0e-4", "dt: 1.0e-4, damping_time: -1")).find("msd.damping_time: must lie in [0, inf) s, got -1"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "constants: physical, dt: 1.0e-4", "constants: raw, k_s: 3, dt: 1.0e-4, damping_time: 0.01"))
                .find("msd.damping_time: only meaningful with 'constants: physical'"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "dt: 1.0e-4", "dt: 1.0e-4, calibration: c.yaml, damping_time: 0.01"))
                .find("given together with 'calibration'"),
            std::string::npos);
}

TEST(Spec, PreloadRampsSmoothlyHoldsAndReleases) {
  bench::LoadingSpec l;
  l.release = 2.0;
  l.duration = 1.5;
  const auto p = bench::preload_path(l);
  ASSERT_GE(p.size(), 5u);
  EXPECT_DOUBLE_EQ(p.front().first, 0.0);
  EXPECT_DOUBLE_EQ(p.front().second, 0.0);
  // The ramp: (1 - cos(pi t / T)) / 2 over T = release / 2 at its way-points, monotone.
  for (size_t k = 1; k < p.size(); ++k) {
    EXPECT_GT(p[k].first, p[k - 1].first) << k;
    if (p[k].first <= 1.0) {
      EXPECT_GE(p[k].second, p[k - 1].second) << k;
      EXPECT_NEAR(p[k].second, 0.5 * (1.0 - std::cos(M_PI * p[k].first / 1.0)), 1e-12) << k;
    }
  }
  // Slow start (a linear ramp over T would be at 1/16 after the first piece).
  EXPECT_LT(p[1].second, 0.01);
  // Held at 1 to the release, removed just after it, 0 to the end.
  auto factor_at = [&](double t) {
    for (size_t k = 1; k < p.size(); ++k)
      if (t <= p[k].first)
        return p[k - 1].second + (p[k].second - p[k - 1].second) * (t - p[k - 1].first) / (p[k].first - p[k - 1].first);
    return p.back().second;
  };
  EXPECT_DOUBLE_EQ(factor_at(1.0), 1.0);
  EXPECT_DOUBLE_EQ(factor_at(1.7), 1.0);
  EXPECT_DOUBLE_EQ(factor_at(2.0), 1.0);
  EXPECT_NEAR(factor_at(2.1), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.back().first, 3.5);
  EXPECT_DOUBLE_EQ(p.back().second, 0.0);
}

TEST(Spec, ATimeStepLeavingFewerThanTenStepsOverTheLoadingIsRefused) {
  // dt = 1000 s on a 1 s loading took one step and was marked complete.
  const std::string e = error_of(replace(kGood, "dt: 1.0e-4", "dt: 1000"));
  EXPECT_NE(e.find("s.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("msd.dt: dt = 1000 s leaves fewer than ten steps over the loading, which lasts 1 s: use at most 0.1 s"),
            std::string::npos) << e;
  EXPECT_EQ(error_of(replace(kGood, "dt: 1.0e-4", "dt: 0.1")), "");
  EXPECT_NE(error_of(replace(kGood, "dt: 1.0e-4", "dt: 0.11")).find("fewer than ten steps"), std::string::npos);
}

TEST(Spec, ARepeatedKeyIsRefusedInsteadOfReadingTheFirst) {
  // yaml-cpp keeps the first value: the invalid second one was never checked.
  const std::string e = error_of(replace(kGood, "dt: 1.0e-4}", "dt: 1.0e-4, dt: -1}"));
  EXPECT_NE(e.find("s.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("duplicate key 'dt' (first given at line 5)"), std::string::npos) << e;
}

TEST(Spec, AMemoryLimitIsAFieldOfTheMesh) {
  const bench::Spec s = bench::parse_spec(replace(kGood, "spacing: 0.01}", "spacing: 0.01, memory_limit_gb: 2.5}"), "s.yaml");
  EXPECT_DOUBLE_EQ(s.mesh->memory_limit_gb, 2.5);
  EXPECT_NE(error_of(replace(kGood, "spacing: 0.01}", "spacing: 0.01, memory_limit_gb: -1}")).find("mesh.memory_limit_gb"),
            std::string::npos);
}

TEST(Spec, EdgeClassesAreReadByNameAndABadClassOrLawIsRefusedNamingTheField) {
  const std::string with = replace(kGood, "dt: 1.0e-4}",
                                   "dt: 1.0e-4, edge_classes: {axis: {stiffness: 0.5, compression_exponent: 2}, "
                                   "face_diagonal: {tension_exponent: 0.5}}}");
  const bench::Spec s = bench::parse_spec(with, "s.yaml");
  const auto& laws = s.msd->edge_laws;
  EXPECT_DOUBLE_EQ(laws[0].stiffness, 0.5);
  EXPECT_DOUBLE_EQ(laws[0].tension_exponent, 1.0);  // the default
  EXPECT_DOUBLE_EQ(laws[0].compression_exponent, 2.0);
  EXPECT_DOUBLE_EQ(laws[1].stiffness, 1.0);
  EXPECT_DOUBLE_EQ(laws[1].tension_exponent, 0.5);
  EXPECT_TRUE(laws[2].linear());
  // An unknown class, an unknown field of a class, a negative exponent, a law without stiffness.
  EXPECT_NE(error_of(replace(with, "face_diagonal:", "body_diagonal:")).find("msd.edge_classes.body_diagonal: unknown field"),
            std::string::npos)
      << error_of(replace(with, "face_diagonal:", "body_diagonal:"));
  EXPECT_NE(error_of(replace(with, "stiffness: 0.5", "stifness: 0.5")).find("msd.edge_classes.axis.stifness: unknown field"),
            std::string::npos);
  EXPECT_NE(error_of(replace(with, "compression_exponent: 2", "compression_exponent: -2"))
                .find("msd.edge_classes.axis.compression_exponent: must lie in [0, inf)"),
            std::string::npos)
      << error_of(replace(with, "compression_exponent: 2", "compression_exponent: -2"));
  EXPECT_NE(error_of(replace(with, "stiffness: 0.5", "stiffness: 0")).find("msd.edge_classes.axis.stiffness"),
            std::string::npos);
  const std::string none = error_of(replace(with, "tension_exponent: 0.5", "tension_exponent: 0, compression_exponent: 0"));
  EXPECT_NE(none.find("no stiffness"), std::string::npos) << none;
  EXPECT_NE(none.find("s.yaml:"), std::string::npos) << none;
}

TEST(Spec, TheBulkTermIsReadWithItsFactorAndRefusedWhereItCannotWork) {
  const std::string with = replace(replace(kGood, "youngs_modulus: 5000}", "youngs_modulus: 5000, poisson_ratio: 0.49}"),
                                   "dt: 1.0e-4}", "dt: 1.0e-4, terms: [springs, dampers, bulk], bulk_factor: 0.8}");
  const bench::Spec s = bench::parse_spec(with, "s.yaml");
  EXPECT_DOUBLE_EQ(s.msd->bulk_factor, 0.8);
  EXPECT_EQ(s.msd->terms.back(), "bulk");
  const auto says = [](const std::string& text, const std::string& what) {
    const std::string e = error_of(text);
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  says(replace(with, "poisson_ratio: 0.49", "poisson_ratio: 0.2"), "s.yaml:4:11: material: poisson_ratio must be above 0.25 for the msd term bulk");
  says(replace(with, ", poisson_ratio: 0.49", ""), "poisson_ratio is required for the msd term bulk");
  says(replace(with, "bulk]", "bulk, neo_hookean]"), "msd.terms: bulk and neo_hookean are two volume terms");
  says(replace(with, "springs, dampers, bulk", "springs, dampers"), "msd.bulk_factor: only meaningful with the bulk term");
  says(replace(with, "bulk_factor: 0.8", "bulk_factor: 0"), "msd.bulk_factor");
  says(replace(with, "constants: physical", "constants: raw, k_s: 1"), "msd.bulk_factor: only meaningful with 'constants: physical'");
}

TEST(Spec, ZeroLengthSpringsAreAFlagOfTheLatticeWithTheBulkTermAndRefusedWhereTheyCannotWork) {
  const std::string with = replace(replace(kGood, "youngs_modulus: 5000}", "youngs_modulus: 5000, poisson_ratio: 0.2}"),
                                   "dt: 1.0e-4}", "dt: 1.0e-4, terms: [springs, dampers, bulk], zero_length_springs: true}");
  const bench::Spec s = bench::parse_spec(with, "s.yaml");
  EXPECT_TRUE(s.msd->zero_length_springs);  // and nu = 0.2 is allowed: the law's lambda > 0
  const auto says = [](const std::string& text, const std::string& what) {
    const std::string e = error_of(text);
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  // Springs with a rest length need nu above 1/4 for the bulk term.
  says(replace(with, "zero_length_springs: true", "zero_length_springs: false"), "poisson_ratio must be above 0.25");
  EXPECT_FALSE(bench::parse_spec(replace(replace(with, "zero_length_springs: true", "zero_length_springs: false"),
                                         "poisson_ratio: 0.2", "poisson_ratio: 0.3"),
                                 "s.yaml")
                   .msd->zero_length_springs);
  says(replace(with, "springs, dampers, bulk", "springs, dampers"), "msd.zero_length_springs: needs the springs and the bulk term");
  says(replace(with, "springs, dampers, bulk", "dampers, bulk"), "msd.zero_length_springs: needs the springs and the bulk term");
  says(replace(with, "zero_length_springs: true", "zero_length_springs: true, edge_classes: {axis: {stiffness: 0.5}}"),
       "msd.edge_classes: does not apply with zero_length_springs");
  says(replace(with, "zero_length_springs: true", "zero_length_springs: yes please"), "msd.zero_length_springs");
  says(replace(with, "zero_length_springs: true", "zero_length_springs: true, calibration: c.yaml"),
       "msd.calibration: does not apply with zero_length_springs");
  says(replace(with, "poisson_ratio: 0.2", "poisson_ratio: -0.1"), "poisson_ratio must be above 0 for the msd term bulk with zero_length_springs");
  says(replace(with, "constants: physical", "constants: raw, k_s: 1"), "msd.zero_length_springs: only meaningful with 'constants: physical'");
}

TEST(Spec, QuasiStaticIsAnIntegratorWithNewtonsFieldsAndIsRefusedForAVibration) {
  const std::string with = replace(kGood, "dt: 1.0e-4}", "dt: 1.0e-2, integrator: quasi_static, newton_tolerance: 1.0e-9}");
  const bench::Spec s = bench::parse_spec(with, "s.yaml");
  EXPECT_EQ(s.msd->integrator, "quasi_static");
  EXPECT_DOUBLE_EQ(s.msd->newton_tolerance, 1e-9);
  const std::string vib = error_of(replace(with, "loading: {type: uniaxial, path: [[0, 0], [1, 0.1]]}",
                                           "loading: {type: vibration, initial: preload, traction: {face: top, force: [0, 0, 0.3]}, release: 1.0, duration: 0.5}"));
  EXPECT_NE(vib.find("msd.integrator: quasi_static solves equilibria without inertia"), std::string::npos) << vib;
  // The indenter's contact is not held by it yet: refused, naming the field.
  std::string ind = testing_support::read_text(std::string(TISSUEBENCH_SOURCE_DIR) + "/benchmarks/specs/indentation.yaml");
  ind = replace(ind, "integrator: symplectic_euler", "integrator: quasi_static");
  ind = replace(ind, "dt: 1.0e-4", "dt: 0.05");
  const std::string contact = error_of(ind);
  EXPECT_NE(contact.find("msd.integrator: quasi_static does not hold contact with the indenter"), std::string::npos) << contact;
}
