// Rig helpers shared by the virtual material tests.
#include "msd/experiments/rig.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

TEST(Rig, ElementVolumesSumsSignedVolumesAndCountsInversions) {
  const msd::Model model = testing_support::corner_tet_model();
  msd::ElementVolumes v = msd::element_volumes(model, model.rest_positions);
  EXPECT_NEAR(v.volume, 0.1 * 0.1 * 0.1 / 6.0, 1e-15);
  EXPECT_EQ(v.inverted, 0);
  msd::Points x = model.rest_positions;
  x(2, 3) = -0.1;  // the apex pushed through its opposite face
  v = msd::element_volumes(model, x);
  EXPECT_NEAR(v.volume, -0.1 * 0.1 * 0.1 / 6.0, 1e-15);
  EXPECT_EQ(v.inverted, 1);
  x(2, 3) = 0.0;  // flat counts as inverted
  EXPECT_EQ(msd::element_volumes(model, x).inverted, 1);
}

TEST(Rig, BulkSampleAndAppliedForceAddTheDeadLoadsAtTheirScale) {
  msd::ModelOptions opt;
  opt.terms = msd::kSprings | msd::kGravity;
  opt.gravity = msd::Vec3(0, 0, -10);
  opt.external_force = msd::Points::Zero(3, 4);
  opt.external_force(0, 2) = 3.0;
  const msd::Model model = testing_support::corner_tet_model(opt);
  msd::State s = msd::rest_state(model);
  s.v(1, 3) = 2.0;
  s.x(2, 3) = 0.2;  // apex lifted: the volume doubles, the spring pulls it back
  msd::Scratch scratch;
  msd::evaluate_forces(model, s, scratch);
  const double v0 = 0.1 * 0.1 * 0.1 / 6.0;
  const msd::BulkSample b = msd::measure_bulk(model, s, v0);
  EXPECT_NEAR(b.volume_ratio, 2.0, 1e-12);
  EXPECT_EQ(b.inverted_elements, 0);
  EXPECT_NEAR(b.kinetic_energy, 0.5 * model.mass[3] * 4.0, 1e-15);
  const msd::Vec3 f = msd::applied_force(model, scratch, 0.5, 2);
  const msd::Vec3 expected = scratch.f.col(2) + msd::Vec3(1.5, 0, -5.0 * model.mass[2]);
  EXPECT_NEAR((f - expected).norm(), 0.0, 1e-15);
}
