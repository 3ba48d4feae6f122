// Rig helpers shared by the virtual material tests.
#include "msd/experiments/rig.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

TEST(Rig, ElementVolumesSumsSignedVolumesAndCountsInversions) {
  const msd::TetMesh mesh = testing_support::corner_tet_mesh(0.1);
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 1.0;
  msd::ModelOptions opt;
  opt.region_materials = {mat};
  const msd::Model model = msd::build_model(mesh, opt);
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
