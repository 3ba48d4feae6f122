#include "msd/integrate/imex_strands.hpp"

#include "msd/forces/jacobians.hpp"
#include "msd/forces/parts.hpp"
#include "msd/forces/tendon.hpp"
#include "msd/integrate/step.hpp"
#include "msd/mesh/cubic_grid.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

using msd::Vec3;

namespace {

// The 10 cm corner tet with no element terms: nodes 0, 1, 2 (or only 0) held
// by group "base", the others free; a kilogram-scale node hangs on strands.
msd::Model corner(bool pin_three, unsigned terms = 0) {
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 1.0;
  msd::ModelOptions o;
  o.terms = terms;
  o.region_materials = {mat};
  o.gravity = Vec3(0, 0, -9.81);
  o.groups = {{"base", pin_three ? std::vector<int>{0, 1, 2} : std::vector<int>{0}, {true, true, true}}};
  return msd::build_model(testing_support::corner_tet_mesh(0.1), o);
}

msd::Controls still(const msd::Model& m) {
  msd::Controls c;
  c.group_offset.assign(m.groups.size(), Vec3::Zero());
  c.group_velocity.assign(m.groups.size(), Vec3::Zero());
  return c;
}

// A strand from node `node` straight up to an anchor `above` m over its rest
// position, fixed on the base, natural length `natural`.
msd::Strand hanger(const msd::Model& m, int node, double above, double natural, double k_t) {
  msd::Strand s;
  s.nodes = {node};
  s.natural_length = natural;
  s.k_t = k_t;
  s.anchor_group = 0;
  s.anchor_rest = Vec3(m.rest_positions.col(node)) + Vec3(0, 0, above);
  return s;
}

}  // namespace

TEST(ImexStrands, OneStepOfAStretchedStrandIsTheLinearlyImplicitClosedForm) {
  // Node 3 (mass m) under an anchor 0.2 m above, natural length 0.19: tension
  // T = k 0.01 straight up. With no gravity and v = 0, the step solves
  // (m + h^2 k) v+ = h T along the strand (its transverse stiffness T/d does
  // not enter: the motion is axial), x+ = x + h v+ - at h^2 k / m = 100, 25
  // times past symplectic Euler's limit of 4.
  msd::Model m = corner(true);
  m.gravity = Vec3::Zero();
  const double mass = m.mass[3], k = 100.0 * mass / (1e-3 * 1e-3);
  m.strands = {hanger(m, 3, 0.2, 0.19, k)};
  msd::check_model_parts(m);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  const double h = 1e-3, T = k * 0.01;
  msd::step(m, s, still(m), h, msd::Integrator::ImexEuler, scratch);
  const double v_expected = h * T / (mass + h * h * k);
  EXPECT_NEAR(s.v(2, 3), v_expected, 1e-12 * v_expected);
  EXPECT_NEAR(s.v(0, 3), 0.0, 1e-15);
  EXPECT_NEAR(s.x(2, 3), 0.1 + h * v_expected, 1e-15);
  // Symplectic Euler's step would be h T / m, a hundred and one times larger.
  EXPECT_NEAR(h * T / mass / v_expected, 101.0, 1e-9);
}

TEST(ImexStrands, AHangingNodeSettlesAtTheStaticStretchWhereSymplecticEulerRattles) {
  // Node 3 hangs on a stiff strand: at equilibrium k (d - L0) = m g, d the
  // node's distance below the anchor. The IMEX step damps the strand's mode
  // (|lambda|^2 = 1 / (1 + h^2 omega^2)) and settles there; symplectic Euler
  // at the same step (h omega = 10) does not.
  msd::Model m = corner(true, msd::kGravity);
  const double mass = m.mass[3], h = 1e-3, k = 100.0 * mass / (h * h);
  m.strands = {hanger(m, 3, 0.2, 0.2, k)};
  msd::check_model_parts(m);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  for (int i = 0; i < 400; ++i) msd::step(m, s, still(m), h, msd::Integrator::ImexEuler, scratch);
  const double stretch = 0.1 + 0.2 - s.x(2, 3) - 0.2;
  EXPECT_NEAR(stretch, mass * 9.81 / k, 1e-9 * mass * 9.81 / k);
  EXPECT_GT(scratch.strand_tension[0], 0.0);

  // Symplectic Euler overshoots by h^2 omega^2 = 100 times the stretch each
  // step; the tension-only strand goes slack and the node rattles instead of
  // settling (it stays bounded only because a slack strand pushes nothing).
  msd::State e = msd::rest_state(m);
  msd::Scratch se;
  double worst = 0.0;
  for (int i = 0; i < 400; ++i) {
    msd::step(m, e, still(m), h, msd::Integrator::SymplecticEuler, se);
    if (i >= 300) worst = std::max(worst, std::abs(0.1 - e.x(2, 3) - mass * 9.81 / k));
  }
  EXPECT_GT(worst, 10.0 * mass * 9.81 / k);
}

