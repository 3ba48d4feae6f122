// The rigid-cylinder contact kernel: gap and normal, the thesis' projection
// with both velocity responses, input checks, and the model/step wiring.
#include "msd/contact/rigid_obstacle.hpp"

#include "msd/integrate/step.hpp"
#include "msd/model/model.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

namespace {

msd::RigidCylinder rod() {
  msd::RigidCylinder c;
  c.point = Vec3(0.0, 0.0, 1.0);
  c.axis = Vec3::UnitY();
  c.radius = 0.5;
  return c;
}

}  // namespace

TEST(RigidCylinder, GapAndNormalAreRadialFromTheAxis) {
  const msd::RigidCylinder c = rod();
  // Below the axis, 0.2 inside, anywhere along the axis.
  msd::CylinderGap g = msd::cylinder_gap(c, Vec3::Zero(), Vec3(0.0, 7.0, 0.7));
  EXPECT_NEAR(g.depth, 0.2, 1e-15);
  EXPECT_NEAR((g.normal - Vec3(0, 0, -1)).norm(), 0.0, 1e-15);
  // Outside, diagonally: depth = R - r < 0.
  g = msd::cylinder_gap(c, Vec3::Zero(), Vec3(1.0, -3.0, 2.0));
  EXPECT_NEAR(g.depth, 0.5 - std::sqrt(2.0), 1e-15);
  EXPECT_NEAR((g.normal - Vec3(1, 0, 1).normalized()).norm(), 0.0, 1e-15);
  // The offset moves the cylinder.
  g = msd::cylinder_gap(c, Vec3(0, 0, -0.4), Vec3(0.0, 0.0, 0.7));
  EXPECT_NEAR(g.depth, 0.5 - 0.1, 1e-15);
  EXPECT_NEAR(g.normal.z(), 1.0, 1e-15);
  // On the axis the normal is still a unit vector normal to the axis.
  g = msd::cylinder_gap(c, Vec3::Zero(), Vec3(0.0, 2.0, 1.0));
  EXPECT_NEAR(g.normal.norm(), 1.0, 1e-15);
  EXPECT_NEAR(g.normal.dot(c.axis), 0.0, 1e-15);
}

TEST(RigidCylinder, StickResponseProjectsToTheSurfaceAndTakesTheObjectsVelocity) {
  const msd::RigidCylinder c = rod();
  Vec3 x(0.1, 0.3, 0.6), v(1.0, 2.0, -3.0);
  const Vec3 object_velocity(0.0, 0.0, -0.25);
  ASSERT_TRUE(msd::resolve_cylinder_contact(c, msd::ContactResponse::Stick, Vec3::Zero(), object_velocity, x, v));
  EXPECT_NEAR(msd::cylinder_gap(c, Vec3::Zero(), x).depth, 0.0, 1e-15);
  // Moved along the radial direction only: same y, same direction from the axis.
  EXPECT_DOUBLE_EQ(x.y(), 0.3);
  EXPECT_NEAR((Vec3(x.x(), 0, x.z() - 1.0).normalized() - Vec3(0.1, 0, -0.4).normalized()).norm(), 0.0, 1e-15);
  EXPECT_EQ(v, object_velocity);
}

TEST(RigidCylinder, FrictionlessResponseRemovesOnlyTheInwardNormalVelocity) {
  const msd::RigidCylinder c = rod();
  // Directly below the axis: normal -z. Moving up (into the rod) and sideways.
  Vec3 x(0.0, 0.0, 0.6), v(0.3, -0.2, 1.5);
  ASSERT_TRUE(msd::resolve_cylinder_contact(c, msd::ContactResponse::Frictionless, Vec3::Zero(), Vec3::Zero(), x, v));
  EXPECT_NEAR(x.z(), 0.5, 1e-15);
  EXPECT_NEAR((v - Vec3(0.3, -0.2, 0.0)).norm(), 0.0, 1e-15);
  // Already moving away from the rod (relative to it): the velocity is kept.
  x = Vec3(0.0, 0.0, 0.6);
  v = Vec3(0.0, 0.0, -0.1);
  ASSERT_TRUE(msd::resolve_cylinder_contact(c, msd::ContactResponse::Frictionless, Vec3::Zero(), Vec3(0, 0, 0.5), x, v));
  EXPECT_EQ(v, Vec3(0.0, 0.0, -0.1));
}

