// Calibration files: written with provenance, read back, applied to specs
// (msd.calibration and run --calibration), and refused when they do not fit.
#include "bench/calibration.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace {

const char* kSpec = R"(name: small
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {library: non_muscular_tissue}
msd: {constants: physical, repulsion_factor: 0.1, volume_factor: 0.5, dt: 1.0e-4}
loading: {type: uniaxial, path: [[0, 0], [0.2, -0.1], [0.4, 0.1]]}
output: {interval: 0.02}
)";

bench::CalibrationResult result() {
  bench::CalibrationResult r;
  r.material = "non_muscular_tissue";
  r.before = {1.0, 0.1, 1.0, std::nullopt, std::nullopt, std::nullopt};
  r.after = {0.8, 0.05, 7.5, std::nullopt, std::nullopt, std::nullopt};
  r.before.damping_time = 4.2e-3;
  r.objective_before = 0.7;
  r.objective_after = 0.1;
  r.optimiser_status = "converged (relative reduction)";
  bench::SpecError e;
  e.spec = "calibrate_uniaxial";
  e.sha256 = "ab";
  e.load_series = "nominal_stress";
  r.specs = {e};
  r.fem_version = "1.0";
  r.fem_git_revision = "abc";
  r.created = "2026-11-22T00:00:00Z";
  return r;
}

}  // namespace

TEST(Calibration, ShippedFilesNameACleanReferenceBuildAndWereCheckedOnEveryShippedSpec) {
  // Issue 17 item 2: the calibration files under benchmarks/calibration -
  // the three factors (MATERIAL.yaml) and the edge classes
  // (MATERIAL_lattice.yaml) for both materials - name, as their provenance,
  // an FEM reference build without uncommitted changes, and calibrate ran
  // each fitted set on every shipped comparison spec without a blow-up or an
  // inverted element.
  const std::string dir = std::string(TISSUEBENCH_CALIBRATION_DIR) + "/";
  for (const char* material : {"non_muscular_tissue", "passive_muscle"})
    for (const char* suffix : {"", "_lattice"}) {
      const std::string file = dir + material + suffix + ".yaml";
      std::string named;
      const bench::CalibrationParameters p = bench::read_calibration(file, &named);
      EXPECT_EQ(named, material) << file;
      EXPECT_EQ(p.axis_stiffness.has_value(), std::string(suffix) == "_lattice") << file;
      EXPECT_TRUE(p.damping_time.has_value()) << file << ": stage 2 fitted the dampers";
      std::ifstream in(file);
      std::stringstream text;
      text << in.rdbuf();
      const std::string t = text.str();
      const auto rev = t.find("git_revision: \"");
      ASSERT_NE(rev, std::string::npos) << file;
      const std::string revision = t.substr(rev + 15, t.find('"', rev + 15) - rev - 15);
      EXPECT_EQ(revision.size(), 12u) << file << ": " << revision;
      EXPECT_EQ(revision.find("dirty"), std::string::npos) << file << ": " << revision;
      EXPECT_NE(t.find("checked_on: [uniaxial, shear, bending, bending_gravity, vibration, indentation]"),
                std::string::npos) << file;
    }
}

TEST(Calibration, WithParametersSetsThePhysicalFactors) {
  const bench::Spec s = bench::with_parameters(bench::parse_spec(kSpec, "s.yaml"), {2.0, 0.3, 4.0, std::nullopt, std::nullopt, std::nullopt});
  EXPECT_EQ(s.msd->constants, "physical");
  EXPECT_DOUBLE_EQ(s.msd->stiffness_scale, 2.0);
  EXPECT_DOUBLE_EQ(s.msd->repulsion_factor, 0.3);
  EXPECT_DOUBLE_EQ(s.msd->volume_factor, 4.0);
}

