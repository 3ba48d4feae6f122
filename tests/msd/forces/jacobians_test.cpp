#include "msd/forces/jacobians.hpp"

#include "msd/forces/edge_dampers.hpp"
#include "msd/forces/edge_springs.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/forces/face_repulsion.hpp"
#include "msd/forces/muscle_units.hpp"
#include "msd/forces/tendon.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <random>

using msd::Mat3;
using msd::Vec3;

namespace {

// Central differences of a vector function of a 3-vector.
Mat3 fd3(const std::function<Vec3(const Vec3&)>& f, const Vec3& at, double h) {
  Mat3 J;
  for (int d = 0; d < 3; ++d) {
    Vec3 up = at, down = at;
    up[d] += h;
    down[d] -= h;
    J.col(d) = (f(up) - f(down)) / (2 * h);
  }
  return J;
}

Vec3 spring_force(const Vec3& l, double rest, double ks) {
  return msd::edge_spring_factor(ks, l.norm(), 1.0 / l.norm(), rest) * l;
}

Vec3 damper_force(const Vec3& l, const Vec3& w, double kd) {
  return msd::edge_damper_factor(kd, w.dot(l), 1.0 / l.norm()) * l;
}

// The element's non-linear forces as a 12-vector (what the Jacobian differentiates).
Eigen::Matrix<double, 12, 1> nonlinear_forces(const msd::Model& m, const Vec3 x[4]) {
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  msd::add_nonlinear_element_forces(m, m.elements[0], x, f);
  Eigen::Matrix<double, 12, 1> out;
  for (int i = 0; i < 4; ++i) out.segment<3>(3 * i) = f[i];
  return out;
}

msd::Mat12 fd_nonlinear(const msd::Model& m, const Vec3 x[4], double h) {
  msd::Mat12 J;
  Vec3 y[4] = {x[0], x[1], x[2], x[3]};
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) {
      const double keep = y[k][d];
      y[k][d] = keep + h;
      const auto up = nonlinear_forces(m, y);
      y[k][d] = keep - h;
      const auto down = nonlinear_forces(m, y);
      y[k][d] = keep;
      J.col(3 * k + d) = (up - down) / (2 * h);
    }
  return J;
}

// The 10 cm corner tet with raw repulsion and volume constants.
msd::Model nonlinear_tet(unsigned terms, double threshold = 0.0) {
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 1.0;
  mat.k_r = 30.0;
  mat.k_v = 50.0;
  mat.repulsion_floor = 0.2;
  msd::ModelOptions o;
  o.terms = terms;
  o.nonlinear_threshold = threshold;
  o.region_materials = {mat};
  return msd::build_model(testing_support::corner_tet_mesh(0.1), o);
}

double rel_err(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace

TEST(Jacobians, EdgeSpringMatchesFiniteDifferencesStretchedAndCompressed) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 l(u(rng), u(rng), u(rng));
    const double rest = l.norm() * (trial % 2 ? 1.6 : 0.5);  // compressed, then stretched
    const Mat3 J = msd::edge_spring_jacobian(l, rest, 7.0);
    const Mat3 fd = fd3([&](const Vec3& y) { return spring_force(y, rest, 7.0); }, l, 1e-6);
    EXPECT_LT(rel_err(J, fd), 1e-7) << trial;
    EXPECT_LT((J - J.transpose()).norm(), 1e-12 * J.norm());  // a spring is conservative
  }
}

TEST(Jacobians, EdgeDamperMatchesFiniteDifferencesInPositionAndVelocity) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 l(u(rng), u(rng), u(rng)), w(u(rng), u(rng), u(rng));
    Mat3 dl, dw;
    msd::edge_damper_jacobians(l, w, 0.3, dl, dw);
    EXPECT_LT(rel_err(dl, fd3([&](const Vec3& y) { return damper_force(y, w, 0.3); }, l, 1e-6)), 1e-7);
    EXPECT_LT(rel_err(dw, fd3([&](const Vec3& y) { return damper_force(l, y, 0.3); }, w, 1e-6)), 1e-7);
  }
}

