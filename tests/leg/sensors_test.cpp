// What the viewer draws of an obstacle (leg::obstacle_surface): a cylinder's
// piece lies on its radius about its axis, centred on its point; a plane's
// square lies on the plane about its point.
#include "leg/sensors.hpp"

#include <gtest/gtest.h>

namespace {

TEST(ObstacleSurface, CylinderPieceLiesOnItsRadiusCentredOnItsAxisPoint) {
  msd::RigidObstacle ob;
  ob.shape = msd::ObstacleShape::Cylinder;
  ob.cylinder.point = msd::Vec3(0.1, -0.2, 0.5);
  ob.cylinder.axis = msd::Vec3(1.0, 1.0, 0.0).normalized();
  ob.cylinder.radius = 0.04;
  const msd::TriangleMesh m = leg::obstacle_surface(ob, 0.4);
  ASSERT_GT(m.num_triangles(), 16);
  double lo = 1e9, hi = -1e9;
  int on_side = 0;
  for (int i = 0; i < m.num_vertices(); ++i) {
    const msd::Vec3 d = m.vertices.col(i) - ob.cylinder.point;
    const double along = d.dot(ob.cylinder.axis);
    const double r = (d - along * ob.cylinder.axis).norm();
    lo = std::min(lo, along);
    hi = std::max(hi, along);
    EXPECT_LE(r, 0.04 + 1e-12);
    on_side += std::abs(r - 0.04) < 1e-12;
  }
  EXPECT_NEAR(lo, -0.2, 1e-12);
  EXPECT_NEAR(hi, 0.2, 1e-12);
  EXPECT_EQ(on_side, 32);  // the two 16-gons; the caps' centres lie on the axis
}

TEST(ObstacleSurface, PlaneSquareLiesOnThePlaneAboutItsPoint) {
  msd::RigidObstacle ob;
  ob.shape = msd::ObstacleShape::Plane;
  ob.plane.point = msd::Vec3(0.0, 0.0, 0.1);
  ob.plane.normal = msd::Vec3(0.0, 0.0, 1.0);
  const msd::TriangleMesh m = leg::obstacle_surface(ob, 0.4);
  for (int i = 0; i < m.num_vertices(); ++i) {
    const msd::Vec3 d = m.vertices.col(i) - ob.plane.point;
    EXPECT_LE(d.z(), 1e-12);   // on or just below the plane (a 2 mm slab under it)
    EXPECT_GE(d.z(), -0.002 - 1e-12);
    EXPECT_NEAR(std::max(std::abs(d.x()), std::abs(d.y())), 0.2, 1e-12);
  }
}

}  // namespace
