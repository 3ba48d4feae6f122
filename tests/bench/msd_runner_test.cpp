#include "bench/msd_runner.hpp"

#include "bench/shared_io.hpp"
#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

const char* const kSpec = testing_support::small_uniaxial_spec();

// kSpec read with its msd section's "dt: 1.0e-4" replaced by `msd_fields`
// must be refused with a message naming the file and `field`.
void expect_refused(const std::string& msd_fields, const std::string& field) {
  std::string text = kSpec;
  text.replace(text.find("dt: 1.0e-4"), 10, msd_fields);
  try {
    bench::parse_spec(text, "small.yaml");
    ADD_FAILURE() << "accepted: " << msd_fields;
  } catch (const msd::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("small.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find(field), std::string::npos) << what;
  }
}

}  // namespace

TEST(MsdRunner, WritesACompleteResultsFile) {
  testing_support::TempDir dir("runner");
  const bench::Spec spec = bench::parse_spec(kSpec, "small.yaml");
  const bench::RunSummary s = bench::run_msd(spec, dir.file("sub/small.h5"));
  ASSERT_TRUE(s.complete) << s.failure;
  EXPECT_EQ(s.tets, 5 * 16);
  const bench::Results r = bench::read_results(dir.file("sub/small.h5"));
  EXPECT_EQ(r.status(), "complete");
  for (const char* k : {"time", "strain", "nominal_stress", "volume_ratio", "inverted_elements"})
    ASSERT_EQ(r.series.at(k).size(), 21u) << k;
  EXPECT_NEAR(r.series.at("strain").back(), 0.1, 1e-12);
  EXPECT_GT(r.series.at("nominal_stress").back(), 0.0);
  EXPECT_DOUBLE_EQ(r.material.at("youngs_modulus"), 5000);
  EXPECT_DOUBLE_EQ(r.material.at("lattice_factor"), 5.0 / 6.0);
  EXPECT_GT(r.material.at("k_s_max"), 0.0);
  EXPECT_EQ(r.meta.at("integrator"), "symplectic_euler");
  EXPECT_DOUBLE_EQ(r.timing.at("steps"), 4000);
  EXPECT_TRUE(std::filesystem::exists(dir.file("sub/small.csv")));
}

TEST(MsdRunner, BlowUpLeavesAFailedFileWithTheRowsSoFar) {
  testing_support::TempDir dir("runner");
  std::string text = kSpec;
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-2");
  const bench::Spec spec = bench::parse_spec(text, "small.yaml");
  const bench::RunSummary s = bench::run_msd(spec, dir.file("b.h5"));
  EXPECT_FALSE(s.complete);
  EXPECT_NE(s.failure.find("t = "), std::string::npos) << s.failure;
  const bench::Results r = bench::read_results(dir.file("b.h5"));
  EXPECT_EQ(r.status(), "failed");
  EXPECT_EQ(r.meta.at("failure"), s.failure);
  EXPECT_GE(r.series.at("time").size(), 1u);
}

TEST(MsdRunner, BadInputWritesNothing) {
  testing_support::TempDir dir("runner");
  std::string text = kSpec;
  text.replace(text.find("spacing: 0.01"), 13, "spacing: 0.5");  // larger than the box: no cube
  text.replace(text.find("mesh: {"), 7, "mesh: {rule: inside, ");
  const bench::Spec spec = bench::parse_spec(text, "small.yaml");
  EXPECT_THROW(bench::run_msd(spec, dir.file("x.h5")), msd::Error);
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.h5")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.csv")));
}

TEST(MsdRunner, ObjGeometry) {
  testing_support::TempDir dir("runner");
  msd::write_obj(dir.file("c.obj"), msd::make_cylinder(0.02, 0.04, 24));
  std::string text = kSpec;
  const std::string box = "{shape: box, size: [0.02, 0.02, 0.04]}";
  text.replace(text.find(box), box.size(), "{shape: obj, file: c.obj}");
  const bench::Spec spec = bench::parse_spec(text, dir.file("spec.yaml"));
  const msd::SampleMesh m = bench::make_sample_mesh(spec);
  EXPECT_GT(m.cubes, 0);
}

