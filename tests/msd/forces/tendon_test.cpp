// Tendon strands (thesis 5.3): forces are minus the energy's gradient, pull only
// when stretched, cancel along a straight strand at inner nodes, sum to zero.
#include "msd/forces/tendon.hpp"

#include <gtest/gtest.h>

#include <random>

namespace {

msd::Points random_strand(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  msd::Points x(3, n);
  for (int i = 0; i < n; ++i) x.col(i) = msd::Vec3(0.02 * i + u(rng), u(rng), u(rng));
  return x;
}

// Each force component is minus the central difference of the strand's
// energy (toe strain `toe`), to 1e-6 of the tension t.
void expect_minus_energy_gradient(const msd::Points& x, const std::vector<int>& nodes, double l0, double kt,
                                  double toe, const msd::Points& f, double t) {
  const double h = 1e-7;
  for (int i = 0; i < static_cast<int>(x.cols()); ++i)
    for (int a = 0; a < 3; ++a) {
      msd::Points xp = x, xm = x;
      xp(a, i) += h;
      xm(a, i) -= h;
      const double grad = (msd::tendon_energy(xp, nodes, l0, kt, toe) - msd::tendon_energy(xm, nodes, l0, kt, toe)) / (2 * h);
      EXPECT_NEAR(f(a, i), -grad, 1e-6 * t) << "toe " << toe << " node " << i << " axis " << a;
    }
}

}  // namespace

TEST(Tendon, ForcesAreMinusTheGradientOfTheEnergy) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 5; ++trial) {
    const msd::Points x = random_strand(rng, 6);
    const std::vector<int> nodes{0, 1, 2, 3, 4, 5};
    const double l0 = 0.8 * msd::strand_length(x, nodes), kt = 2500.0;
    msd::Points f = msd::Points::Zero(3, 6);
    const double t = msd::add_tendon_forces(x, nodes, l0, kt, f);
    EXPECT_NEAR(t, kt * (msd::strand_length(x, nodes) - l0), 1e-12);
    expect_minus_energy_gradient(x, nodes, l0, kt, 0.0, f, t);
    EXPECT_LT(f.rowwise().sum().norm(), 1e-12 * t);  // internal: no net force
  }
}

TEST(Tendon, ASlackStrandPushesNothing) {
  std::mt19937 rng(3);
  const msd::Points x = random_strand(rng, 4);
  const std::vector<int> nodes{0, 1, 2, 3};
  msd::Points f = msd::Points::Zero(3, 4);
  EXPECT_EQ(msd::add_tendon_forces(x, nodes, 1.01 * msd::strand_length(x, nodes), 1e4, f), 0.0);
  EXPECT_EQ(f.norm(), 0.0);
  EXPECT_EQ(msd::tendon_energy(x, nodes, 1.01 * msd::strand_length(x, nodes), 1e4), 0.0);
}

TEST(Tendon, InnerNodesOfAStraightStrandFeelNothingAndABendFeelsTheTransverseResultant) {
  msd::Points x(3, 3);
  x << 0, 0.05, 0.1,  //
      0, 0, 0,        //
      0, 0, 0;
  const std::vector<int> nodes{0, 1, 2};
  msd::Points f = msd::Points::Zero(3, 3);
  const double t = msd::add_tendon_forces(x, nodes, 0.09, 1000.0, f);
  EXPECT_NEAR(t, 10.0, 1e-12);
  EXPECT_LT(f.col(1).norm(), 1e-12);            // slides: no pull along the strand
  EXPECT_NEAR(f(0, 0), 10.0, 1e-12);             // the muscle end pulled towards the bone
  EXPECT_NEAR(f(0, 2), -10.0, 1e-12);
  // Bent over the middle node by 90 degrees: it is pushed into the bend, along
  // the bisector, with magnitude T sqrt(2).
  x.col(2) = msd::Vec3(0.05, 0.05, 0);
  f.setZero();
  const double tb = msd::add_tendon_forces(x, nodes, 0.09, 1000.0, f);
  EXPECT_NEAR(f.col(1).norm(), std::sqrt(2.0) * tb, 1e-9);
  EXPECT_NEAR(f(0, 1), -tb, 1e-9);
  EXPECT_NEAR(f(1, 1), tb, 1e-9);
}

