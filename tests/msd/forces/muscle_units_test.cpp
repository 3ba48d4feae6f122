// Contractile units (thesis 5.2.7): the units are the muscle edges along the
// line of action; their forces are equal and opposite (no net force or
// torque); a section of a box muscle carries activation * sigma_max * area.
#include "msd/forces/muscle_units.hpp"

#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

#include <random>

namespace {

// A 4 x 4 x 8 cm box of muscle at h = 1 cm, its long axis along z.
msd::TetMesh muscle_box() {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  o.region = msd::kBackMuscle;
  return msd::mesh_closed_surface(msd::make_box(msd::Vec3::Zero(), msd::Vec3(0.04, 0.04, 0.08)), o, "muscle").mesh;
}

}  // namespace

TEST(MuscleUnits, UnitsAreTheEdgesAlongTheLineOfAction) {
  const msd::TetMesh m = muscle_box();
  const auto along = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  ASSERT_FALSE(along.empty());
  for (const auto& u : along) {
    const msd::Vec3 l = m.nodes.col(u.b) - m.nodes.col(u.a);
    EXPECT_NEAR(std::abs(l.z()), l.norm(), 1e-12);  // axis-aligned z edges only
  }
  // Face diagonals (45 degrees) join within a 50 degree tolerance.
  EXPECT_GT(msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 50.0).size(), along.size());
  EXPECT_TRUE(msd::contractile_units(m, msd::kFrontMuscle, msd::Vec3::UnitZ(), 10.0).empty());
  EXPECT_THROW(msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::Zero(), 10.0), msd::Error);
  EXPECT_THROW(msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 95.0), msd::Error);
}

TEST(MuscleUnits, ASectionCarriesActivationTimesMaxStressTimesArea) {
  const msd::TetMesh m = muscle_box();
  const auto units = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  const double a = 0.6, sigma = 3.0e5, area = 0.04 * 0.04;
  const double f = msd::unit_force(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), a, sigma);
  // The units crossing the plane z = 4.5 cm.
  int crossing = 0;
  for (const auto& u : units) {
    const double za = m.nodes(2, u.a), zb = m.nodes(2, u.b);
    crossing += (std::min(za, zb) < 0.045 && std::max(za, zb) > 0.045) ? 1 : 0;
  }
  EXPECT_NEAR(crossing * f, a * sigma * area, 1e-9 * a * sigma * area);
  EXPECT_EQ(msd::unit_force(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), 0.0, sigma), 0.0);
}

TEST(MuscleUnits, ForcesAreEqualAndOppositeWithNoNetForceOrTorque) {
  const msd::TetMesh m = muscle_box();
  const auto units = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.002, 0.002);
  msd::Points x = m.nodes;
  for (int i = 0; i < x.cols(); ++i) x.col(i) += msd::Vec3(u(rng), u(rng), u(rng));
  msd::Points f = msd::Points::Zero(3, x.cols());
  msd::add_muscle_forces(x, units, 2.5, f);
  EXPECT_LT(f.rowwise().sum().norm(), 1e-12);
  msd::Vec3 torque = msd::Vec3::Zero();
  for (int i = 0; i < x.cols(); ++i) torque += msd::Vec3(x.col(i)).cross(msd::Vec3(f.col(i)));
  EXPECT_LT(torque.norm(), 1e-12);
  // Contraction: the top face is pulled down, the bottom face up.
  double top = 0, bottom = 0;
  for (int i = 0; i < x.cols(); ++i) {
    if (m.nodes(2, i) > 0.08 - 1e-9) top += f(2, i);
    if (m.nodes(2, i) < 1e-9) bottom += f(2, i);
  }
  EXPECT_LT(top, 0.0);
  EXPECT_GT(bottom, 0.0);
}

TEST(MuscleUnits, ForceLengthFactorIsTheAscendingLimb) {
  // f_L = 1 at and above the rest (optimal) length, 1 - ((1 - l) / (1 - l0))^2
  // between, 0 at and below l0; l0 < 0 is the thesis' constant force.
  EXPECT_EQ(msd::force_length_factor(1.0, 0.5), 1.0);
  EXPECT_EQ(msd::force_length_factor(1.3, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(msd::force_length_factor(0.75, 0.5), 0.75);  // 1 - (0.25 / 0.5)^2
  EXPECT_DOUBLE_EQ(msd::force_length_factor(0.9, 0.6), 1.0 - 0.25 * 0.25);
  EXPECT_EQ(msd::force_length_factor(0.5, 0.5), 0.0);
  EXPECT_EQ(msd::force_length_factor(0.2, 0.5), 0.0);
  EXPECT_EQ(msd::force_length_factor(0.2, -1.0), 1.0);
  // Continuous at both ends of the limb.
  EXPECT_NEAR(msd::force_length_factor(1.0 - 1e-9, 0.5), 1.0, 1e-8);
  EXPECT_NEAR(msd::force_length_factor(0.5 + 1e-9, 0.5), 0.0, 1e-8);
}

TEST(MuscleUnits, WithForceLengthAShortenedUnitPullsLessAndAHalfLengthOneNotAtAll) {
  // One unit along z of rest length 1 cm; pulled with 2 N at full length.
  const std::vector<msd::ContractileUnit> units{{0, 1, 0.01}};
  const msd::ForceLength fl{true, 0.5};
  auto pull = [&](double length) {
    msd::Points x(3, 2);
    x.col(0) = msd::Vec3::Zero();
    x.col(1) = msd::Vec3(0, 0, length);
    msd::Points f = msd::Points::Zero(3, 2);
    msd::add_muscle_forces(x, units, 2.0, f, fl);
    EXPECT_NEAR((f.col(0) + f.col(1)).norm(), 0.0, 1e-15);  // still equal and opposite
    return f(2, 0);  // node 0 pulled towards node 1 (+z)
  };
  EXPECT_DOUBLE_EQ(pull(0.012), 2.0);
  EXPECT_DOUBLE_EQ(pull(0.01), 2.0);
  EXPECT_DOUBLE_EQ(pull(0.0075), 2.0 * 0.75);
  EXPECT_EQ(pull(0.004), 0.0);
  // Without it (the thesis) the pull does not depend on length.
  msd::Points x(3, 2);
  x.col(0) = msd::Vec3::Zero();
  x.col(1) = msd::Vec3(0, 0, 0.004);
  msd::Points f = msd::Points::Zero(3, 2);
  msd::add_muscle_forces(x, units, 2.0, f);
  EXPECT_DOUBLE_EQ(f(2, 0), 2.0);
  // A zero stretch outside [0, 1) is refused.
  EXPECT_THROW(msd::add_muscle_forces(x, units, 2.0, f, msd::ForceLength{true, 1.0}), msd::Error);
}