TEST(MsdRunner, IndentationWritesTheForceDepthCurveAndRefusesCvode) {
  const std::string text = R"(name: ind
geometry: {shape: box, size: [0.04, 0.01, 0.02]}
mesh: {spacing: 0.005}
material: {density: 1000, youngs_modulus: 3000, damping_time: 0.01}
msd: {constants: physical, terms: [springs, dampers], dt: 2.0e-4}
loading:
  type: indentation
  indenter: {shape: cylinder, radius: 0.01, axis: y, depth: 0.004}
  path: [[0, 0], [0.5, 1], [1.0, 1]]
output: {interval: 0.05}
)";
  testing_support::TempDir dir("runner");
  const bench::RunSummary s = bench::run_msd(bench::parse_spec(text, "ind.yaml"), dir.file("ind.h5"));
  ASSERT_TRUE(s.complete) << s.failure;
  const bench::Results r = bench::read_results(dir.file("ind.h5"));
  ASSERT_EQ(r.series.at("depth").size(), 21u);
  EXPECT_NEAR(r.series.at("depth").back(), 0.004, 1e-15);
  const double f = r.series.at("indentation_force").back();
  EXPECT_GT(f, 0.0);
  EXPECT_GT(r.series.at("contact_nodes").back(), 0.0);
  EXPECT_NEAR(r.series.at("base_reaction_z").back(), f, 0.02 * f);  // settled after the hold
  std::string cvode = text;
  cvode.replace(cvode.find("dt: 2.0e-4"), 10, "integrator: cvode");
  try {
    bench::compile_msd(bench::parse_spec(cvode, "ind.yaml"));
    FAIL() << "cvode with contact was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot integrate contact"), std::string::npos) << e.what();
  }
}

TEST(MsdRunner, ImplicitIntegratorsCompleteAtAStepWhereSymplecticEulerBlowsUpAndRecordNewtonsWork) {
  // dt = 1e-2 s: the step BlowUpLeavesAFailedFileWithTheRowsSoFar fails with.
  for (const std::string integ : {"backward_euler", "bdf2"}) {
    testing_support::TempDir dir("runner");
    std::string text = kSpec;
    text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-2, integrator: " + integ);
    const bench::RunSummary s = bench::run_msd(bench::parse_spec(text, "small.yaml"), dir.file("i.h5"));
    ASSERT_TRUE(s.complete) << integ << ": " << s.failure;
    const bench::Results r = bench::read_results(dir.file("i.h5"));
    EXPECT_EQ(r.meta.at("integrator"), integ);
    EXPECT_DOUBLE_EQ(r.timing.at("steps"), 40) << integ;
    EXPECT_GE(r.timing.at("newton_iterations"), 40) << integ;  // at least one per step under load
    EXPECT_GE(r.timing.at("factorizations"), 1) << integ;
    EXPECT_EQ(r.series.at("inverted_elements").back(), 0.0) << integ;
    EXPECT_GT(r.series.at("nominal_stress").back(), 0.0) << integ;  // stretched at the end
  }
}

TEST(MsdRunner, NewtonSettingsBelongToBackwardEulerOnly) {
  std::string text = kSpec;
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-4, newton_tolerance: 1.0e-6");
  try {
    bench::parse_spec(text, "small.yaml");
    FAIL() << "expected a refusal";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("newton_tolerance"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("only meaningful with 'integrator: backward_euler'"), std::string::npos);
  }
  text = kSpec;
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-4, integrator: backward_euler, newton_max_iterations: 0");
  EXPECT_THROW(bench::parse_spec(text, "small.yaml"), msd::Error);
  // BDF2 takes them too.
  text = kSpec;
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-4, integrator: bdf2, newton_max_iterations: 7");
  EXPECT_EQ(bench::parse_spec(text, "small.yaml").msd->newton_max_iterations, 7);
}

TEST(MsdRunner, TheLinearSolverIsReadForTheImplicitIntegratorsAndAnUnknownOneIsRefusedByName) {
  std::string text = kSpec;
  EXPECT_EQ(bench::parse_spec(text, "small.yaml").msd->newton_linear_solver, "sparse_lu");  // the default
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-2, integrator: bdf2, newton_linear_solver: symmetric_ldlt");
  const bench::Spec spec = bench::parse_spec(text, "small.yaml");
  EXPECT_EQ(spec.msd->newton_linear_solver, "symmetric_ldlt");
  EXPECT_EQ(bench::compile_msd(spec).model.newton.linear_solver, msd::LinearSolver::symmetric_ldlt);
  expect_refused("dt: 1.0e-4, newton_linear_solver: symmetric_ldlt", "newton_linear_solver");
  expect_refused("dt: 1.0e-2, integrator: bdf2, newton_linear_solver: cholesky", "newton_linear_solver");
}

