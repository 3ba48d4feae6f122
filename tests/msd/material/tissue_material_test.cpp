#include "msd/material/tissue_material.hpp"

#include <gtest/gtest.h>

TEST(TissueMaterial, RawConstantsAreUsedAsGiven) {
  msd::TissueMaterial m;
  m.density = 920;
  m.k_s = 10.75;
  m.k_d = 0.2;
  m.k_r = 3;
  m.k_v = 50;
  const double L[6] = {1, 1, 1, 1, 1, 1}, h[4] = {1, 1, 1, 1};
  const auto c = msd::element_constants(m, 1.0, L, h);
  for (int e = 0; e < 6; ++e) {
    EXPECT_EQ(c.k_s[e], 10.75);
    EXPECT_EQ(c.k_d[e], 0.2);
  }
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(c.k_r[i], 3);
    EXPECT_EQ(c.k_v[i], 50);
  }
}

TEST(TissueMaterial, PhysicalConstantsFollowTheVanGelderForm) {
  msd::TissueMaterial m;
  m.mode = msd::ConstantsMode::Physical;
  m.density = 1000;
  m.youngs_modulus = 6000;
  m.damping_time = 0.01;
  m.stiffness_scale = 2.0;
  m.repulsion_factor = 0.5;
  m.volume_factor = 3.0;
  const double V = 1e-6, L[6] = {0.01, 0.02, 0.01, 0.01, 0.01, 0.01}, h[4] = {0.005, 0.01, 0.01, 0.01};
  const auto c = msd::element_constants(m, V, L, h);
  const double ev = 5.0 / 6.0 * 2.0 * 6000 * V;
  EXPECT_DOUBLE_EQ(c.k_s[0], ev / 1e-4);
  EXPECT_DOUBLE_EQ(c.k_s[1], ev / 4e-4);
  EXPECT_DOUBLE_EQ(c.k_d[1], 0.01 * c.k_s[1]);
  EXPECT_DOUBLE_EQ(c.k_r[0], 0.5 * ev / 2.5e-5);
  EXPECT_DOUBLE_EQ(c.k_v[3], 3.0 * ev / 1e-4);
}

TEST(TissueMaterial, UnphysicalValuesAreRejectedWithTheFieldName) {
  auto message = [](const msd::TissueMaterial& m) {
    try {
      msd::check_material(m, "mat");
    } catch (const msd::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  msd::TissueMaterial m;
  m.density = 920;
  m.k_s = 1;
  EXPECT_EQ(message(m), "");
  m.density = 0;
  EXPECT_NE(message(m).find("density"), std::string::npos);
  m.density = 920;
  m.k_d = -1;
  EXPECT_NE(message(m).find("k_d"), std::string::npos);
  m.k_d = 0;
  m.repulsion_floor = 1.5;
  EXPECT_NE(message(m).find("repulsion_floor"), std::string::npos);
  m.repulsion_floor = 0.01;
  m.mode = msd::ConstantsMode::Physical;
  EXPECT_NE(message(m).find("youngs_modulus"), std::string::npos);
  m.youngs_modulus = 1e3;
  m.volume_factor = std::nan("");
  EXPECT_NE(message(m).find("volume_factor"), std::string::npos);
}
