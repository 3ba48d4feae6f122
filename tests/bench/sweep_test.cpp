// The sweep's grid, point specs and Pareto front (the runs themselves: the
// CLI test and the benchmarks).
#include "bench/sweep.hpp"

#include "msd/core/types.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace {

const char* const kSpec = testing_support::small_uniaxial_spec();

bench::SweepPoint point(double cost, double error) {
  bench::SweepPoint p;
  p.status = "complete";
  p.cost = cost;
  p.load_rel_rms = error;
  return p;
}

}  // namespace

TEST(Sweep, DefaultGridCoversEveryKnobWithACvodePointPerSpatialConfiguration) {
  const bench::Spec spec = bench::parse_spec(kSpec, "small.yaml");
  const auto pts = bench::sweep_points(spec, {});
  // 2 h x 4 term sets x 2 thresholds x (3 integrators x 2 dt + 1 cvode)
  ASSERT_EQ(pts.size(), 2u * 4u * 2u * 7u);
  std::set<double> hs, dts;
  std::set<std::string> integ, terms;
  int cvode = 0;
  for (size_t k = 0; k < pts.size(); ++k) {
    EXPECT_EQ(pts[k].id, static_cast<int>(k));
    hs.insert(pts[k].spacing);
    integ.insert(pts[k].integrator);
    terms.insert(pts[k].terms);
    if (pts[k].integrator == "cvode") ++cvode;
    else dts.insert(pts[k].dt);
  }
  EXPECT_EQ(hs, (std::set<double>{0.01, 0.02}));
  EXPECT_EQ(dts, (std::set<double>{1e-4, 2.5e-4}));
  EXPECT_EQ(integ, (std::set<std::string>{"symplectic_euler", "velocity_verlet", "explicit_euler", "cvode"}));
  EXPECT_EQ(terms.size(), 4u);
  EXPECT_EQ(cvode, 16);
}

TEST(Sweep, PointSpecsParseBackWithTheirKnobs) {
  const bench::Spec spec = bench::parse_spec(kSpec, "small.yaml");
  bench::SweepGrid g;
  g.spacing = {0.02};
  g.dt = {2e-4};
  g.integrators = {"velocity_verlet"};
  g.term_sets = {"no_volume"};
  g.thresholds = {0.7};
  const auto pts = bench::sweep_points(spec, g);
  ASSERT_EQ(pts.size(), 2u);
  const bench::Spec a = bench::parse_spec(bench::point_spec_text(spec, pts[0]), "p0.yaml");
  EXPECT_DOUBLE_EQ(a.mesh->spacing, 0.02);
  EXPECT_DOUBLE_EQ(a.msd->dt, 2e-4);
  EXPECT_EQ(a.msd->integrator, "velocity_verlet");
  EXPECT_EQ(a.msd->terms, (std::vector<std::string>{"springs", "dampers", "repulsion"}));
  EXPECT_DOUBLE_EQ(a.msd->nonlinear_threshold, 0.7);
  EXPECT_EQ(a.name, spec.name);  // the comparison matches points to the reference by name
  const bench::Spec c = bench::parse_spec(bench::point_spec_text(spec, pts[1]), "p1.yaml");
  EXPECT_EQ(c.msd->integrator, "cvode");
  EXPECT_GT(c.msd->rtol, 0.0);
}

TEST(Sweep, BadGridsAreErrors) {
  const bench::Spec spec = bench::parse_spec(kSpec, "small.yaml");
  bench::SweepGrid g;
  g.spacing = {-0.01};
  EXPECT_THROW(bench::sweep_points(spec, g), msd::Error);
  g = {};
  g.dt = {0.5};  // longer than the output interval
  EXPECT_THROW(bench::sweep_points(spec, g), msd::Error);
  g = {};
  g.integrators = {"runge_kutta"};
  EXPECT_THROW(bench::sweep_points(spec, g), msd::Error);
  g = {};
  g.term_sets = {"everything"};
  EXPECT_THROW(bench::sweep_points(spec, g), msd::Error);
  g = {};
  g.thresholds = {1.5};
  EXPECT_THROW(bench::sweep_points(spec, g), msd::Error);
}

TEST(Sweep, ParetoFrontKeepsOnlyUndominatedCompletePoints) {
  std::vector<bench::SweepPoint> pts = {point(1.0, 0.5), point(2.0, 0.2), point(3.0, 0.3), point(4.0, 0.1),
                                        point(0.5, 0.05)};
  pts[4].status = "failed";  // cheapest and best, but it blew up
  bench::mark_pareto(pts);
  EXPECT_TRUE(pts[0].pareto);
  EXPECT_TRUE(pts[1].pareto);
  EXPECT_FALSE(pts[2].pareto);  // dominated by point 1
  EXPECT_TRUE(pts[3].pareto);
  EXPECT_FALSE(pts[4].pareto);
}