TEST(MsdRunner, TheAndersonDepthIsReadForTheImplicitIntegratorsAndMisuseIsRefusedByName) {
  std::string text = kSpec;
  EXPECT_EQ(bench::parse_spec(text, "small.yaml").msd->newton_anderson_depth, 0);  // the default: plain chord steps
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-2, integrator: bdf2, newton_anderson_depth: 3");
  const bench::Spec spec = bench::parse_spec(text, "small.yaml");
  EXPECT_EQ(spec.msd->newton_anderson_depth, 3);
  EXPECT_EQ(bench::compile_msd(spec).model.newton.anderson_depth, 3);
  expect_refused("dt: 1.0e-4, newton_anderson_depth: 3", "newton_anderson_depth");  // an explicit step
  expect_refused("dt: 1.0e-2, integrator: bdf2, newton_anderson_depth: 9", "newton_anderson_depth");
  expect_refused("dt: 1.0e-2, integrator: bdf2, newton_anderson_depth: -1", "newton_anderson_depth");
}

TEST(MsdRunner, TheNeoHookeanTermAndItsCubeVolumesAreReadAndMisuseIsRefusedByName) {
  std::string text = kSpec;
  text.replace(text.find("youngs_modulus: 5000"), 20, "youngs_modulus: 5000, poisson_ratio: 0.45");
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-2, integrator: bdf2, terms: [neo_hookean, dampers], continuum_volume: per_cube");
  const bench::Spec spec = bench::parse_spec(text, "small.yaml");
  EXPECT_EQ(spec.msd->continuum_volume, "per_cube");
  const bench::MsdProblem p = bench::compile_msd(spec);
  EXPECT_EQ(p.model.terms, unsigned(msd::kNeoHookean | msd::kDampers));
  EXPECT_EQ(p.model.volume_groups.size(), 2 * 2 * 4);
  EXPECT_EQ(bench::compile_msd(bench::parse_spec(kSpec, "small.yaml")).model.volume_groups.size(), 0);
  testing_support::TempDir dir("runner_snh");
  const bench::RunSummary s = bench::run_msd(spec, dir.file("snh.h5"));
  ASSERT_TRUE(s.complete) << s.failure;
  const bench::Results r = bench::read_results(dir.file("snh.h5"));
  EXPECT_EQ(r.meta.at("continuum_volume"), "per_cube");
  EXPECT_EQ(r.meta.at("terms"), "dampers,neo_hookean");
  // Compressed 10 % and stretched 10 %: the stress follows the strain's sign.
  EXPECT_GT(r.series.at("nominal_stress").back(), 0.0);
  for (const auto& [bad, field] : std::vector<std::pair<std::string, std::string>>{
           {"terms: [springs, dampers], continuum_volume: per_cube", "continuum_volume"},
           {"terms: [neo_hookean], continuum_volume: per_node", "continuum_volume"},
           {"terms: [neo_hookean, dampers]", "poisson_ratio"}}) {
    text = kSpec;
    text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-4, " + bad);
    try {
      bench::parse_spec(text, "small.yaml");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const msd::Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("small.yaml"), std::string::npos) << what;
      EXPECT_NE(what.find(field), std::string::npos) << what;
    }
  }
}

TEST(MsdRunner, TheIndentationRunsWithTheImplicitIntegratorsAtTenMillisecondSteps) {
  // The shipped indentation at the quick tier's grid (h = 5 mm) with BDF2
  // and backward Euler at 10 ms. Before the solve held the nodes on the
  // indenter, both failed at t = 1.6 s (Newton did not converge under the
  // indenter after six step halvings); so did BDF2 against a frictionless
  // indenter until the solve held its contacts' normal motion.
  std::ifstream in(std::string(TISSUEBENCH_SOURCE_DIR) + "/benchmarks/specs/indentation.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  for (const char* integ : {"bdf2", "backward_euler", "bdf2 frictionless"}) {
    std::string text = buf.str();
    const std::string label = integ;
    const bool frictionless = label == "bdf2 frictionless";
    if (frictionless) {
      text.replace(text.find("response: stick"), 15, "response: frictionless");
      integ = "bdf2";
    }
    text.replace(text.find("spacing: 0.0025"), 15, "spacing: 0.005");
    text.replace(text.find("integrator: symplectic_euler"), 28, std::string("integrator: ") + integ);
    text.replace(text.find("dt: 1.0e-4"), 10, "dt: 1.0e-2");
    testing_support::TempDir dir("runner");
    const bench::RunSummary s = bench::run_msd(bench::parse_spec(text, "indentation.yaml"), dir.file("i.h5"));
    ASSERT_TRUE(s.complete) << label << ": " << s.failure;
    const bench::Results r = bench::read_results(dir.file("i.h5"));
    double most = 0.0, contacts = 0.0;
    for (double v : r.series.at("inverted_elements")) EXPECT_EQ(v, 0.0) << label;
    for (double f : r.series.at("indentation_force")) most = std::max(most, f);
    for (double c : r.series.at("contact_nodes")) contacts = std::max(contacts, c);
    EXPECT_GT(most, 0.0) << label;
    EXPECT_GT(contacts, 0.0) << label;
  }
}