TEST(Jacobians, RepulsionSlopeIsTheMagnitudesDerivativeOnBothSidesOfTheFloor) {
  const double x0 = 0.05, kr = 40.0, floor = 0.1;
  for (double x : {0.08, 0.05, 0.02, 0.007, 0.003, -0.01}) {
    const double h = 1e-7;
    const double fd = (msd::face_repulsion_magnitude(x + h, x0, kr, floor) -
                       msd::face_repulsion_magnitude(x - h, x0, kr, floor)) / (2 * h);
    EXPECT_NEAR(msd::face_repulsion_slope(x, x0, kr, floor), fd, 1e-6 * std::abs(fd)) << x;
  }
}

TEST(Jacobians, NonlinearElementMatchesFiniteDifferencesForEachTermAndBoth) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned terms : {unsigned{msd::kRepulsion}, unsigned{msd::kVolume}, msd::kRepulsion | msd::kVolume}) {
    const msd::Model m = nonlinear_tet(terms);
    for (int trial = 0; trial < 30; ++trial) {
      // Squeezed, sheared, some below the repulsion floor, some inverted.
      Vec3 x[4];
      for (int i = 0; i < 4; ++i) x[i] = m.rest_positions.col(i);
      const double squeeze = trial < 10 ? 0.9 : trial < 20 ? 0.3 : -0.2;
      x[3].z() *= squeeze;
      for (int i = 0; i < 4; ++i) x[i] += 0.01 * Vec3(u(rng), u(rng), u(rng));
      msd::Mat12 K;
      ASSERT_TRUE(msd::nonlinear_element_jacobian(m, m.elements[0], x, K));
      EXPECT_LT(rel_err(K, fd_nonlinear(m, x, 1e-7)), 2e-6) << "terms " << terms << " trial " << trial;
    }
  }
}

TEST(Jacobians, RepulsionIsSymmetricVolumeIsNotAndEveryColumnSumsToZero) {
  Vec3 x[4];
  const msd::Model rep = nonlinear_tet(msd::kRepulsion), vol = nonlinear_tet(msd::kVolume);
  for (int i = 0; i < 4; ++i) x[i] = rep.rest_positions.col(i);
  x[3] = Vec3(0.02, 0.01, 0.04);
  msd::Mat12 K, V;
  msd::nonlinear_element_jacobian(rep, rep.elements[0], x, K);
  msd::nonlinear_element_jacobian(vol, vol.elements[0], x, V);
  // Repulsion is -grad of an energy: K = -Hessian, symmetric.
  EXPECT_LT((K - K.transpose()).cwiseAbs().maxCoeff(), 1e-9 * K.cwiseAbs().maxCoeff());
  // Volume preservation is not (its equalising forces are normal to the face only).
  EXPECT_GT((V - V.transpose()).cwiseAbs().maxCoeff(), 1e-3 * V.cwiseAbs().maxCoeff());
  // Net force is zero for any shape, so its change is too: the three component
  // rows summed over the vertices vanish in every column.
  for (const msd::Mat12* J : {&K, &V})
    for (int c = 0; c < 3; ++c) {
      Eigen::Matrix<double, 1, 12> sum = Eigen::Matrix<double, 1, 12>::Zero();
      for (int j = 0; j < 4; ++j) sum += J->row(3 * j + c);
      EXPECT_LT(sum.cwiseAbs().maxCoeff(), 1e-10 * J->cwiseAbs().maxCoeff());
    }
}

TEST(Jacobians, AnElementTheThresholdLeavesOutHasNone) {
  const msd::Model m = nonlinear_tet(msd::kRepulsion | msd::kVolume, 0.7);
  Vec3 x[4];
  for (int i = 0; i < 4; ++i) x[i] = m.rest_positions.col(i);
  msd::Mat12 K;
  K.setOnes();
  EXPECT_FALSE(msd::nonlinear_element_jacobian(m, m.elements[0], x, K));
  EXPECT_EQ(K.cwiseAbs().maxCoeff(), 0.0);
  x[3].z() *= 0.5;  // below 0.7 of its rest height: on
  EXPECT_TRUE(msd::nonlinear_element_jacobian(m, m.elements[0], x, K));
  EXPECT_GT(K.cwiseAbs().maxCoeff(), 0.0);
}

