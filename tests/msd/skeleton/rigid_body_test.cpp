// A bone's mass properties from its tets match a box's closed forms exactly;
// moments about other axes follow the parallel-axis theorem; the tissue's
// nodal forces reduce to a resultant and a torque.
#include "msd/skeleton/rigid_body.hpp"

#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

namespace {

// A 2 x 3 x 8 cm bone at h = 1 cm, its corner at (1, 2, 3) cm.
msd::TetMesh bone_box() {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  o.region = msd::kUpperBone;
  return msd::mesh_closed_surface(msd::make_box(msd::Vec3(0.01, 0.02, 0.03), msd::Vec3(0.03, 0.05, 0.11)), o, "bone")
      .mesh;
}

}  // namespace

TEST(RigidBody, ABoxOfTetsHasTheBoxsMassCentreAndInertia) {
  const msd::TetMesh m = bone_box();
  const auto p = msd::region_mass_properties(m, msd::kUpperBone, msd::kBoneDensity);
  const double a = 0.02, b = 0.03, c = 0.08, mass = msd::kBoneDensity * a * b * c;
  EXPECT_NEAR(p.mass, mass, 1e-12 * mass);
  EXPECT_LT((p.centre - msd::Vec3(0.02, 0.035, 0.07)).norm(), 1e-14);
  EXPECT_NEAR(p.inertia(0, 0), mass * (b * b + c * c) / 12, 1e-12 * mass * c * c);
  EXPECT_NEAR(p.inertia(1, 1), mass * (a * a + c * c) / 12, 1e-12 * mass * c * c);
  EXPECT_NEAR(p.inertia(2, 2), mass * (a * a + b * b) / 12, 1e-12 * mass * c * c);
  EXPECT_LT(p.inertia(0, 1) * p.inertia(0, 1) + p.inertia(0, 2) * p.inertia(0, 2) + p.inertia(1, 2) * p.inertia(1, 2),
            1e-24 * mass * mass * c * c * c * c);
  // About a hinge through one end of the bone, across it (a knee axis along x).
  const double end = msd::moment_about_axis(p, msd::Vec3(0.02, 0.035, 0.03), msd::Vec3::UnitX());
  EXPECT_NEAR(end, mass * (b * b + c * c) / 12 + mass * (c / 2) * (c / 2), 1e-12 * mass * c * c);
  EXPECT_THROW(msd::region_mass_properties(m, msd::kLowerBone, msd::kBoneDensity), msd::Error);
  EXPECT_THROW(msd::region_mass_properties(m, msd::kUpperBone, 0.0), msd::Error);
}

TEST(RigidBody, NodalForcesReduceToAResultantAndATorque) {
  msd::Points x(3, 3);
  x << 0, 1, 0,  //
      0, 0, 1,   //
      0, 0, 0;
  msd::Points f = msd::Points::Zero(3, 3);
  f.col(1) = msd::Vec3(0, 2, 0);   // at (1, 0, 0), along +y
  f.col(2) = msd::Vec3(-2, 0, 0);  // at (0, 1, 0), along -x: a couple with the first plus a net force
  const auto [force, torque] = msd::force_and_torque(x, f, {1, 2}, msd::Vec3::Zero());
  EXPECT_LT((force - msd::Vec3(-2, 2, 0)).norm(), 1e-15);
  EXPECT_LT((torque - msd::Vec3(0, 0, 4)).norm(), 1e-15);
  // Node 0 is not on the bone: its force does not count.
  f.col(0) = msd::Vec3(5, 5, 5);
  EXPECT_LT((msd::force_and_torque(x, f, {1, 2}, msd::Vec3::Zero()).first - force).norm(), 1e-15);
}
