// The blow-up detector (msd/experiments/blowup.hpp): its reference speed from
// closed forms, and each limit tripped with its measured value in the message,
// while states inside the limits pass.
#include "msd/experiments/blowup.hpp"

#include "msd/experiments/rig.hpp"
#include "msd/integrate/step.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

std::string failure_of(const msd::BlowUpLimits& l, const msd::Model& m, const msd::State& s) {
  try {
    l.check(m, s);
  } catch (const msd::SimulationFailure& f) {
    return f.what();
  }
  return "";
}

}  // namespace

TEST(BlowUp, TheWaveSpeedIsTheLongestSpringChainsClosedForm) {
  const msd::Model model = testing_support::corner_tet_model();
  // Lumped masses: a quarter of rho V each; the longest edge is a face
  // diagonal, sqrt(2) h: c = sqrt(2) h sqrt(k / m).
  const double m = 1000.0 * (0.1 * 0.1 * 0.1 / 6.0) / 4.0;
  ASSERT_NEAR(model.mass[0], m, 1e-15);
  EXPECT_NEAR(msd::lattice_wave_speed(model), std::sqrt(2.0) * 0.1 * std::sqrt(1.0 / m), 1e-12);
  // Reference speed: c + loading + free fall across the sample.
  msd::ModelOptions g;
  g.terms = msd::kSprings | msd::kGravity;
  g.gravity = msd::Vec3(0, 0, -9.81);
  msd::BlowUpLimits l(testing_support::corner_tet_model(g), 0.1, 10.0);
  EXPECT_NEAR(l.free_fall_speed, std::sqrt(2 * 9.81 * 0.1), 1e-12);
  EXPECT_DOUBLE_EQ(l.max_displacement, 1.0);
  l.see_load_speed(3.0);
  l.see_load_speed(1.0);  // the fastest seen so far stays
  EXPECT_NEAR(l.reference_speed(), l.wave_speed + 3.0 + l.free_fall_speed, 1e-12);
}

TEST(BlowUp, ADisplacementPastTheLimitNamesTheNodeAndTheDistance) {
  const msd::Model model = testing_support::corner_tet_model();
  const msd::BlowUpLimits l(model, 0.1, 10.0);  // 1 m
  msd::State s = msd::rest_state(model);
  EXPECT_EQ(failure_of(l, model, s), "");
  s.x(2, 3) += 0.95;
  EXPECT_EQ(failure_of(l, model, s), "");
  s.x(2, 3) += 1.0;  // 1.95 m from rest
  const std::string w = failure_of(l, model, s);
  EXPECT_NE(w.find("blow-up: node 3 moved 1.95 m from rest, more than the limit 1 m (1.95 times the limit)"),
            std::string::npos) << w;
}

TEST(BlowUp, ABodyCarriedFarByAScriptedBoneIsMeasuredFromWhereItWasCarried) {
  // A scripted hip may carry the whole leg far from its rest place: that is
  // no blow-up; a node 1.95 m from its carried place is.
  const msd::Model model = testing_support::corner_tet_model();
  const msd::BlowUpLimits l(model, 0.1, 10.0);  // 1 m
  msd::RigidMotion carried;
  carried.rotation = Eigen::AngleAxisd(1.0, msd::Vec3(1, 2, 3).normalized()).toRotationMatrix();
  carried.offset = msd::Vec3(40.0, -3.0, 7.0);
  msd::State s = msd::rest_state(model);
  for (int i = 0; i < 4; ++i) s.x.col(i) = carried.place(model.rest_positions.col(i));
  s.x(2, 3) += 0.95;
  EXPECT_NE(failure_of(l, model, s), "");  // from rest: 40 m
  EXPECT_NO_THROW(l.check(model, s, &carried));
  s.x(2, 3) += 1.0;
  try {
    l.check(model, s, &carried);
    FAIL() << "1.95 m from its carried place passed";
  } catch (const msd::SimulationFailure& f) {
    EXPECT_NE(std::string(f.what()).find("node 3 moved 1.95 m from its carried rest place"), std::string::npos) << f.what();
  }
}

TEST(BlowUp, ANodeFasterThanTenReferenceSpeedsOrTooMuchKineticEnergyIsABlowUp) {
  const msd::Model model = testing_support::corner_tet_model();
  const msd::BlowUpLimits l(model, 0.1, 10.0);
  const double v_ref = l.reference_speed();
  ASSERT_GT(v_ref, 0.0);
  msd::State s = msd::rest_state(model);
  // Every node at 0.9 v_ref: inside the energy limit (the body at v_ref).
  s.v.setZero();
  s.v.row(0).setConstant(0.9 * v_ref);
  EXPECT_EQ(failure_of(l, model, s), "");
  // Every node at 1.1 v_ref: 1.21 times the energy limit.
  s.v.row(0).setConstant(1.1 * v_ref);
  std::string w = failure_of(l, model, s);
  EXPECT_NE(w.find("blow-up: kinetic energy"), std::string::npos) << w;
  EXPECT_NE(w.find("more than the whole body"), std::string::npos) << w;
  // One node at 11 v_ref: the speed limit names it and its speed.
  s.v.setZero();
  s.v(1, 2) = 11.0 * v_ref;
  w = failure_of(l, model, s);
  EXPECT_NE(w.find("blow-up: node 2 moves at"), std::string::npos) << w;
  EXPECT_NE(w.find("more than ten times the scene's reference speed"), std::string::npos) << w;
}

TEST(BlowUp, ATimeStepOfAThousandSecondsFailsTheRunInsteadOfCompletingIt) {
  // The run the issue found marked complete: dt = 1000 s, one step. The rig
  // itself (without the spec's dt check) must now fail it.
  msd::ModelOptions opt;
  opt.terms = msd::kSprings | msd::kGravity;
  opt.gravity = msd::Vec3(0, 0, -9.81);
  const msd::Model model = testing_support::corner_tet_model(opt);
  msd::TimeSteppingOptions t;
  t.dt = 1000.0;
  t.output_interval = 1000.0;
  msd::ExperimentHooks hooks;
  hooks.controls = [&](double) { return msd::Controls{}; };
  hooks.sample = [](const msd::State&, msd::Scratch&) { return true; };
  try {
    msd::run_experiment(model, msd::rest_state(model), 1000.0, 0.1, t, hooks);
    FAIL() << "a 1000 s step under gravity completed";
  } catch (const msd::SimulationFailure& f) {
    EXPECT_NE(std::string(f.what()).find("blow-up"), std::string::npos) << f.what();
    EXPECT_DOUBLE_EQ(f.time, 1000.0);
  }
}