TEST(ImexStrands, AStrandCarriedAtConstantVelocityMovesAsAtRest) {
  // Galilean invariance: the base (and with it the anchor) and node 3 moving
  // at V give the rest run's motion plus V t. The held points' motion enters
  // the system (dt K_sp dx_p); without it the taut strand would drag node 3
  // back with k_t dt V, a numerical damper.
  // Node 3 hangs on the strand under gravity, taut at every step.
  msd::Model m = corner(true, msd::kGravity);
  const double mass = m.mass[3], h = 1e-3, k = 100.0 * mass / (h * h);
  m.strands = {hanger(m, 3, 0.2, 0.2, k)};
  msd::check_model_parts(m);
  const Vec3 V(0.3, -0.1, 0.5);
  msd::State rest = msd::rest_state(m), moving = msd::rest_state(m);
  moving.v.colwise() = V;
  msd::Scratch sr, sm;
  msd::Controls c = still(m);
  bool always_taut = true;
  for (int i = 1; i <= 50; ++i) {
    msd::step(m, rest, still(m), h, msd::Integrator::ImexEuler, sr);
    c.group_offset[0] = i * h * V;
    c.group_velocity[0] = V;
    msd::step(m, moving, c, h, msd::Integrator::ImexEuler, sm);
    always_taut = always_taut && sr.strand_tension[0] > 0.0 && sm.strand_tension[0] > 0.0;
  }
  const double t = 50 * h;
  EXPECT_TRUE(always_taut);
  EXPECT_LT((Vec3(moving.x.col(3)) - t * V - Vec3(rest.x.col(3))).norm(), 1e-12);
  EXPECT_LT((Vec3(moving.v.col(3)) - V - Vec3(rest.v.col(3))).norm(), 1e-9 * V.norm());
}

TEST(ImexStrands, WithoutATautStrandItIsSymplecticEulerBitForBit) {
  // A squeezed block with every element term and a slack strand, and the same
  // block without strands: the IMEX step adds nothing.
  msd::SampleMeshOptions so;
  so.spacing = 0.01;
  const msd::TetMesh mesh = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.03, 0.03, 0.03)), so, "block").mesh;
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.mode = msd::ConstantsMode::Physical;
  mat.youngs_modulus = 3000.0;
  mat.damping_time = 4e-3;
  mat.repulsion_factor = 0.5;
  mat.volume_factor = 1.6;
  msd::ModelOptions o;
  o.region_materials = {mat};
  o.terms = msd::kSprings | msd::kDampers | msd::kRepulsion | msd::kVolume | msd::kGravity;
  o.gravity = Vec3(0, 0, -9.81);
  o.groups = {{"base", {0}, {true, true, true}}};
  msd::Model m = msd::build_model(mesh, o);
  for (bool strand : {false, true}) {
    SCOPED_TRACE(strand);
    if (strand) {
      m.strands = {hanger(m, m.num_nodes() - 1, 0.02, 0.05, 1e6)};  // 0.02 m to an anchor, natural 0.05: slack
      msd::check_model_parts(m);
    }
    msd::State a = msd::rest_state(m);
    msd::Points v;
    testing_support::deform(m, 0.9, 0.0005, a.x, v);
    a.v = v;
    msd::State b = a;
    msd::Scratch sa, sb;
    for (int i = 0; i < 10; ++i) {
      msd::step(m, a, still(m), 1e-5, msd::Integrator::SymplecticEuler, sa);
      msd::step(m, b, still(m), 1e-5, msd::Integrator::ImexEuler, sb);
    }
    EXPECT_EQ((a.x - b.x).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ((a.v - b.v).cwiseAbs().maxCoeff(), 0.0);
    if (strand) {
      EXPECT_EQ(sb.strand_tension[0], 0.0);
    }
  }
}

