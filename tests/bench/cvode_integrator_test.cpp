// The CVODE time integration of the MSD model: exact-in-time on problems with
// known trajectories, the same sampling as the fixed-step loop, and failures
// that name when.
#include "bench/cvode_integrator.hpp"

#include "bench/msd_runner.hpp"
#include "bench/spec.hpp"
#include "msd/model/model.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

const char* kSpec = R"(name: small
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {density: 1000, youngs_modulus: 5000, damping_time: 0.002}
msd: {constants: physical, repulsion_factor: 0.1, volume_factor: 0.5, integrator: cvode}
loading: {type: uniaxial, path: [[0, 0], [0.2, -0.1], [0.4, 0.1]]}
output: {interval: 0.02}
)";

std::vector<double> series_of(const bench::MsdProblem& p, const std::string& name,
                              std::vector<double>* times = nullptr) {
  int c = -1;
  for (size_t k = 0; k < p.columns.size(); ++k)
    if (p.columns[k].name == name) c = static_cast<int>(k);
  std::vector<double> out;
  const msd::ExperimentHooks hooks = bench::msd_hooks(p, [&](const std::vector<double>& r) {
    out.push_back(r[static_cast<size_t>(c)]);
    if (times) times->push_back(r[0]);
    return true;
  });
  bench::integrate_msd(p, hooks);
  return out;
}

}  // namespace

TEST(Cvode, FreeFallUnderGravityIsExact) {
  // A one-tet body with no internal forces under gravity: x(t) = x0 + g t^2 / 2.
  const msd::TetMesh mesh = testing_support::corner_tet_mesh(0.01);
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 1.0;
  msd::ModelOptions opt;
  opt.terms = msd::kGravity;
  opt.gravity = msd::Vec3(0, 0, -9.81);
  opt.region_materials = {mat};
  const msd::Model model = msd::build_model(mesh, opt);
  std::vector<double> z;
  msd::ExperimentHooks hooks;
  hooks.controls = [](double) { return msd::Controls{}; };
  hooks.sample = [&](const msd::State& s, msd::Scratch&) {
    z.push_back(s.x(2, 3) - model.rest_positions(2, 3) + 0.5 * 9.81 * s.t * s.t);
    return true;
  };
  bench::CvodeOptions o;
  o.output_interval = 0.05;
  const bench::CvodeStats st = bench::run_experiment_cvode(model, msd::rest_state(model), 0.5, 10.0, o, hooks);
  ASSERT_EQ(z.size(), 11u);
  for (double e : z) EXPECT_NEAR(e, 0.0, 1e-8);
  EXPECT_NEAR(st.simulated_seconds, 0.5, 1e-12);
  EXPECT_GT(st.steps, 0);
}

TEST(Cvode, AgreesWithFixedStepIntegratorsAsTheirStepShrinks) {
  const bench::Spec spec = bench::parse_spec(kSpec, "small.yaml");
  const bench::MsdProblem pc = bench::compile_msd(spec);
  ASSERT_TRUE(pc.cvode);
  std::vector<double> tc;
  const auto ref = series_of(pc, "nominal_stress", &tc);
  ASSERT_EQ(ref.size(), 21u);  // the same samples as the fixed-step loop: 0, 0.02, ..., 0.4
  EXPECT_NEAR(tc.back(), 0.4, 1e-12);
  double scale = 0.0;
  for (double v : ref) scale = std::max(scale, std::abs(v));
  double previous = 1e300;
  for (double dt : {4e-4, 1e-4, 2.5e-5}) {
    std::string text = kSpec;
    text.replace(text.find("integrator: cvode"), 17, "integrator: symplectic_euler, dt: " + std::to_string(dt));
    const auto y = series_of(bench::compile_msd(bench::parse_spec(text, "small.yaml")), "nominal_stress");
    ASSERT_EQ(y.size(), ref.size());
    double err = 0.0;
    for (size_t i = 1; i < y.size(); ++i) err = std::max(err, std::abs(y[i] - ref[i]));
    EXPECT_LT(err, previous) << "dt " << dt;  // the time error shrinks with dt (first order)
    previous = err;
  }
  EXPECT_LT(previous, 0.02 * scale);
}

TEST(Cvode, SpecFieldsAreChecked) {
  std::string text = kSpec;
  text.replace(text.find("integrator: cvode"), 17, "integrator: cvode, dt: 1.0e-4");
  EXPECT_THROW(bench::parse_spec(text, "x.yaml"), msd::Error);  // cvode chooses its steps
  text = kSpec;
  text.replace(text.find("integrator: cvode"), 17, "integrator: symplectic_euler, dt: 1.0e-4, rtol: 1.0e-6");
  EXPECT_THROW(bench::parse_spec(text, "x.yaml"), msd::Error);  // rtol only with cvode
  text = kSpec;
  text.replace(text.find("integrator: cvode"), 17, "integrator: cvode, rtol: -1");
  EXPECT_THROW(bench::parse_spec(text, "x.yaml"), msd::Error);
}

TEST(Cvode, BlowUpThrowsWithTheTime) {
  // A body driven far beyond ten sample sizes by a huge dead load.
  std::string text = kSpec;
  text.replace(text.find("loading:"), std::string::npos,
               "loading: {type: static, fixed: bottom, traction: {face: top, force: [0, 0, 1.0e6]}, "
               "path: [[0, 0], [0.1, 1]]}\n");
  const bench::MsdProblem p = bench::compile_msd(bench::parse_spec(text, "x.yaml"));
  const msd::ExperimentHooks hooks = bench::msd_hooks(p, [](const std::vector<double>&) { return true; });
  try {
    bench::integrate_msd(p, hooks);
    FAIL() << "expected a failure";
  } catch (const msd::SimulationFailure& f) {
    EXPECT_GT(f.time, 0.0);
    EXPECT_LE(f.time, 0.1);
  }
}