TEST(Calibration, FileRoundTripsWithProvenance) {
  testing_support::TempDir dir("cal");
  bench::write_calibration(result(), dir.file("c.yaml"));
  std::string material;
  const bench::CalibrationParameters p = bench::read_calibration(dir.file("c.yaml"), &material);
  EXPECT_EQ(material, "non_muscular_tissue");
  EXPECT_DOUBLE_EQ(p.stiffness_scale, 0.8);
  EXPECT_DOUBLE_EQ(p.repulsion_factor, 0.05);
  EXPECT_DOUBLE_EQ(p.volume_factor, 7.5);
  std::ifstream in(dir.file("c.yaml"));
  std::stringstream ss;
  ss << in.rdbuf();
  for (const char* k : {"sha256: ab", "git_revision: \"abc\"", "objective:", "optimiser:", "created:"})
    EXPECT_NE(ss.str().find(k), std::string::npos) << k;
}

TEST(Calibration, TheEdgeClassesRoundTripThroughTheFileAndSetTheSpecsSpringLaws) {
  bench::CalibrationResult r = result();
  r.before.axis_stiffness = 0.5;
  r.before.compression_exponent = 1.0;
  r.after.axis_stiffness = 0.61;
  r.after.compression_exponent = 1.7;
  testing_support::TempDir dir("cal");
  bench::write_calibration(r, dir.file("c.yaml"));
  const bench::CalibrationParameters p = bench::read_calibration(dir.file("c.yaml"));
  ASSERT_TRUE(p.axis_stiffness && p.compression_exponent);
  EXPECT_DOUBLE_EQ(*p.axis_stiffness, 0.61);
  EXPECT_DOUBLE_EQ(*p.compression_exponent, 1.7);
  bench::Spec s = bench::parse_spec(kSpec, "s.yaml");
  s.material.name = "non_muscular_tissue";
  bench::apply_calibration(s, dir.file("c.yaml"));
  const auto& laws = s.msd->edge_laws;
  EXPECT_DOUBLE_EQ(laws[0].stiffness, 0.61);
  EXPECT_DOUBLE_EQ(laws[1].stiffness, 1.0);
  EXPECT_DOUBLE_EQ(laws[0].compression_exponent, 1.7);
  EXPECT_DOUBLE_EQ(laws[1].compression_exponent, 1.7);
  EXPECT_DOUBLE_EQ(laws[2].compression_exponent, 0.0);  // `other` edges: none in the lattice, left linear
  // with_parameters (the fit's evaluations) sets the same.
  const bench::Spec w = bench::with_parameters(bench::parse_spec(kSpec, "s.yaml"), p);
  EXPECT_DOUBLE_EQ(w.msd->edge_laws[0].stiffness, 0.61);
  EXPECT_DOUBLE_EQ(w.msd->edge_laws[1].compression_exponent, 1.7);
  // One without the other is refused, naming the field.
  std::ofstream(dir.file("half.yaml")) << "material: non_muscular_tissue\nparameters: {stiffness_scale: 1, "
                                          "repulsion_factor: 0.1, volume_factor: 1, axis_stiffness: 0.5}\n";
  try {
    bench::read_calibration(dir.file("half.yaml"));
    FAIL() << "axis_stiffness without compression_exponent was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("axis_stiffness"), std::string::npos) << e.what();
  }
}

TEST(Calibration, SpecFieldReadsTheFileRelativeToTheSpec) {
  testing_support::TempDir dir("cal");
  bench::write_calibration(result(), dir.file("c.yaml"));
  std::string text = kSpec;
  text.replace(text.find("repulsion_factor: 0.1, volume_factor: 0.5"), 41, "calibration: c.yaml");
  std::ofstream(dir.file("s.yaml")) << text;
  const bench::Spec s = bench::load_spec(dir.file("s.yaml"));
  EXPECT_DOUBLE_EQ(s.msd->stiffness_scale, 0.8);
  EXPECT_DOUBLE_EQ(s.msd->volume_factor, 7.5);
  EXPECT_EQ(s.msd->calibration, dir.file("c.yaml"));
}

