// Verification of the FEM reference (reference_fem) on the shipped specs:
// closed-form homogeneous cases to solver tolerance, Cook's membrane against
// published values (and locking of the plain displacement formulation), the
// first frequency of a bar against the closed form with the time-integration
// error below the spatial error, and the bonded thesis cylinder's refinement
// study.
#include "bench/closed_form.hpp"
#include "bench/convergence.hpp"
#include "bench/fem_runner.hpp"
#include "bench/shared_io.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace {

testing_support::TempDir& dir() {
  static testing_support::TempDir d("fem_verification");
  return d;
}

bench::Spec shipped(const std::string& name) {
  return bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/" + name + ".yaml");
}

bench::Results run(const bench::Spec& spec, const std::string& tag) {
  const std::string file = dir().file(tag + ".h5");
  const bench::RunSummary s = bench::run_fem(spec, file);
  EXPECT_TRUE(s.complete) << s.failure;
  return bench::read_results(file);
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

void expect_uniaxial_closed_form(const std::string& name) {
  const bench::Spec spec = shipped(name);
  const fem::NeoHookean m = bench::fem_material(spec);
  const bench::Results r = run(spec, name);
  const auto& e = r.series.at("strain");
  const auto& s = r.series.at("nominal_stress");
  const auto& v = r.series.at("volume_ratio");
  ASSERT_GT(e.size(), 30u);
  EXPECT_NEAR(*std::min_element(e.begin(), e.end()), -0.5, 1e-12);
  EXPECT_NEAR(*std::max_element(e.begin(), e.end()), 1.0, 1e-12);
  const double scale = max_abs(s);
  for (size_t i = 0; i < e.size(); ++i) {
    const bench::UniaxialClosedForm c = bench::neo_hookean_uniaxial(m.mu, m.kappa, e[i]);
    EXPECT_NEAR(s[i], c.nominal_stress, 1e-8 * scale) << "strain " << e[i];
    EXPECT_NEAR(v[i], c.volume_ratio, 1e-8) << "strain " << e[i];
  }
}

}  // namespace

TEST(FemVerification, UniaxialRollerMatchesClosedForm) { expect_uniaxial_closed_form("verify_uniaxial_roller"); }

TEST(FemVerification, UniaxialRollerNearlyIncompressibleMatchesClosedForm) {
  expect_uniaxial_closed_form("verify_uniaxial_roller_incompressible");
}

TEST(FemVerification, SimpleShearMatchesClosedForm) {
  const bench::Spec spec = shipped("verify_simple_shear");
  const fem::NeoHookean m = bench::fem_material(spec);
  const bench::Results r = run(spec, "shear");
  const auto& g = r.series.at("shear_strain");
  ASSERT_EQ(g.size(), 21u);
  EXPECT_NEAR(g.back(), 0.6, 1e-12);
  const double scale = m.mu * 0.6;
  for (size_t i = 0; i < g.size(); ++i) {
    const auto c = bench::neo_hookean_simple_shear(m.mu, g[i]);
    EXPECT_NEAR(r.series.at("shear_stress")[i], c[0], 1e-8 * scale);
    EXPECT_NEAR(r.series.at("normal_stress_xx")[i], c[1], 1e-8 * scale);
    EXPECT_NEAR(r.series.at("normal_stress_yy")[i], c[2], 1e-8 * scale);
    EXPECT_NEAR(r.series.at("normal_stress_zz")[i], c[3], 1e-8 * scale);
    EXPECT_NEAR(r.series.at("volume_ratio")[i], 1.0, 1e-10);
  }
}

TEST(FemVerification, CooksMembraneCompressibleMatchesPublishedValues) {
  // Pelteret & McBride (deal.II code gallery, 2016): Q2, vertical displacement
  // of the loaded edge's mid-point (48, 52) mm: 8 x 8 -> 14.71 mm,
  // 16 x 16 -> 14.73 mm, converged 14.74 mm.
  bench::Spec spec = shipped("verify_cooks_membrane");
  spec.fem.cells = std::array<unsigned, 3>{{8, 8, 1}};
  const bench::Results r = run(spec, "cooks8");
  EXPECT_NEAR(1e3 * r.series.at("mid_edge_displacement").back(), 14.71, 0.006);
  EXPECT_GT(r.series.at("tip_displacement").back(), 0.0);
}

TEST(FemVerification, CooksMembraneIncompressibleConvergesWithoutLocking) {
  // de Souza Neto et al. 1996 / Elguedj et al. 2008: converged vertical
  // displacement of the top-right corner 6.9083 mm (128 x 128).
  const bench::Spec spec = shipped("verify_cooks_membrane_incompressible");
  bench::Spec base = spec;
  base.fem.cells = std::array<unsigned, 3>{{8, 8, 1}};
  const bench::ConvergenceStudy st = bench::run_convergence(base, {0, 1, 2}, 1, dir().file(""));
  ASSERT_EQ(st.levels.size(), 3u);
  const double d8 = st.levels[0].values.back(), d16 = st.levels[1].values.back(), d32 = st.levels[2].values.back();
  EXPECT_LT(d8, d16);
  EXPECT_LT(d16, d32);
  EXPECT_NEAR(1e3 * d32, 6.9083, 0.01 * 6.9083);
  EXPECT_GT(st.observed_order, 0.8);
  // Richardson extrapolation of the corner displacement lands on the published value.
  const double p = st.observed_order;
  const double extrapolated = d32 + (d32 - d16) / (std::pow(2.0, p) - 1.0);
  EXPECT_NEAR(1e3 * extrapolated, 6.9083, 0.005 * 6.9083);
  // The plain displacement formulation locks on the same 16 x 16 mesh.
  bench::Spec locking = spec;
  locking.fem.formulation = "displacement";
  const bench::Results r = run(locking, "cooks_locking");
  EXPECT_LT(r.series.at("tip_displacement").back(), 0.5 * d16);
}

