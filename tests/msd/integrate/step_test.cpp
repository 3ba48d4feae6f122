#include "msd/integrate/step.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

using msd::Vec3;

namespace {

// One tet with nodes 0, 1, 2 pinned: node 3 oscillates on its three springs, a
// small smooth non-linear oscillator (about 4.5 Hz for k = 100 N/m, 0.25 kg).
msd::Model oscillator(double k, double mass_density) {
  const msd::TetMesh m = testing_support::corner_tet_mesh(1.0);
  msd::TissueMaterial mat;
  mat.density = mass_density;
  mat.k_s = k;
  msd::ModelOptions o;
  o.terms = msd::kSprings;
  o.region_materials = {mat};
  o.groups = {{"base", {0, 1, 2}, {true, true, true}}};
  return msd::build_model(m, o);
}

double run(const msd::Model& model, msd::Integrator integ, double dt, double t_end, double z0) {
  msd::State s = msd::rest_state(model);
  s.x(2, 3) = 1.0 + z0;
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  const long n = std::lround(t_end / dt);
  for (long i = 0; i < n; ++i) msd::step(model, s, c, dt, integ, scratch);
  return s.x(2, 3) - 1.0;
}

}  // namespace

TEST(Step, IntegratorsConvergeAtTheirOrder) {
  // Compare against a velocity-Verlet reference with a 200x smaller step.
  const msd::Model m = oscillator(100.0, 6.0);  // mass per node = 6 * (1/6) / 4
  const double ref = run(m, msd::Integrator::VelocityVerlet, 1e-5, 0.5, 1e-3);
  auto err = [&](msd::Integrator i, double dt) { return std::abs(run(m, i, dt, 0.5, 1e-3) - ref); };
  // First order: halving dt halves the error (ratio ~2); second order: ~4.
  const double e1 = err(msd::Integrator::ExplicitEuler, 2e-3), e2 = err(msd::Integrator::ExplicitEuler, 1e-3);
  EXPECT_NEAR(e1 / e2, 2.0, 0.4);
  const double s1 = err(msd::Integrator::SymplecticEuler, 2e-3), s2 = err(msd::Integrator::SymplecticEuler, 1e-3);
  EXPECT_NEAR(s1 / s2, 2.0, 0.4);
  const double v1 = err(msd::Integrator::VelocityVerlet, 2e-3), v2 = err(msd::Integrator::VelocityVerlet, 1e-3);
  EXPECT_NEAR(v1 / v2, 4.0, 0.6);
}

TEST(Step, ExplicitEulerGainsEnergySymplecticDoesNot) {
  const msd::Model m = oscillator(100.0, 6.0);
  // Over many periods explicit Euler's amplitude grows; symplectic Euler's stays.
  const double a_exp = std::abs(run(m, msd::Integrator::ExplicitEuler, 2e-3, 5.0, 1e-3));
  double peak = 0.0;
  msd::State s = msd::rest_state(m);
  s.x(2, 3) = 1.001;
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  for (int i = 0; i < 2500; ++i) {
    msd::step(m, s, c, 2e-3, msd::Integrator::SymplecticEuler, scratch);
    peak = std::max(peak, std::abs(s.x(2, 3) - 1.0));
  }
  EXPECT_LT(peak, 1.1e-3);
  msd::State e = msd::rest_state(m);
  e.x(2, 3) = 1.001;
  double peak_e = 0.0;
  for (int i = 0; i < 2500; ++i) {
    msd::step(m, e, c, 2e-3, msd::Integrator::ExplicitEuler, scratch);
    peak_e = std::max(peak_e, std::abs(e.x(2, 3) - 1.0));
  }
  EXPECT_GT(peak_e, 1.5e-3);
  (void)a_exp;
}

TEST(Step, ConstraintsHoldPrescribedMotion) {
  const msd::Model m = oscillator(100.0, 6.0);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  msd::Controls c{{Vec3(0.1, 0, 0)}, {Vec3(1, 0, 0)}};
  msd::step(m, s, c, 1e-3, msd::Integrator::SymplecticEuler, scratch);
  for (int n : {0, 1, 2}) {
    EXPECT_DOUBLE_EQ(s.x(0, n), m.rest_positions(0, n) + 0.1);
    EXPECT_DOUBLE_EQ(s.v(0, n), 1.0);
  }
  EXPECT_EQ(s.step, 1);
  EXPECT_DOUBLE_EQ(s.t, 1e-3);
}

TEST(Step, GravityAcceleratesFreeNodes) {
  msd::Model m = oscillator(1e-9, 6.0);
  m.terms |= msd::kGravity;
  m.gravity = Vec3(0, 0, -9.81);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  for (int i = 0; i < 100; ++i) msd::step(m, s, c, 1e-3, msd::Integrator::VelocityVerlet, scratch);
  EXPECT_NEAR(s.v(2, 3), -9.81 * 0.1, 1e-6);
  EXPECT_NEAR(s.x(2, 3) - 1.0, -0.5 * 9.81 * 0.01, 1e-6);
}

TEST(Step, NonFiniteValueStopsWithTimeStepAndElement) {
  const msd::Model m = oscillator(100.0, 6.0);
  msd::State s = msd::rest_state(m);
  s.x.col(3) = s.x.col(0);  // zero-length edge: 0/0 in the spring direction
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  try {
    msd::step(m, s, c, 1e-3, msd::Integrator::SymplecticEuler, scratch);
    FAIL() << "expected a SimulationFailure";
  } catch (const msd::SimulationFailure& f) {
    EXPECT_EQ(f.element, 0);
    EXPECT_EQ(f.step, 0);
    EXPECT_NE(std::string(f.what()).find("non-finite"), std::string::npos) << f.what();
    EXPECT_NE(std::string(f.what()).find("t = "), std::string::npos) << f.what();
  }
}

TEST(Step, IntegratorNames) {
  for (auto i : {msd::Integrator::ExplicitEuler, msd::Integrator::SymplecticEuler, msd::Integrator::VelocityVerlet})
    EXPECT_EQ(msd::parse_integrator(msd::to_string(i)), i);
  EXPECT_EQ(msd::parse_integrator("semi_implicit_euler"), msd::Integrator::SymplecticEuler);
  EXPECT_THROW(msd::parse_integrator("rk4"), msd::Error);
}