TEST(Calibration, MisfitsAreClearErrors) {
  testing_support::TempDir dir("cal");
  bench::CalibrationResult r = result();
  r.material = "passive_muscle";
  bench::write_calibration(r, dir.file("muscle.yaml"));
  bench::Spec s = bench::parse_spec(kSpec, "s.yaml");
  try {
    bench::apply_calibration(s, dir.file("muscle.yaml"));
    FAIL();
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("passive_muscle"), std::string::npos) << e.what();
  }
  EXPECT_THROW(bench::apply_calibration(s, dir.file("missing.yaml")), msd::Error);
  std::ofstream(dir.file("bad.yaml")) << "material: non_muscular_tissue\nparameters: {stiffness_scale: -1, "
                                         "repulsion_factor: 0, volume_factor: 0}\n";
  EXPECT_THROW(bench::apply_calibration(s, dir.file("bad.yaml")), msd::Error);
  // Both the calibration and the factors it sets in one spec.
  std::string text = kSpec;
  text.replace(text.find("repulsion_factor: 0.1"), 21, "calibration: c.yaml, repulsion_factor: 0.1");
  EXPECT_THROW(bench::parse_spec(text, dir.file("s.yaml")), msd::Error);
  // Raw constants cannot take a calibration.
  EXPECT_THROW(bench::parse_spec("name: r\ngeometry: {shape: box, size: [0.02, 0.02, 0.04]}\nmesh: {spacing: 0.01}\n"
                                 "material: {density: 1000}\nmsd: {constants: raw, k_s: 1, dt: 1.0e-4, calibration: "
                                 "c.yaml}\nloading: {type: uniaxial, path: [[0, 0], [1, 0.1]]}\n",
                                 "r.yaml"),
               msd::Error);
}

