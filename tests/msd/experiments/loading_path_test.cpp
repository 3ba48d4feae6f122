#include "msd/experiments/loading_path.hpp"

#include <gtest/gtest.h>

TEST(LoadingPath, ThesisCycle) {
  const auto p = msd::LoadingPath::thesis_cycle();
  EXPECT_DOUBLE_EQ(p.end_time(), 12.0);
  EXPECT_DOUBLE_EQ(p.value(1.0), -0.25);
  EXPECT_DOUBLE_EQ(p.value(2.0), -0.5);
  EXPECT_DOUBLE_EQ(p.value(6.0), 0.5);
  EXPECT_DOUBLE_EQ(p.value(20.0), 0.0);
  EXPECT_DOUBLE_EQ(p.rate(1.0), -0.25);
  EXPECT_DOUBLE_EQ(p.rate(5.0), 0.25);
  EXPECT_DOUBLE_EQ(p.rate(13.0), 0.0);
  EXPECT_DOUBLE_EQ(p.min_value(), -0.5);
  EXPECT_DOUBLE_EQ(p.max_value(), 1.0);
}

TEST(LoadingPath, RejectsBadWayPoints) {
  EXPECT_THROW(msd::LoadingPath({{0, 0}}, "p"), msd::Error);
  EXPECT_THROW(msd::LoadingPath({{1, 0}, {2, 1}}, "p"), msd::Error);
  EXPECT_THROW(msd::LoadingPath({{0, 0}, {1, 1}, {1, 2}}, "p"), msd::Error);
  EXPECT_THROW(msd::LoadingPath({{0, 0}, {1, std::nan("")}}, "p"), msd::Error);
}