TEST(RigidCylinder, PointsOutsideAreLeftAlone) {
  const msd::RigidCylinder c = rod();
  Vec3 x(0.0, 0.0, 0.4), v(1, 2, 3);
  EXPECT_FALSE(msd::resolve_cylinder_contact(c, msd::ContactResponse::Stick, Vec3::Zero(), Vec3::Zero(), x, v));
  EXPECT_EQ(x, Vec3(0.0, 0.0, 0.4));
  EXPECT_EQ(v, Vec3(1, 2, 3));
}

TEST(RigidCylinder, BadCylindersAndResponsesAreRefused) {
  msd::RigidCylinder c = rod();
  c.radius = 0.0;
  EXPECT_THROW(msd::check_cylinder(c, "here"), msd::Error);
  c = rod();
  c.axis = Vec3(0, 2, 0);
  try {
    msd::check_cylinder(c, "obstacle 'rod'");
    FAIL() << "a non-unit axis was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("obstacle 'rod'"), std::string::npos);
  }
  EXPECT_THROW(msd::parse_contact_response("sticky"), msd::Error);
  EXPECT_EQ(msd::parse_contact_response("thesis"), msd::ContactResponse::Stick);
}

TEST(RigidCylinder, ModelTestsSurfaceNodesOutsideKinematicGroupsAndStepKeepsThemOut) {
  // One tet with its base (nodes 0-2) in a group; the rod comes down on the apex.
  const msd::TetMesh mesh = testing_support::corner_tet_mesh(0.1);
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 50.0;
  msd::ModelOptions opt;
  opt.region_materials = {mat};
  msd::KinematicGroup base{"base", {0, 1, 2}, {true, true, true}};
  opt.groups = {base};
  msd::RigidObstacle ob;
  ob.name = "rod";
  ob.cylinder.axis = Vec3::UnitY();
  ob.cylinder.radius = 0.05;
  ob.cylinder.point = Vec3(0.0, 0.0, 0.1 + 0.05);  // touching the apex (0, 0, 0.1)
  opt.obstacles = {ob};
  const msd::Model model = msd::build_model(mesh, opt);
  ASSERT_EQ(model.obstacles.size(), 1u);
  EXPECT_EQ(model.obstacles[0].nodes, std::vector<int>{3});
  msd::State s = msd::rest_state(model);
  msd::Scratch scratch;
  msd::Controls c;
  c.group_offset = {Vec3::Zero()};
  c.group_velocity = {Vec3::Zero()};
  for (int k = 1; k <= 100; ++k) {
    c.obstacle_offset = {Vec3(0, 0, -0.02 * k / 100.0)};
    c.obstacle_velocity = {Vec3(0, 0, -0.02)};
    msd::step(model, s, c, 1e-3, msd::Integrator::SymplecticEuler, scratch);
    EXPECT_LE(msd::cylinder_gap(model.obstacles[0].cylinder, c.obstacle_offset[0], s.x.col(3)).depth, 1e-15);
  }
  // Pushed down with the rod and resting on it: on its surface, near its
  // lowest line (the apex drifts sideways a little under the spring forces).
  EXPECT_NEAR(msd::cylinder_gap(model.obstacles[0].cylinder, c.obstacle_offset[0], s.x.col(3)).depth, 0.0, 1e-12);
  EXPECT_NEAR(s.x(2, 3), 0.08, 1e-5);
  // A bad node index is refused, naming the obstacle.
  opt.obstacles[0].nodes = {9};
  EXPECT_THROW(msd::build_model(mesh, opt), msd::Error);
}

