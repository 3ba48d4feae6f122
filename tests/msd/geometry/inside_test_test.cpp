#include "msd/geometry/inside_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using msd::InsideTest;
using msd::TriangleMesh;
using msd::Vec3;

namespace {

// Reference: generalised winding number by solid angles (Van Oosterom &
// Strackee 1983); robust for points off the surface.
double winding_number(const TriangleMesh& m, const Vec3& p) {
  double w = 0.0;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.vertices.col(t[0]) - p, b = m.vertices.col(t[1]) - p, c = m.vertices.col(t[2]) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    w += 2.0 * std::atan2(num, den);
  }
  return w / (4.0 * M_PI);
}

}  // namespace

TEST(InsideTest, AgreesWithWindingNumberOnRandomPoints) {
  const TriangleMesh c = msd::make_cylinder(0.05, 0.15, 24);
  const InsideTest test(c);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-0.07, 0.07), uz(-0.02, 0.17);
  int inside = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3 p(ux(rng), ux(rng), uz(rng));
    const bool ref = winding_number(c, p) > 0.5;
    EXPECT_EQ(test.inside(p), ref) << p.transpose();
    inside += ref;
  }
  EXPECT_GT(inside, 500);
}

TEST(InsideTest, RaysThroughVerticesAndEdgesCountOnce) {
  // The box's faces are split along diagonals and its vertices sit on integer
  // coordinates: rays along +x through y, z in {0, 0.5, 1} hit edges, diagonals
  // and vertices of the triangulation exactly.
  const TriangleMesh box = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const InsideTest test(box);
  for (double y : {0.25, 0.5, 0.75})
    for (double z : {0.25, 0.5, 0.75}) {
      EXPECT_TRUE(test.inside(Vec3(0.5, y, z))) << y << " " << z;
      EXPECT_FALSE(test.inside(Vec3(1.5, y, z)));
      EXPECT_FALSE(test.inside(Vec3(-0.5, y, z)));
      EXPECT_EQ(test.crossings(y, z).size(), 2u);
    }
  // Rays grazing the box along an edge or a face: an even number of crossings,
  // so points beyond the box and before it are both outside.
  for (double y : {0.0, 1.0})
    for (double z : {0.0, 0.5, 1.0}) {
      EXPECT_EQ(test.crossings(y, z).size() % 2, 0u) << y << " " << z;
      EXPECT_FALSE(test.inside(Vec3(-0.5, y, z)));
    }
  // A line through the diagonal's mid-point of the x = 1 face.
  const auto cross = test.crossings(0.5, 0.5);
  ASSERT_EQ(cross.size(), 2u);
  EXPECT_DOUBLE_EQ(cross[0], 0.0);
  EXPECT_DOUBLE_EQ(cross[1], 1.0);
}

TEST(InsideTest, SurfacePointsAreInsideWithTolerance) {
  const TriangleMesh box = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const InsideTest test(box);
  EXPECT_TRUE(test.inside(Vec3(1.0, 0.3, 0.3), 1e-9));
  EXPECT_TRUE(test.inside(Vec3(0.3, 0.3, 1.0), 1e-9));
  EXPECT_TRUE(test.inside(Vec3(1.0, 1.0, 1.0), 1e-9));
  EXPECT_FALSE(test.inside(Vec3(1.0 + 1e-6, 0.3, 0.3), 1e-9));
}

TEST(InsideTest, InsideOnLineMatchesSinglePointQueries) {
  const TriangleMesh c = msd::make_cylinder(0.05, 0.15, 32);
  const InsideTest test(c);
  std::vector<double> xs;
  for (int i = -8; i <= 8; ++i) xs.push_back(0.0073 * i);
  for (double y : {-0.04, 0.0, 0.0213})
    for (double z : {0.01, 0.075}) {
      const auto line = test.inside_on_line(y, z, xs);
      for (size_t i = 0; i < xs.size(); ++i) EXPECT_EQ(bool(line[i]), test.inside(Vec3(xs[i], y, z)));
    }
}

TEST(InsideTest, ClosestPointAndDistance) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(msd::closest_point_on_triangle(Vec3(0.2, 0.2, 3), a, b, c).isApprox(Vec3(0.2, 0.2, 0)));
  EXPECT_TRUE(msd::closest_point_on_triangle(Vec3(-1, -1, 0), a, b, c).isApprox(a));
  EXPECT_TRUE(msd::closest_point_on_triangle(Vec3(1, 1, 0), a, b, c).isApprox(Vec3(0.5, 0.5, 0)));
  const InsideTest test(msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1)));
  EXPECT_NEAR(test.distance(Vec3(0.5, 0.5, 1.25), 10.0), 0.25, 1e-14);
}

TEST(InsideTest, TriangleBoxOverlap) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  EXPECT_TRUE(msd::triangle_box_overlap(lo, hi, Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 2), Vec3(2, 0.5, 0.5)));
  EXPECT_FALSE(msd::triangle_box_overlap(lo, hi, Vec3(2, 2, 2), Vec3(3, 2, 2), Vec3(2, 3, 2)));
  // Separated only by the triangle's plane.
  EXPECT_FALSE(msd::triangle_box_overlap(lo, hi, Vec3(3, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3.1)));
  EXPECT_TRUE(msd::triangle_box_overlap(lo, hi, Vec3(2.9, 0, 0), Vec3(0, 2.9, 0), Vec3(0, 0, 2.9)));
  // A sliver crossing the box's interior with all its vertices outside.
  EXPECT_TRUE(msd::triangle_box_overlap(lo, hi, Vec3(-0.5, 1.6, 0.5), Vec3(1.6, -0.5, 0.5), Vec3(1.6, -0.5, 0.6)));
  // Touching the box only at its surface (closed box): overlap.
  EXPECT_TRUE(msd::triangle_box_overlap(lo, hi, Vec3(1, 0.2, 0.2), Vec3(2, 0.2, 0.2), Vec3(2, 0.8, 0.2)));
}