// --- The moving parts (msd/forces/parts.hpp) --------------------------------

TEST(Jacobians, MuscleUnitMatchesFiniteDifferencesOnEveryLimbOfItsForceLength) {
  const double rest = 0.02, force = 3.0;
  const msd::ForceLength fl{true, 0.5};
  auto pull = [&](const msd::ForceLength& law) {
    return [&, law](const Vec3& l) {
      msd::Points x(3, 2), f = msd::Points::Zero(3, 2);
      x.col(0).setZero();
      x.col(1) = l;
      msd::add_muscle_forces(x, {{0, 1, rest}}, force, f, law);
      return Vec3(f.col(0));
    };
  };
  const Vec3 dir = Vec3(0.3, -0.2, 0.9).normalized();
  for (double stretch : {0.55, 0.7, 0.95, 1.2}) {  // ascending limb, and the plateau above 1
    const Vec3 l = stretch * rest * dir + Vec3(1e-4, 2e-4, 0.0);
    for (const msd::ForceLength& law : {fl, msd::ForceLength{}}) {
      const Mat3 J = msd::muscle_unit_jacobian(l, rest, force, law), Jfd = fd3(pull(law), l, 1e-8);
      EXPECT_LT((J - Jfd).norm(), 1e-6 * Jfd.norm()) << "stretch " << stretch << " f_L " << law.enabled;
    }
  }
  // Below lambda_0 the unit pulls nothing and its Jacobian is zero.
  EXPECT_EQ(msd::muscle_unit_jacobian(0.4 * rest * dir, rest, force, fl).norm(), 0.0);
}

TEST(Jacobians, StrandMatchesFiniteDifferencesAndIsSymmetricAndZeroWhenSlack) {
  // A bent strand of five points stretched 6 % past its natural length.
  msd::Points p(3, 5);
  p << 0.00, 0.010, 0.020, 0.031, 0.040,  //
      0.00, 0.004, 0.003, -0.002, 0.001,  //
      0.00, 0.010, 0.021, 0.030, 0.042;
  std::vector<int> idx = {0, 1, 2, 3, 4};
  const double length = msd::strand_length(p, idx), k_t = 4.8e5, l0 = length / 1.06;
  Eigen::MatrixXd K;
  ASSERT_TRUE(msd::strand_jacobian(p, l0, k_t, K));
  Eigen::MatrixXd Kfd(15, 15);
  const double h = 1e-8;
  for (int k = 0; k < 15; ++k) {
    msd::Points up = p, down = p, fu = msd::Points::Zero(3, 5), fd = msd::Points::Zero(3, 5);
    up.data()[k] += h;
    down.data()[k] -= h;
    msd::add_tendon_forces(up, idx, l0, k_t, fu);
    msd::add_tendon_forces(down, idx, l0, k_t, fd);
    Kfd.col(k) = (Eigen::Map<const Eigen::VectorXd>(fu.data(), 15) - Eigen::Map<const Eigen::VectorXd>(fd.data(), 15)) /
                 (2 * h);
  }
  EXPECT_LT((K - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
  EXPECT_LT((K - K.transpose()).cwiseAbs().maxCoeff(), 1e-9 * K.cwiseAbs().maxCoeff());
  // A rigid translation changes no force: every row's blocks sum to zero.
  for (int r = 0; r < 15; ++r)
    for (int d = 0; d < 3; ++d) {
      double sum = 0.0;
      for (int j = 0; j < 5; ++j) sum += K(r, 3 * j + d);
      EXPECT_NEAR(sum, 0.0, 1e-9 * K.cwiseAbs().maxCoeff());
    }
  // Slack: no tension, no stiffness.
  EXPECT_FALSE(msd::strand_jacobian(p, 1.01 * length, k_t, K));
  EXPECT_EQ(K.norm(), 0.0);
}
