// The material kernels of the FEM reference against finite differences: P_iso
// is the derivative of the isochoric energy, the tangent contractions are the
// derivatives of the stresses, and the condensed three-field dilatation
// reproduces its defining projections.
#include "dilatation.h"
#include "neo_hookean.h"

#include <gtest/gtest.h>

#include <random>

using dealii::Tensor;
using namespace fem::internal;

namespace {

Tensor<2, 3> random_grad(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Tensor<2, 3> g;
  for (unsigned i = 0; i < 3; ++i)
    for (unsigned j = 0; j < 3; ++j) g[i][j] = u(rng);
  return g;
}

Tensor<2, 3> unit(unsigned i, unsigned J) {
  Tensor<2, 3> e;
  e[i][J] = 1.0;
  return e;
}

}  // namespace

TEST(NeoHookean, IsochoricStressIsEnergyDerivative) {
  std::mt19937 rng(1);
  const double mu = 2.5, h = 1e-6;
  for (int k = 0; k < 50; ++k) {
    const Tensor<2, 3> g = random_grad(rng, 0.3);
    const Tensor<2, 3> P = P_iso(mu, Kinematics(g));
    for (unsigned i = 0; i < 3; ++i)
      for (unsigned J = 0; J < 3; ++J) {
        const double fd = (psi_iso(mu, Kinematics(g + h * unit(i, J))) - psi_iso(mu, Kinematics(g - h * unit(i, J)))) / (2 * h);
        EXPECT_NEAR(P[i][J], fd, 1e-7 * (1 + std::abs(fd)));
      }
  }
}

TEST(NeoHookean, TangentContractionsAreStressDerivatives) {
  std::mt19937 rng(2);
  const double mu = 1.7, h = 1e-6;
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 50; ++k) {
    const Tensor<2, 3> g = random_grad(rng, 0.3);
    const Kinematics kin(g);
    // Two primitive shape functions: components ca, cb and gradients ga, gb.
    for (unsigned ca = 0; ca < 3; ++ca)
      for (unsigned cb = 0; cb < 3; ++cb) {
        Tensor<1, 3> ga, gb;
        for (unsigned d = 0; d < 3; ++d) {
          ga[d] = u(rng);
          gb[d] = u(rng);
        }
        Tensor<2, 3> Ga, Gb;
        for (unsigned d = 0; d < 3; ++d) {
          Ga[ca][d] = ga[d];
          Gb[cb][d] = gb[d];
        }
        const ShapeTerms A = shape_terms(kin, ga, ca), B = shape_terms(kin, gb, cb);
        // d/ds [P_iso(F + s Gb) : Ga]
        const double fd_iso = (scalar_product(P_iso(mu, Kinematics(g + h * Gb)), Ga) -
                               scalar_product(P_iso(mu, Kinematics(g - h * Gb)), Ga)) / (2 * h);
        EXPECT_NEAR(iso_tangent(mu, kin, A, B), fd_iso, 1e-6 * (1 + std::abs(fd_iso)));
        // d/ds [J F^-T (F + s Gb) : Ga]
        auto jfit = [&](const Tensor<2, 3>& gg) {
          const Kinematics kk(gg);
          return kk.J * scalar_product(kk.F_inv_T, Ga);
        };
        const double fd_vol = (jfit(g + h * Gb) - jfit(g - h * Gb)) / (2 * h);
        EXPECT_NEAR(dJFinvT(kin, A, B), fd_vol, 1e-6 * (1 + std::abs(fd_vol)));
      }
  }
}

TEST(NeoHookean, VolumetricFunctionAndCauchyStress) {
  const double kappa = 3.0;
  EXPECT_DOUBLE_EQ(U(kappa, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(dU(kappa, 1.0), 0.0);
  const double h = 1e-6, J = 0.8;
  EXPECT_NEAR(dU(kappa, J), (U(kappa, J + h) - U(kappa, J - h)) / (2 * h), 1e-8);
  EXPECT_NEAR(ddU(kappa, J), (dU(kappa, J + h) - dU(kappa, J - h)) / (2 * h), 1e-8);
  // Simple shear: sigma_xz = mu gamma, sigma_xx = 2/3 mu gamma^2, trace-free.
  Tensor<2, 3> g;
  g[0][2] = 0.6;
  const Tensor<2, 3> s = cauchy(2.0, 0.0, Kinematics(g));
  EXPECT_NEAR(s[0][2], 2.0 * 0.6, 1e-14);
  EXPECT_NEAR(s[0][0], 2.0 / 3.0 * 2.0 * 0.36, 1e-14);
  EXPECT_NEAR(s[0][0] + s[1][1] + s[2][2], 0.0, 1e-14);
}

TEST(CellDilatation, ProjectsJAndPressure) {
  // A unit cell sampled at 27 points; J linear in x is reproduced exactly by
  // the P1 projection and averaged by P0.
  std::vector<dealii::Point<3>> X;
  std::vector<double> w, J;
  const double g[3] = {0.1127016653792583, 0.5, 0.8872983346207417};
  const double gw[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        X.emplace_back(g[i], g[j], g[k]);
        w.push_back(gw[i] * gw[j] * gw[k]);
        J.push_back(0.9 + 0.2 * g[i]);
      }
  CellDilatation p1;
  p1.reinit(1, X, w);
  ASSERT_TRUE(p1.compute(J, 5.0));
  EXPECT_EQ(p1.size(), 4u);
  for (unsigned q = 0; q < X.size(); ++q) EXPECT_NEAR(p1.J_tilde(q), J[q], 1e-12);
  // The pressure is the L2 projection of U'(J~): its error is orthogonal to P1.
  for (unsigned l = 0; l < p1.size(); ++l) {
    double r = 0.0;
    for (unsigned q = 0; q < X.size(); ++q) r += (p1.pressure(q) - dU(5.0, p1.J_tilde(q))) * p1.phi(q, l) * w[q];
    EXPECT_NEAR(r, 0.0, 1e-14) << l;
  }
  CellDilatation p0;
  p0.reinit(0, X, w);
  ASSERT_TRUE(p0.compute(J, 5.0));
  EXPECT_EQ(p0.size(), 1u);
  for (unsigned q = 0; q < X.size(); ++q) EXPECT_NEAR(p0.J_tilde(q), 1.0, 1e-12);
  // A negative projected J is reported.
  std::vector<double> bad(J.size(), -0.1);
  EXPECT_FALSE(p0.compute(bad, 5.0));
}