TEST(Tendon, StiffnessIsModulusTimesAreaOverLength) {
  // The thesis' softened modulus (0.8 MPa) and one of the order of real tendon (1.2 GPa).
  EXPECT_NEAR(msd::tendon_stiffness(0.8e6, 1e-4, 0.1), 800.0, 1e-9);
  EXPECT_NEAR(msd::tendon_stiffness(1.2e9, 1e-4, 0.1), 1.2e6, 1e-3);
  EXPECT_THROW(msd::tendon_stiffness(0.0, 1e-4, 0.1), msd::Error);
  EXPECT_THROW(msd::tendon_stiffness(1e6, -1.0, 0.1), msd::Error);
  EXPECT_THROW(msd::tendon_stiffness(1e6, 1e-4, 0.0), msd::Error);
}

TEST(Tendon, EnergyAtLengthIsTheStrandsEnergyAndZeroWhenSlack) {
  msd::Points x(3, 3);
  x << 0, 0.3, 0.3, 0, 0, 0.4, 0, 0, 0;  // segments 0.3 and 0.4
  const std::vector<int> nodes{0, 1, 2};
  EXPECT_DOUBLE_EQ(msd::tendon_energy_at_length(0.7, 0.5, 100.0), 0.5 * 100.0 * 0.2 * 0.2);
  EXPECT_NEAR(msd::tendon_energy(x, nodes, 0.5, 100.0), msd::tendon_energy_at_length(0.7, 0.5, 100.0), 1e-13);
  EXPECT_EQ(msd::tendon_energy_at_length(0.7, 0.8, 100.0), 0.0);
}

TEST(TendonToe, TheTensionRisesQuadraticallyThenLinearlyAtTheModulusAndIsC1) {
  // E A / L0 for 1.2 GPa, 20 mm^2, 10 cm; toe to 3 % strain.
  const double l0 = 0.1, kt = 1.2e9 * 2e-5 / l0, toe = 0.03;
  double slope = -1.0;
  EXPECT_EQ(msd::tendon_tension(0.099, l0, kt, toe, &slope), 0.0);
  EXPECT_EQ(slope, 0.0);
  // In the toe: k_t L0 e^2 / (2 e_t); at 1.5 % strain that is a quarter of
  // the linear law's tension at the same strain.
  EXPECT_NEAR(msd::tendon_tension(l0 * 1.015, l0, kt, toe, &slope), kt * l0 * 0.015 * 0.015 / 0.06, 1e-9);
  EXPECT_NEAR(slope, kt * 0.5, 1e-6);
  // Beyond: the modulus's slope, offset by half the toe.
  EXPECT_NEAR(msd::tendon_tension(l0 * 1.05, l0, kt, toe, &slope), kt * l0 * (0.05 - 0.015), 1e-9);
  EXPECT_EQ(slope, kt);
  // Continuous with a continuous slope at e_t.
  double below = 0.0, above = 0.0;
  const double tb = msd::tendon_tension(l0 * (1 + toe) - 1e-12, l0, kt, toe, &below);
  const double ta = msd::tendon_tension(l0 * (1 + toe) + 1e-12, l0, kt, toe, &above);
  EXPECT_NEAR(tb, ta, 1e-6);
  EXPECT_NEAR(below, above, 1e-6 * kt);
  // No toe: the thesis' strand.
  EXPECT_NEAR(msd::tendon_tension(l0 * 1.01, l0, kt), kt * 0.001, 1e-9);
}

TEST(TendonToe, ForcesAreMinusTheGradientOfTheToeEnergyInAndBeyondTheToe) {
  std::mt19937 rng(3);
  const std::vector<int> nodes{0, 1, 2, 3, 4, 5};
  for (double strain : {0.01, 0.025, 0.06}) {
    const msd::Points x = random_strand(rng, 6);
    const double toe = 0.03, l0 = msd::strand_length(x, nodes) / (1.0 + strain), kt = 2500.0;
    msd::Points f = msd::Points::Zero(3, 6);
    const double t = msd::add_tendon_forces(x, nodes, l0, kt, f, toe);
    EXPECT_NEAR(t, msd::tendon_tension(msd::strand_length(x, nodes), l0, kt, toe), 1e-12);
    expect_minus_energy_gradient(x, nodes, l0, kt, toe, f, t);
  }
}