TEST(ImexStrands, StrandsSharingANodeAreSolvedAsOneSystem) {
  // Nodes 1, 2, 3 free (node 0 held). Strand A runs 1 -> 3 -> anchor, strand
  // B runs 2 -> 0 (held) -> 3 -> anchor: they share node 3, and B passes over
  // a held node. The step's velocities must be the solution of the whole
  // system (M - h^2 K) v+ = M (v + h a), K the strands' Jacobians with the
  // held node and the anchors dropped, solved here densely from the 12
  // unknowns.
  msd::Model m = corner(false, msd::kGravity);
  const double h = 2e-3, k = 5e4;
  msd::Strand a, b;
  a.nodes = {1, 3};
  a.k_t = k;
  a.anchor_group = 0;
  a.anchor_rest = Vec3(0.05, 0.05, 0.3);
  b = a;
  b.nodes = {2, 0, 3};
  b.anchor_rest = Vec3(-0.05, 0.02, 0.25);
  auto length = [&](const msd::Strand& s) {
    return testing_support::polyline_length(m.rest_positions, s.nodes, &s.anchor_rest);
  };
  a.natural_length = 0.97 * length(a);
  b.natural_length = 0.95 * length(b);
  m.strands = {a, b};
  msd::check_model_parts(m);
  msd::State s = msd::rest_state(m);
  s.v.col(1) = Vec3(0.1, -0.2, 0.05);
  s.v.col(3) = Vec3(-0.3, 0.1, 0.2);
  const msd::State start = s;
  msd::Scratch scratch;
  const msd::Controls c = still(m);
  msd::step(m, s, c, h, msd::Integrator::ImexEuler, scratch);

  // The reference: forces at the start, the Jacobians of both strands.
  msd::Scratch fs;
  msd::evaluate_forces(m, start, c, fs);
  const int n = m.num_nodes();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  Eigen::VectorXd rhs(3 * n);
  for (int i = 0; i < n; ++i) {
    A.block<3, 3>(3 * i, 3 * i) = m.mass[i] * msd::Mat3::Identity();
    rhs.segment<3>(3 * i) = m.mass[i] * Vec3(start.v.col(i)) + h * (Vec3(fs.f.col(i)) + m.mass[i] * m.gravity);
  }
  for (size_t si = 0; si < m.strands.size(); ++si) {
    const msd::Strand& st = m.strands[si];
    msd::Points p(3, static_cast<Eigen::Index>(st.nodes.size()) + 1);
    for (size_t i = 0; i < st.nodes.size(); ++i) p.col(static_cast<Eigen::Index>(i)) = start.x.col(st.nodes[i]);
    p.col(p.cols() - 1) = st.anchor_rest;
    Eigen::MatrixXd K;
    ASSERT_TRUE(msd::strand_jacobian(p, st.natural_length, st.k_t, K));
    for (size_t i = 0; i < st.nodes.size(); ++i)
      for (size_t j = 0; j < st.nodes.size(); ++j)
        A.block<3, 3>(3 * st.nodes[i], 3 * st.nodes[j]) -= h * h * K.block<3, 3>(3 * static_cast<Eigen::Index>(i), 3 * static_cast<Eigen::Index>(j));
  }
  // Node 0 is held: its rows and columns leave the system.
  const Eigen::MatrixXd Af = A.bottomRightCorner(9, 9);
  const Eigen::VectorXd expected = Af.ldlt().solve(rhs.tail(9));
  for (int i = 1; i < n; ++i)
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(s.v(d, i), expected[3 * (i - 1) + d], 1e-12 * expected.cwiseAbs().maxCoeff()) << i << " " << d;
  // The shared node's coupling matters: solving node 3 alone gives another answer.
  const Eigen::Vector3d alone = A.block<3, 3>(9, 9).ldlt().solve(rhs.segment<3>(9));
  EXPECT_GT((alone - expected.tail(3)).norm(), 1e-6 * expected.tail(3).norm());
  EXPECT_EQ(s.v.col(0).norm(), 0.0);
}

TEST(ImexStrands, TheIntegratorIsNamedImexEuler) {
  EXPECT_EQ(msd::parse_integrator("imex_euler"), msd::Integrator::ImexEuler);
  EXPECT_EQ(msd::to_string(msd::Integrator::ImexEuler), "imex_euler");
  EXPECT_FALSE(msd::is_implicit(msd::Integrator::ImexEuler));
  try {
    msd::parse_integrator("imex");
    FAIL() << "an unknown integrator was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("imex_euler"), std::string::npos) << e.what();
  }
}