TEST(Sweep, ErrorPrefersTheWorkingRange) {
  bench::SweepPoint p = point(1.0, 0.5);
  EXPECT_DOUBLE_EQ(p.error(), 0.5);
  p.load_rel_rms_working = 0.1;
  EXPECT_DOUBLE_EQ(p.error(), 0.1);
}

TEST(Sweep, TermSets) {
  EXPECT_EQ(bench::term_set("all").size(), 4u);
  EXPECT_EQ(bench::term_set("springs_dampers"), (std::vector<std::string>{"springs", "dampers"}));
  EXPECT_THROW(bench::term_set("nothing"), msd::Error);
}

TEST(Sweep, QuasiStaticPointsComeOncePerSpatialConfigurationAndTermSetWithoutTheirDampers) {
  std::string text = kSpec;
  const std::string e = "youngs_modulus: 5000,";
  text.replace(text.find(e), e.size(), e + " poisson_ratio: 0.45,");
  const bench::Spec spec = bench::parse_spec(text, "small.yaml");
  bench::SweepGrid g;
  g.spacing = {0.02};
  g.dt = {2e-4, 1e-3};
  g.integrators = {"velocity_verlet"};
  g.term_sets = {"neo_lattice", "all"};
  g.thresholds = {0.0};
  g.cvode = false;
  g.quasi_static = true;
  const auto pts = bench::sweep_points(spec, g);
  ASSERT_EQ(pts.size(), 2u * (2u + 1u));  // per term set: two dynamic points and one quasi-static
  int statics = 0;
  for (const auto& p : pts) {
    const bench::Spec s = bench::parse_spec(bench::point_spec_text(spec, p), "p.yaml");
    EXPECT_EQ(s.msd->zero_length_springs, p.terms == "neo_lattice");
    if (p.integrator != "quasi_static") {
      EXPECT_EQ(s.msd->integrator, "velocity_verlet");
      EXPECT_EQ(s.msd->terms, bench::term_set(p.terms));
      continue;
    }
    ++statics;
    EXPECT_DOUBLE_EQ(p.dt, spec.output.interval);
    EXPECT_DOUBLE_EQ(s.msd->dt, spec.output.interval);
    if (p.terms == "neo_lattice") {
      EXPECT_EQ(s.msd->terms, (std::vector<std::string>{"springs", "bulk"}));
      EXPECT_EQ(s.msd->newton_linear_solver, "symmetric_ldlt");  // every term has an energy: symmetric
    } else {
      EXPECT_EQ(s.msd->terms, (std::vector<std::string>{"springs", "repulsion", "volume"}));
      EXPECT_EQ(s.msd->newton_linear_solver, "sparse_lu");  // the thesis' volume term is not symmetric
    }
  }
  EXPECT_EQ(statics, 2);
  // Without the flag: none.
  g.quasi_static = false;
  EXPECT_EQ(bench::sweep_points(spec, g).size(), 4u);
  EXPECT_EQ(bench::term_set("neo_lattice"), (std::vector<std::string>{"springs", "dampers", "bulk"}));
}

TEST(Sweep, ExplicitPointsOfASpecShippedWithNewtonsFieldsDropThemAndImplicitOnesKeepThem) {
  // vibration.yaml ships BDF2 with newton_linear_solver: symmetric_ldlt; a
  // symplectic Euler point of it is refused by the spec unless the sweep drops the field.
  std::string text = kSpec;
  const std::string d = "dt: 1.0e-4}";
  text.replace(text.find(d), d.size(), "dt: 1.0e-4, integrator: bdf2, newton_linear_solver: symmetric_ldlt, newton_tolerance: 1.0e-9}");
  const bench::Spec spec = bench::parse_spec(text, "small.yaml");
  bench::SweepGrid g;
  g.spacing = {0.02};
  g.dt = {1e-4};
  g.integrators = {"symplectic_euler", "bdf2"};
  g.term_sets = {"springs_dampers"};
  g.thresholds = {0.0};
  const auto pts = bench::sweep_points(spec, g);
  ASSERT_EQ(pts.size(), 3u);  // two fixed steps and CVODE
  for (const auto& p : pts) {
    const bench::Spec s = bench::parse_spec(bench::point_spec_text(spec, p), "p.yaml");  // throws if refused
    EXPECT_EQ(s.msd->integrator, p.integrator);
    if (p.integrator == "bdf2") {
      EXPECT_EQ(s.msd->newton_linear_solver, "symmetric_ldlt");
      EXPECT_DOUBLE_EQ(s.msd->newton_tolerance, 1e-9);
    }
  }
}