TEST(Calibration, AStartOutsideTheBoundsOrWithUnaskedEdgeClassesIsRefusedBeforeAnyRun) {
  // The specs do not exist: the start is checked first, so the message is the start's.
  testing_support::TempDir out("cal_start");
  const auto error_of = [&out](const bench::CalibrationParameters& p, bool edge_classes,
                               const std::string& material = "non_muscular_tissue") {
    try {
      bench::calibrate("non_muscular_tissue", {out.file("missing/u.yaml")}, out.file("fit"), {}, {}, 4, 2.0, 2,
                       edge_classes, {}, bench::CalibrationStart{p, "start.yaml", material});
    } catch (const msd::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  bench::CalibrationParameters p{1.0, 0.1, 1.0, std::nullopt, std::nullopt, std::nullopt};
  p.volume_factor = 20.0;  // on the bound: the logistic variable would be infinite
  EXPECT_NE(error_of(p, false).find("start.yaml: parameters.volume_factor = 20 is not strictly inside calibrate's "
                                    "bounds (0, 20)"),
            std::string::npos) << error_of(p, false);
  p.volume_factor = 1.0;
  p.damping_time = 0.05;
  EXPECT_NE(error_of(p, false).find("start.yaml: parameters.damping_time = 0.05"), std::string::npos)
      << error_of(p, false);
  p.damping_time.reset();
  p.axis_stiffness = 0.3;
  p.compression_exponent = 2.0;
  EXPECT_NE(error_of(p, false).find("start.yaml: parameters.axis_stiffness: a start with edge classes needs "
                                    "--edge-classes"),
            std::string::npos) << error_of(p, false);
  p.compression_exponent = 4.5;
  EXPECT_NE(error_of(p, true).find("parameters.compression_exponent = 4.5"), std::string::npos) << error_of(p, true);
  // A start of another material.
  p.compression_exponent = 2.0;
  EXPECT_NE(error_of(p, true, "passive_muscle").find("start.yaml: material: 'passive_muscle' is not the fit's "
                                                     "'non_muscular_tissue'"),
            std::string::npos) << error_of(p, true, "passive_muscle");
  // A valid start passes the check and the fit goes on to the (missing) spec.
  EXPECT_NE(error_of(p, true).find("missing/u.yaml"), std::string::npos) << error_of(p, true);
}

TEST(Calibration, AFittedDampingTimeRoundTripsAndReachesTheMsdOnly) {
  testing_support::TempDir dir("cal");
  bench::CalibrationResult r = result();
  r.damping_fitted = true;
  r.after.damping_time = 0.0123;
  r.damping_status = "converged (relative error)";
  r.damping_evaluations = 7;
  bench::SpecError ring;
  ring.spec = "calibrate_ringdown";
  ring.sha256 = "cd";
  ring.load_series = "damping_ratio";
  ring.damping_ratio_fem = 0.08;
  ring.damping_ratio_after = 0.079;
  r.specs.push_back(ring);
  bench::write_calibration(r, dir.file("c.yaml"));
  const bench::CalibrationParameters p = bench::read_calibration(dir.file("c.yaml"));
  ASSERT_TRUE(p.damping_time);
  EXPECT_DOUBLE_EQ(*p.damping_time, 0.0123);
  std::ifstream in(dir.file("c.yaml"));
  std::stringstream ss;
  ss << in.rdbuf();
  for (const char* k : {"damping_stage:", "damping_ratio_fem: 0.08", "evaluations: 7"})
    EXPECT_NE(ss.str().find(k), std::string::npos) << k;
  bench::Spec s = bench::parse_spec(kSpec, "s.yaml");
  bench::apply_calibration(s, dir.file("c.yaml"));
  ASSERT_TRUE(s.msd->damping_time);
  EXPECT_DOUBLE_EQ(*s.msd->damping_time, 0.0123);
  // with_parameters carries it too, and leaves the material's (the FEM's) alone.
  const bench::Spec w = bench::with_parameters(bench::parse_spec(kSpec, "s.yaml"), p);
  EXPECT_DOUBLE_EQ(*w.msd->damping_time, 0.0123);
  EXPECT_EQ(w.material.damping_time, bench::parse_spec(kSpec, "s.yaml").material.damping_time);
}

TEST(Calibration, WithoutADampingFitTheMaterialsDampingTimeStays) {
  testing_support::TempDir dir("cal");
  bench::write_calibration(result(), dir.file("c.yaml"));  // damping_fitted false
  EXPECT_FALSE(bench::read_calibration(dir.file("c.yaml")).damping_time);
  bench::Spec s = bench::parse_spec(kSpec, "s.yaml");
  bench::apply_calibration(s, dir.file("c.yaml"));
  EXPECT_FALSE(s.msd->damping_time);
  // A negative fitted damping time is refused, naming the file.
  std::ofstream(dir.file("bad.yaml")) << "material: non_muscular_tissue\nparameters: {stiffness_scale: 1, "
                                         "repulsion_factor: 0, volume_factor: 0, damping_time: -0.1}\n";
  try {
    bench::read_calibration(dir.file("bad.yaml"));
    FAIL();
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
  }
}

TEST(Calibration, UnknownFieldsAndMissingFactorsAreRefusedByName) {
  testing_support::TempDir dir("cal");
  bench::write_calibration(result(), dir.file("c.yaml"));
  EXPECT_NO_THROW(bench::read_calibration(dir.file("c.yaml")));  // what write_calibration writes is known
  auto error_of = [&](const std::string& text) {
    std::ofstream(dir.file("x.yaml")) << text;
    try {
      bench::read_calibration(dir.file("x.yaml"));
    } catch (const msd::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string typo = error_of("material: non_muscular_tissue\nparameters: {stiffness_scale: 1, "
                                    "repulsion_factor: 0, volume_factor: 0, dampin_time: 0.1}\n");
  EXPECT_NE(typo.find("x.yaml:2:"), std::string::npos) << typo;
  EXPECT_NE(typo.find("parameters.dampin_time: unknown field"), std::string::npos) << typo;
  const std::string top = error_of("material: non_muscular_tissue\nparameter: {stiffness_scale: 1}\n");
  EXPECT_NE(top.find("parameter: unknown field"), std::string::npos) << top;
  const std::string missing = error_of("parameters: {stiffness_scale: 1, repulsion_factor: 0}\n");
  EXPECT_NE(missing.find("parameters.volume_factor: required field is missing"), std::string::npos) << missing;
  const std::string twice = error_of("parameters: {stiffness_scale: 1, repulsion_factor: 0, volume_factor: 0, "
                                     "volume_factor: -3}\n");
  EXPECT_NE(twice.find("duplicate key 'volume_factor'"), std::string::npos) << twice;
}

TEST(Calibration, AFittedSetIsRunOnTheCheckSpecsAndRefusedWhenItBlowsUp) {
  testing_support::TempDir dir("cal");
  std::ofstream(dir.file("small.yaml")) << kSpec;
  bench::CalibrationParameters sane{1.0, 0.1, 1.0, std::nullopt, 0.5, 1.0};
  EXPECT_EQ(bench::check_fitted_set("passive_muscle", sane, {dir.file("small.yaml")}),
            std::vector<std::string>{"small"});
  // Ten thousand times stiffer: far past the explicit step's stability limit.
  bench::CalibrationParameters stiff = sane;
  stiff.stiffness_scale = 1e4;
  try {
    bench::check_fitted_set("passive_muscle", stiff, {dir.file("small.yaml")});
    FAIL() << "a set that blows up was accepted";
  } catch (const msd::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the fitted set fails on " + dir.file("small.yaml")), std::string::npos) << m;
    EXPECT_NE(m.find("not written"), std::string::npos) << m;
  }
  // The default list is the six shipped comparison specs.
  EXPECT_EQ(bench::shipped_benchmark_specs().size(), 6u);
}

TEST(Calibration, TheCheckRunsAnExplicitSpecOfASofterMaterialAtTheStepItsMarginGivesTheStifferOne) {
  // The shipped indentation: non-muscular tissue with explicit steps of 1e-4 s.
  // Passive muscle (E 14950 Pa against 2990, rho 1040 against 920, the same
  // damping_time) blows up there with its physical constants (at t = 1.6 ms);
  // the check runs it at the step the dampers' limit scales to,
  // 1e-4 x (2990 / 920) / (14950 / 1040) = 2.26e-5 s (the wave limit alone
  // would give 4.75e-5 s, where it still blows up).
  testing_support::TempDir dir("cal");
  std::string spec = kSpec;  // non-muscular tissue, explicit, 1e-4 s, output every 0.02 s
  std::ofstream(dir.file("small.yaml")) << spec;
  std::vector<std::string> lines;
  const bench::CalibrationParameters physical{1.0, 0.1, 1.0, std::nullopt, std::nullopt, std::nullopt};
  bench::check_fitted_set("passive_muscle", physical, {dir.file("small.yaml")},
                          [&](const std::string& l) { lines.push_back(l); });
  bool shrunk = false;
  for (const auto& l : lines)
    shrunk = shrunk || l.find("explicit step 0.0001 s -> 2.26e-05 s (the material's stable step is 0.226") !=
                           std::string::npos;
  EXPECT_TRUE(shrunk) << (lines.empty() ? "no log" : lines.front());
  // Its own material, or an implicit spec: the shipped step stands.
  lines.clear();
  bench::check_fitted_set("non_muscular_tissue", physical, {dir.file("small.yaml")},
                          [&](const std::string& l) { lines.push_back(l); });
  for (const auto& l : lines) EXPECT_EQ(l.find("explicit step"), std::string::npos) << l;
  spec.replace(spec.find("dt: 1.0e-4"), 10, "integrator: backward_euler, dt: 1.0e-2");
  std::ofstream(dir.file("implicit.yaml")) << spec;
  lines.clear();
  bench::check_fitted_set("passive_muscle", physical, {dir.file("implicit.yaml")},
                          [&](const std::string& l) { lines.push_back(l); });
  for (const auto& l : lines) EXPECT_EQ(l.find("explicit step"), std::string::npos) << l;
}