TEST(RigidPlane, NodesBelowATableAreLiftedOntoItWithTheResponsesVelocity) {
  // A table top at z = 0.8 m (moving up at 0.1 m/s, offset 5 mm so far).
  const msd::RigidPlane table{msd::Vec3(0, 0, 0.8), msd::Vec3::UnitZ()};
  const msd::Vec3 offset(0, 0, 0.005), table_velocity(0, 0, 0.1);
  const msd::ContactGap g = msd::plane_gap(table, offset, msd::Vec3(0.3, -0.2, 0.79));
  EXPECT_NEAR(g.depth, 0.015, 1e-15);
  EXPECT_EQ(g.normal, msd::Vec3::UnitZ());
  // Stick: onto the surface with the table's velocity.
  msd::Vec3 x(0.3, -0.2, 0.79), v(0.5, 0.0, -1.0);
  EXPECT_TRUE(msd::resolve_plane_contact(table, msd::ContactResponse::Stick, offset, table_velocity, x, v));
  EXPECT_LT((x - msd::Vec3(0.3, -0.2, 0.805)).norm(), 1e-15);
  EXPECT_EQ(v, table_velocity);
  // Frictionless: keeps its sliding velocity, loses only the approach.
  x = msd::Vec3(0.3, -0.2, 0.79);
  v = msd::Vec3(0.5, 0.0, -1.0);
  EXPECT_TRUE(msd::resolve_plane_contact(table, msd::ContactResponse::Frictionless, offset, table_velocity, x, v));
  EXPECT_LT((v - msd::Vec3(0.5, 0.0, 0.1)).norm(), 1e-15);
  // Above the table: untouched.
  x = msd::Vec3(0, 0, 0.9);
  v = msd::Vec3(0, 0, -1);
  EXPECT_FALSE(msd::resolve_plane_contact(table, msd::ContactResponse::Stick, offset, table_velocity, x, v));
  EXPECT_EQ(x, msd::Vec3(0, 0, 0.9));
  EXPECT_NO_THROW(msd::check_plane(table, "table"));
  EXPECT_THROW(msd::check_plane({msd::Vec3::Zero(), msd::Vec3(0, 0, 2)}, "table"), msd::Error);
}

TEST(RigidPlane, AModelsPlaneObstacleKeepsItsNodesAboveAndIsCheckedByShape) {
  // The same tet as the rod test, its base held; a ceiling (solid above its
  // plane, normal -z) comes down on the apex.
  const msd::TetMesh mesh = testing_support::corner_tet_mesh(0.1);
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 50.0;
  msd::ModelOptions opt;
  opt.region_materials = {mat};
  opt.groups = {msd::KinematicGroup{"base", {0, 1, 2}, {true, true, true}}};
  msd::RigidObstacle ceiling;
  ceiling.name = "ceiling";
  ceiling.shape = msd::ObstacleShape::Plane;
  ceiling.plane = {Vec3(0, 0, 0.1), -Vec3::UnitZ()};  // solid above z = 0.1
  opt.obstacles = {ceiling};
  const msd::Model model = msd::build_model(mesh, opt);
  ASSERT_EQ(model.obstacles[0].nodes, std::vector<int>{3});
  msd::State s = msd::rest_state(model);
  msd::Scratch scratch;
  msd::Controls c;
  c.group_offset = {Vec3::Zero()};
  c.group_velocity = {Vec3::Zero()};
  for (int k = 1; k <= 100; ++k) {
    c.obstacle_offset = {Vec3(0, 0, -0.03 * k / 100.0)};
    c.obstacle_velocity = {Vec3(0, 0, -0.03)};
    msd::step(model, s, c, 1e-3, msd::Integrator::SymplecticEuler, scratch);
    EXPECT_LE(msd::obstacle_gap(model.obstacles[0], c.obstacle_offset[0], s.x.col(3)).depth, 1e-15);
  }
  EXPECT_NEAR(s.x(2, 3), 0.07, 1e-12);  // pressed down 3 cm with the plane (stick: no sliding)
  // The plane's own check runs for a plane obstacle: a non-unit normal is refused.
  opt.obstacles[0].plane.normal = Vec3(0, 0, -2);
  EXPECT_THROW(msd::build_model(mesh, opt), msd::Error);
}