TEST(FemVerification, BarFrequencyMatchesClosedFormAndTimeErrorIsBelowSpaceError) {
  const bench::Spec spec = shipped("verify_bar_vibration");
  const double exact = bench::bar_first_frequency(*spec.material.youngs_modulus, spec.material.density,
                                                  spec.geometry.size.z());
  auto frequency = [&](unsigned cells, double rtol, const std::string& tag) {
    bench::Spec s = spec;
    s.fem.cells = std::array<unsigned, 3>{{1, 1, cells}};
    s.fem.relative_tolerance = rtol;
    return run(s, tag).metrics.at("first_frequency");
  };
  const double f8 = frequency(8, spec.fem.relative_tolerance, "bar8");
  EXPECT_NEAR(f8, exact, 1e-4 * exact);
  const double f4 = frequency(4, spec.fem.relative_tolerance, "bar4");
  const double tight = frequency(8, 1e-9, "bar8_tight");
  const double spatial = std::abs(f8 - f4), temporal = std::abs(f8 - tight);
  EXPECT_GT(spatial, 0.0);
  EXPECT_LT(temporal, spatial) << "time error " << temporal << " Hz, spatial error " << spatial << " Hz";
}

TEST(FemVerification, BondedCylinderConvergesUnderRefinement) {
  // The thesis cylinder bonded to platens (uniaxial_reference.yaml) on a
  // shortened path, Q1-P0-P0 at three refinement levels: the reaction-force
  // curve converges (the bonded edges are singular, so the order is about 1).
  bench::Spec spec = shipped("uniaxial_reference");
  spec.loading.path = {{0.0, 0.0}, {1.0, -0.5}, {3.0, 1.0}};
  spec.output.interval = 0.25;
  const bench::ConvergenceStudy st = bench::run_convergence(spec, {0, 1, 2}, 1, dir().file(""));
  ASSERT_EQ(st.differences.size(), 2u);
  EXPECT_LT(st.differences[1], 0.7 * st.differences[0]);
  EXPECT_GT(st.observed_order, 0.5);
  EXPECT_LT(st.finest_relative_error, 0.05);
  // The finest curve is compressive under compression and tensile under tension.
  const auto& v = st.levels.back().values;
  EXPECT_LT(*std::min_element(v.begin(), v.end()), 0.0);
  EXPECT_GT(*std::max_element(v.begin(), v.end()), 0.0);
}

TEST(FemVerification, HangingBarSagsAsClosedFormAndCarriesItsWeight) {
  const bench::Spec spec = shipped("verify_hanging_bar");
  const double E = *spec.material.youngs_modulus, rho = spec.material.density, L = spec.geometry.size.z();
  const double g = 9.81;
  const bench::Results r = run(spec, "hanging");
  const double sag = -r.series.at("tip_displacement_z").back();
  EXPECT_NEAR(sag, rho * g * L * L / (2 * E), 1e-3 * rho * g * L * L / (2 * E));
  const double weight = rho * g * spec.geometry.size.x() * spec.geometry.size.y() * L;
  EXPECT_NEAR(r.series.at("reaction_force_z").back(), weight, 1e-10 * weight);
}

namespace {

// The indentation benchmark, loading only, on a coarse Q1 mesh.
bench::Spec small_indentation(double penalty) {
  bench::Spec spec = shipped("indentation");
  spec.fem.degree = 1;
  spec.fem.cells = std::array<unsigned, 3>{{6, 2, 3}};
  spec.fem.contact_penalty = penalty;
  spec.loading.path = {{0.0, 0.0}, {1.0, 1.0}};
  spec.output.interval = 0.05;
  spec.output.fields_interval = 1.0;
  return spec;
}

}  // namespace

TEST(FemVerification, IndentationForceIsTheStoredEnergysDerivativeAndConvergesInThePenalty) {
  const bench::Results r = run(small_indentation(100.0), "indentation_p100");
  const auto& d = r.series.at("depth");
  const auto& F = r.series.at("indentation_force");
  const auto& E = r.series.at("stored_energy");
  ASSERT_EQ(d.size(), 21u);
  // Work done on the body by the cylinder (trapezoid rule) = the energy stored
  // in it, strain plus penalty: the reported force is the energy's derivative
  // with respect to the indenter's position.
  double work = 0.0;
  for (size_t i = 1; i < d.size(); ++i) work += 0.5 * (F[i] + F[i - 1]) * (d[i] - d[i - 1]);
  EXPECT_GT(E.back(), 0.0);
  EXPECT_NEAR(work, E.back(), 0.01 * E.back());
  // Equilibrium: the bonded base carries what the cylinder pushes.
  EXPECT_NEAR(r.series.at("base_reaction_z").back(), F.back(), 1e-8 * F.back());
  // A tenfold penalty moves the force by less than 1 % and cuts the
  // penetration about tenfold.
  const bench::Results r10 = run(small_indentation(1000.0), "indentation_p1000");
  EXPECT_NEAR(r10.series.at("indentation_force").back(), F.back(), 0.01 * F.back());
  const double ratio = r.series.at("max_penetration").back() / r10.series.at("max_penetration").back();
  EXPECT_GT(ratio, 5.0);
  EXPECT_LT(ratio, 20.0);
}
