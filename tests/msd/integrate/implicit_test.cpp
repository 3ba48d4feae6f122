#include "msd/integrate/implicit.hpp"
#include "msd/forces/parts.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/forces/tendon.hpp"
#include "msd/integrate/step.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "msd/mesh/tet_mesh.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using msd::Vec3;

namespace {

constexpr unsigned kAll = msd::kSprings | msd::kDampers | msd::kRepulsion | msd::kVolume;

// A 3 x 2 x 4 cm block at h = 1 cm with physical constants; `base` pins the
// nodes of its bottom face (z = 0) and `top` moves the top face (z = 4 cm).
// The block's mesh and its model options (material, terms, threads), before
// any group or obstacle.
msd::TetMesh block_mesh(unsigned terms, int threads, double E, msd::ModelOptions& mo) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.03, 0.02, 0.04)), o, "block");
  msd::TissueMaterial mat;
  mat.mode = msd::ConstantsMode::Physical;
  mat.density = 1000;
  mat.youngs_modulus = E;
  mat.damping_time = 0.01;
  mat.repulsion_factor = 0.5;
  mat.volume_factor = 1.6;
  mat.poisson_ratio = 0.45;  // read only by the neo_hookean term
  mo.terms = terms;
  mo.region_materials = {mat};
  mo.threads = threads;
  return s.mesh;
}

msd::Model block(unsigned terms, int threads = 1, bool platens = false, double E = 3000.0, bool cube_volumes = false) {
  msd::ModelOptions mo;
  const msd::TetMesh mesh = block_mesh(terms, threads, E, mo);
  if (cube_volumes) {
    msd::SampleMeshOptions o;
    o.spacing = 0.01;
    mo.volume_group = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.03, 0.02, 0.04)), o, "block").info.tet_cube_id;
  }
  if (platens) {
    msd::KinematicGroup base{"base", {}, {true, true, true}}, top{"top", {}, {true, true, true}};
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      if (mesh.nodes(2, i) < 1e-9) base.nodes.push_back(i);
      if (mesh.nodes(2, i) > 0.04 - 1e-9) top.nodes.push_back(i);
    }
    mo.groups = {base, top};
  }
  return msd::build_model(mesh, mo);
}

using testing_support::deform;

// Central differences of the internal forces along every coordinate of x (or v).
Eigen::MatrixXd fd_jacobian(const msd::Model& m, const msd::Points& x, const msd::Points& v, bool of_velocity,
                            double h) {
  const Eigen::Index n = 3 * x.cols();
  Eigen::MatrixXd J(n, n);
  msd::Points y = of_velocity ? v : x, up, down;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double keep = y.data()[k];
    y.data()[k] = keep + h;
    msd::compute_internal_forces(m, of_velocity ? x : y, of_velocity ? y : v, up);
    y.data()[k] = keep - h;
    msd::compute_internal_forces(m, of_velocity ? x : y, of_velocity ? y : v, down);
    y.data()[k] = keep;
    J.col(k) = Eigen::Map<const Eigen::VectorXd>(up.data(), n) - Eigen::Map<const Eigen::VectorXd>(down.data(), n);
    J.col(k) /= 2 * h;
  }
  return J;
}

// One tet with three nodes pinned: node 3 oscillates on its three springs.
msd::Model oscillator() {
  msd::TissueMaterial mat;
  mat.density = 6.0;
  mat.k_s = 100.0;
  msd::ModelOptions o;
  o.terms = msd::kSprings;
  o.region_materials = {mat};
  o.groups = {{"base", {0, 1, 2}, {true, true, true}}};
  return msd::build_model(testing_support::corner_tet_mesh(1.0), o);
}

double spring_energy(const msd::Model& m, const msd::State& s) {
  return msd::conservative_energy(m, s.x) + msd::kinetic_energy(m, s.v);
}

msd::Controls at_rest(const msd::Model& m) {
  return {std::vector<Vec3>(m.groups.size(), Vec3::Zero()), std::vector<Vec3>(m.groups.size(), Vec3::Zero())};
}

double run_oscillator(msd::Integrator integ, double dt, double t_end) {
  const msd::Model m = oscillator();
  msd::State s = msd::rest_state(m);
  s.x(2, 3) += 1e-3;
  msd::Scratch scratch;
  const long n = std::lround(t_end / dt);
  for (long i = 0; i < n; ++i) msd::step(m, s, at_rest(m), dt, integ, scratch);
  return s.x(2, 3) - 1.0;
}

}  // namespace

TEST(Implicit, AssembledJacobiansMatchFiniteDifferencesOfTheWholeModel) {
  const msd::Model m = block(kAll);
  msd::Points x, v;
  deform(m, 0.45, 0.001, x, v);  // squeezed so repulsion and volume work hard
  const msd::SystemLayout L = msd::make_system_layout(m);
  Eigen::SparseMatrix<double> K = L.pattern, D = L.pattern;
  msd::assemble_system(m, L, x, v, 0.0, 0.0, 1.0, K);
  msd::assemble_system(m, L, x, v, 0.0, 1.0, 0.0, D);
  const Eigen::MatrixXd Kfd = fd_jacobian(m, x, v, false, 1e-7), Dfd = fd_jacobian(m, x, v, true, 1e-6);
  EXPECT_LT((Eigen::MatrixXd(K) - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
  EXPECT_LT((Eigen::MatrixXd(D) - Dfd).cwiseAbs().maxCoeff(), 1e-6 * Dfd.cwiseAbs().maxCoeff());
  // And the mass: c_m M on the diagonal.
  Eigen::SparseMatrix<double> M = L.pattern;
  msd::assemble_system(m, L, x, v, 2.0, 0.0, 0.0, M);
  EXPECT_DOUBLE_EQ(M.coeff(3 * 5 + 1, 3 * 5 + 1), 2.0 * m.mass[5]);
  EXPECT_EQ(M.coeff(3 * 5 + 1, 3 * 5), 0.0);
}

TEST(Implicit, FreeVibrationLosesEnergyEveryStepAndNeverGainsIt) {
  // Springs only, no dampers: the exact motion keeps its energy; backward Euler
  // dissipates it (monotonically), explicit Euler gains it.
  const msd::Model m = oscillator();
  msd::State s = msd::rest_state(m);
  s.x(2, 3) += 1e-2;
  msd::Scratch scratch;
  double e = spring_energy(m, s);
  const double e0 = e;
  for (int k = 0; k < 500; ++k) {
    msd::step(m, s, at_rest(m), 2e-3, msd::Integrator::BackwardEuler, scratch);
    const double next = spring_energy(m, s);
    ASSERT_LE(next, e * (1 + 1e-12)) << "step " << k;
    e = next;
  }
  EXPECT_LT(e, 0.9 * e0);
  EXPECT_GT(e, 0.0);
}

TEST(Implicit, ConvergesAtFirstOrder) {
  const double ref = run_oscillator(msd::Integrator::VelocityVerlet, 1e-5, 0.5);
  const double e1 = std::abs(run_oscillator(msd::Integrator::BackwardEuler, 2e-3, 0.5) - ref);
  const double e2 = std::abs(run_oscillator(msd::Integrator::BackwardEuler, 1e-3, 0.5) - ref);
  EXPECT_NEAR(e1 / e2, 2.0, 0.4);
}

TEST(Implicit, StaysBoundedFarBeyondTheExplicitStabilityLimit) {
  // omega about 2 pi 4.5 Hz: explicit Euler's limit is near 2 / omega = 0.07 s
  // for symplectic Euler; at dt = 0.2 s it blows up, backward Euler decays.
  const double amp_be = std::abs(run_oscillator(msd::Integrator::BackwardEuler, 0.2, 10.0));
  EXPECT_LT(amp_be, 1e-3);
  EXPECT_THROW(
      {
        const double a = run_oscillator(msd::Integrator::SymplecticEuler, 0.2, 10.0);
        if (std::abs(a) > 1.0) throw msd::Error("blew up");
      },
      msd::Error);
}

TEST(Implicit, PrescribedNodesTakeTheirControlsAndRepeatedRunsAreBitIdenticalOnAnyThreadCount) {
  auto run = [](int threads) {
    const msd::Model m = block(kAll, threads, true);
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    const double dt = 2e-3;
    for (int k = 1; k <= 50; ++k) {
      const double t = k * dt;
      msd::Controls c{{Vec3::Zero(), Vec3(0, 0, -0.1 * t)}, {Vec3::Zero(), Vec3(0, 0, -0.1)}};
      msd::step(m, s, c, dt, msd::Integrator::BackwardEuler, scratch);
      for (int node : m.groups[1].nodes) {
        EXPECT_EQ(s.x(2, node), m.rest_positions(2, node) - 0.1 * t);
        EXPECT_EQ(s.v(2, node), -0.1);
      }
    }
    EXPECT_GT(scratch.newton_iterations, 0);
    return s.x;
  };
  const msd::Points one = run(1), again = run(1), two = run(2);
  EXPECT_EQ((one - again).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Implicit, ExtremeCompressionWithTheFullModelEndsFiniteAndUninverted) {
  // The top platen pushed down to 10 % of the height (strain -0.9) in 0.1 s,
  // at 5 ms steps: repulsion and volume on.
  const msd::Model m = block(kAll, 1, true);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  const double dt = 5e-3, speed = 0.9 * 0.04 / 0.1;
  for (int k = 1; k <= 20; ++k) {
    const double t = k * dt;
    msd::Controls c{{Vec3::Zero(), Vec3(0, 0, -speed * t)}, {Vec3::Zero(), Vec3(0, 0, -speed)}};
    msd::step(m, s, c, dt, msd::Integrator::BackwardEuler, scratch);
  }
  for (int k = 0; k < 40; ++k) {  // hold
    msd::Controls c{{Vec3::Zero(), Vec3(0, 0, -0.036)}, {Vec3::Zero(), Vec3::Zero()}};
    msd::step(m, s, c, dt, msd::Integrator::BackwardEuler, scratch);
  }
  ASSERT_TRUE(s.x.allFinite());
  for (const msd::Element& el : m.elements) {
    const auto& n = el.nodes;
    EXPECT_GT(msd::tet_signed_volume(s.x.col(n[0]), s.x.col(n[1]), s.x.col(n[2]), s.x.col(n[3])), 0.0);
  }
}

TEST(Implicit, AssembledJacobiansOfTheNeoHookeanElementMatchFiniteDifferences) {
  // The continuum element with the edge dampers, squeezed and sheared; its
  // stiffness is the energy's Hessian (symmetric), the dampers' is not.
  const msd::Model m = block(msd::kNeoHookean | msd::kDampers);
  msd::Points x, v;
  deform(m, 0.45, 0.001, x, v);
  const msd::SystemLayout L = msd::make_system_layout(m);
  Eigen::SparseMatrix<double> K = L.pattern, Kel = L.pattern;
  msd::assemble_system(m, L, x, v, 0.0, 0.0, 1.0, K);
  const Eigen::MatrixXd Kfd = fd_jacobian(m, x, v, false, 1e-7);
  EXPECT_LT((Eigen::MatrixXd(K) - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
  const msd::Model elastic = block(msd::kNeoHookean);
  msd::assemble_system(elastic, L, x, v, 0.0, 0.0, 1.0, Kel);
  const Eigen::MatrixXd dense(Kel);
  ASSERT_GT(dense.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((dense - dense.transpose()).cwiseAbs().maxCoeff(), 1e-12 * dense.cwiseAbs().maxCoeff());
}

TEST(Implicit, AssembledJacobiansOfTheEdgeClassesSpringLawsMatchFiniteDifferences) {
  // Cube edges softer and stiffening in compression, face diagonals with the
  // neo-Hookean bar's law: the springs' K is their laws' (spring_law_jacobian).
  msd::ModelOptions mo;
  const msd::TetMesh mesh = block_mesh(msd::kSprings | msd::kDampers, 1, 3000.0, mo);
  mo.region_materials[0].edge_laws[0] = {0.5, 1.0, 1.5};
  mo.region_materials[0].edge_laws[1] = {1.0, 1.0, 2.0};
  const msd::Model m = msd::build_model(mesh, mo);
  ASSERT_FALSE(m.plan.edge_law_m.empty());
  msd::Points x, v;
  deform(m, 0.45, 0.001, x, v);
  const msd::SystemLayout L = msd::make_system_layout(m);
  Eigen::SparseMatrix<double> K = L.pattern;
  msd::assemble_system(m, L, x, v, 0.0, 0.0, 1.0, K);
  const Eigen::MatrixXd Kfd = fd_jacobian(m, x, v, false, 1e-7);
  EXPECT_LT((Eigen::MatrixXd(K) - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
  // The laws matter here: the linear springs' K differs.
  msd::ModelOptions linear;
  const msd::Model plain = msd::build_model(block_mesh(msd::kSprings | msd::kDampers, 1, 3000.0, linear), linear);
  Eigen::SparseMatrix<double> K0 = L.pattern;
  msd::assemble_system(plain, L, x, v, 0.0, 0.0, 1.0, K0);
  EXPECT_GT((Eigen::MatrixXd(K) - Eigen::MatrixXd(K0)).cwiseAbs().maxCoeff(), 0.1 * Kfd.cwiseAbs().maxCoeff());
}

TEST(Implicit, AssembledJacobiansOfTheNeoHookeanElementWithCubeVolumesMatchFiniteDifferences) {
  // Each cube's shared volume ratio couples all eight of its nodes, beyond the lattice's edges.
  const msd::Model m = block(msd::kNeoHookean | msd::kDampers, 1, false, 3000.0, true);
  ASSERT_FALSE(m.volume_groups.empty());
  msd::Points x, v;
  deform(m, 0.45, 0.001, x, v);
  const msd::SystemLayout L = msd::make_system_layout(m);
  EXPECT_GT(L.pattern.nonZeros(), msd::make_system_layout(block(msd::kNeoHookean | msd::kDampers)).pattern.nonZeros());
  Eigen::SparseMatrix<double> K = L.pattern;
  msd::assemble_system(m, L, x, v, 0.0, 0.0, 1.0, K);
  const Eigen::MatrixXd Kfd = fd_jacobian(m, x, v, false, 1e-7);
  EXPECT_LT((Eigen::MatrixXd(K) - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
}

TEST(Implicit, AssembledJacobiansOfTheLatticesBulkTermMatchFiniteDifferences) {
  // The bulk term per cube (bulk_volume.hpp): its pressure times each tet's
  // volume Hessian, and the coupling of a cube's eight nodes; with the
  // thesis' repulsion and volume terms and the edge classes' laws beside it.
  msd::ModelOptions mo;
  const msd::TetMesh mesh = block_mesh(msd::kSprings | msd::kDampers | msd::kRepulsion | msd::kVolume | msd::kBulk, 1,
                                       3000.0, mo);
  mo.region_materials[0].edge_laws[0] = {0.5, 1.0, 1.5};
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  mo.volume_group = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.03, 0.02, 0.04)), o, "block").info.tet_cube_id;
  const msd::Model m = msd::build_model(mesh, mo);
  ASSERT_EQ(m.volume_groups.bulk_law.size(), static_cast<size_t>(m.volume_groups.size()));
  msd::Points x, v;
  deform(m, 0.45, 0.001, x, v);
  const msd::SystemLayout L = msd::make_system_layout(m);
  Eigen::SparseMatrix<double> K = L.pattern;
  msd::assemble_system(m, L, x, v, 0.0, 0.0, 1.0, K);
  const Eigen::MatrixXd Kfd = fd_jacobian(m, x, v, false, 1e-7);
  EXPECT_LT((Eigen::MatrixXd(K) - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
  // The bulk term matters here (at nu = 0.45 its K = lambda - mu is about 2.8 E;
  // the thesis' terms, crushed to 0.45, dominate the largest entries).
  mo.terms &= ~msd::kBulk;
  mo.volume_group.clear();
  const msd::Model without = msd::build_model(mesh, mo);
  Eigen::SparseMatrix<double> K0 = L.pattern;
  msd::assemble_system(without, L, x, v, 0.0, 0.0, 1.0, K0);
  EXPECT_GT((Eigen::MatrixXd(K) - Eigen::MatrixXd(K0)).cwiseAbs().maxCoeff(), 0.01 * Kfd.cwiseAbs().maxCoeff());
}

TEST(Implicit, ExtremeCompressionOfTheNeoHookeanElementEndsFiniteAndUninvertedWithBdf2) {
  // The stability extreme (strain -0.9 in 0.1 s, then held) with the
  // continuum element at nu = 0.45 and the dampers, BDF2 at 5 ms steps with the
  // symmetric LDLT solve.
  msd::Model m = block(msd::kNeoHookean | msd::kDampers, 1, true);
  m.newton.linear_solver = msd::LinearSolver::symmetric_ldlt;
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  const double dt = 5e-3, speed = 0.9 * 0.04 / 0.1;
  for (int k = 1; k <= 60; ++k) {
    const double t = std::min(k * dt, 0.1);
    msd::Controls c{{Vec3::Zero(), Vec3(0, 0, -speed * t)}, {Vec3::Zero(), Vec3(0, 0, k * dt <= 0.1 ? -speed : 0.0)}};
    msd::step(m, s, c, dt, msd::Integrator::Bdf2, scratch);
  }
  ASSERT_TRUE(s.x.allFinite());
  std::vector<msd::Tet> tets;
  for (const msd::Element& el : m.elements) tets.push_back(el.nodes);
  EXPECT_EQ(msd::count_inverted(s.x, tets), 0);
}

// A stiff block squeezed 2 cm in one 10 ms step with Newton allowed one
// iteration and `cuts` halvings to a tolerance it cannot reach: the failure.
msd::SimulationFailure failed_solve(msd::Integrator integ, int cuts) {
  msd::Model m = block(kAll, 1, true, 3.0e5);
  m.newton.max_iterations = 1;
  m.newton.max_step_cuts = cuts;
  m.newton.tolerance = 1e-14;
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero(), Vec3(0, 0, -0.02)}, {Vec3::Zero(), Vec3(0, 0, -2.0)}};
  try {
    msd::step(m, s, c, 1e-2, integ, scratch);
  } catch (const msd::SimulationFailure& f) {
    return f;
  }
  ADD_FAILURE() << "expected a SimulationFailure";
  return msd::SimulationFailure("no failure", 0.0, 0, -1, -1);
}

TEST(Implicit, ANewtonSolveThatDoesNotConvergeSaysWhenWhereAndTheResidual) {
  {
    const msd::SimulationFailure f = failed_solve(msd::Integrator::BackwardEuler, 2);
    const std::string what = f.what();
    EXPECT_NE(what.find("did not converge after 1 iterations with the step cut 2 times to 0.0025 s"),
              std::string::npos) << what;
    EXPECT_NE(what.find("residual"), std::string::npos) << what;
    EXPECT_NE(what.find("N, tolerance"), std::string::npos) << what;
    // The end of the quarter step that failed: one of 2.5, 5, 7.5, 10 ms.
    EXPECT_NEAR(std::remainder(f.time, 2.5e-3), 0.0, 1e-15);
    EXPECT_GT(f.time, 0.0);
    EXPECT_LE(f.time, 1e-2 + 1e-15);
    EXPECT_EQ(f.step, 1);
    EXPECT_GE(f.node, 0);
  }
}

TEST(Implicit, BadNewtonOptionsAreRefusedByName) {
  msd::ModelOptions o;
  msd::TissueMaterial mat;
  mat.density = 1000;
  mat.k_s = 1;
  o.region_materials = {mat};
  o.newton.tolerance = 0.0;
  EXPECT_THROW(
      {
        try {
          msd::build_model(testing_support::corner_tet_mesh(0.1), o);
        } catch (const msd::Error& e) {
          EXPECT_NE(std::string(e.what()).find("newton tolerance"), std::string::npos);
          throw;
        }
      },
      msd::Error);
  o.newton.tolerance = 1e-8;
  o.newton.max_iterations = 0;
  EXPECT_THROW(msd::build_model(testing_support::corner_tet_mesh(0.1), o), msd::Error);
  o.newton.max_iterations = 20;
  for (int depth : {-1, 9}) {
    o.newton.anderson_depth = depth;
    try {
      msd::build_model(testing_support::corner_tet_mesh(0.1), o);
      ADD_FAILURE() << "anderson_depth " << depth << " was accepted";
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find("newton anderson_depth"), std::string::npos) << e.what();
    }
  }
  o.newton.anderson_depth = 8;
  EXPECT_NO_THROW(msd::build_model(testing_support::corner_tet_mesh(0.1), o));
  EXPECT_THROW(msd::parse_integrator("backward-euler"), msd::Error);
  EXPECT_EQ(msd::parse_integrator("backward_euler"), msd::Integrator::BackwardEuler);
}

TEST(Implicit, OneScratchServesTwoModelsWithDifferentConstraints) {
  // Same mesh and counts, different prescribed nodes: the second model's
  // steps must use its own layout, not the first one's.
  const msd::Model pinned = block(kAll, 1, true), free_block = block(kAll, 1, false);
  msd::Scratch scratch;
  msd::State a = msd::rest_state(pinned);
  msd::step(pinned, a, {{Vec3::Zero(), Vec3(0, 0, -1e-3)}, {Vec3::Zero(), Vec3(0, 0, -0.1)}}, 1e-2,
            msd::Integrator::BackwardEuler, scratch);
  // A deformed free block stepped with the shared scratch and with a fresh
  // one: the same bits (the first model's pinned nodes would hold some
  // velocities at their start values).
  msd::State b = msd::rest_state(free_block);
  msd::Points x, v;
  deform(free_block, 0.8, 0.0005, x, v);
  b.x = x;
  b.v = v;
  msd::State fresh = b;
  msd::Scratch own;
  msd::step(free_block, b, {}, 1e-2, msd::Integrator::BackwardEuler, scratch);
  msd::step(free_block, fresh, {}, 1e-2, msd::Integrator::BackwardEuler, own);
  EXPECT_EQ((b.x - fresh.x).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((b.v - fresh.v).cwiseAbs().maxCoeff(), 0.0);
}

// --- The moving parts: strands, muscles, joints --------------------------------

namespace {

// Central differences of evaluate_forces - the tissue and the moving parts,
// under controls c - along every coordinate of y's positions (or velocities).
Eigen::MatrixXd fd_jacobian_with_parts(const msd::Model& m, msd::State y, const msd::Controls& c, bool of_velocity,
                                       double h) {
  const Eigen::Index n = 3 * m.num_nodes();
  Eigen::MatrixXd J(n, n);
  msd::Scratch scratch;
  for (Eigen::Index k = 0; k < n; ++k) {
    double* q = (of_velocity ? y.v.data() : y.x.data()) + k;
    const double keep = *q;
    *q = keep + h;
    msd::evaluate_forces(m, y, c, scratch);
    const msd::Points up = scratch.f;
    *q = keep - h;
    msd::evaluate_forces(m, y, c, scratch);
    *q = keep;
    J.col(k) = (Eigen::Map<const Eigen::VectorXd>(up.data(), n) - Eigen::Map<const Eigen::VectorXd>(scratch.f.data(), n)) / (2 * h);
  }
  return J;
}

// The block with platens, a three-node strand up its middle anchored on the
// top platen, a free two-node strand, and a muscle of the vertical edges.
msd::Model block_with_parts(double k_t) {
  msd::Model m = block(msd::kSprings | msd::kDampers | msd::kRepulsion | msd::kVolume, 1, true);
  std::vector<int> column;
  for (int z = 1; z <= 3; ++z)
    for (int i = 0; i < m.num_nodes(); ++i)
      if ((m.rest_positions.col(i) - Vec3(0.01, 0.01, 0.01 * z)).norm() < 1e-9) column.push_back(i);
  EXPECT_EQ(column.size(), 3u);
  msd::Strand anchored{column, 0.0, k_t, 1, Vec3(0.01, 0.01, 0.04)};
  msd::Strand free_strand{{column[0], column[2]}, 0.0, k_t, -1, Vec3::Zero()};
  for (msd::Strand* s : {&anchored, &free_strand})
    s->natural_length = testing_support::polyline_length(m.rest_positions, s->nodes) + (s->anchor_group >= 0 ? 0.01 : 0.0);
  m.strands = {anchored, free_strand};
  msd::Muscle mu;
  mu.name = "vertical";
  mu.unit_force = 0.05;
  mu.force_length = {true, 0.5};
  for (int e = 0; e < m.plan.num_edges(); ++e) {
    const int a = m.plan.edge_a[static_cast<size_t>(e)], b = m.plan.edge_b[static_cast<size_t>(e)];
    const Vec3 l = m.rest_positions.col(b) - m.rest_positions.col(a);
    if (std::abs(l.normalized().z()) > 0.99) mu.units.push_back({a, b, l.norm()});
  }
  m.muscles = {mu};
  msd::check_model_parts(m);
  return m;
}

msd::Controls pulling(const msd::Model& m, double top_lift) {
  msd::Controls c = at_rest(m);
  c.group_offset[1] = Vec3(0, 0, top_lift);
  c.activation = {0.8};
  c.strand_natural_length = {m.strands[0].natural_length, 0.7 * m.strands[1].natural_length};
  return c;
}

}  // namespace

TEST(Implicit, AssembledJacobiansOfStrandsAndMusclesMatchFiniteDifferences) {
  const msd::Model m = block_with_parts(2.0e3);
  msd::Points x, v;
  deform(m, 0.8, 0.0005, x, v);
  const msd::Controls c = pulling(m, 0.004);
  msd::State s = msd::rest_state(m);
  s.x = x;
  s.v = v;
  msd::apply_group_constraints(m, c, s.joints, s.x, s.v);
  msd::Scratch scratch;
  msd::evaluate_forces(m, s, c, scratch);
  ASSERT_GT(scratch.strand_tension[0], 0.0);  // both strands taut, the muscle pulling
  ASSERT_GT(scratch.strand_tension[1], 0.0);
  const msd::SystemLayout L = msd::make_system_layout(m);
  Eigen::SparseMatrix<double> K = L.pattern;
  msd::assemble_system(m, L, s.x, s.v, s.joints, c, 0.0, 0.0, 1.0, K);
  const Eigen::Index n = 3 * m.num_nodes();
  Eigen::MatrixXd Kfd = fd_jacobian_with_parts(m, s, c, false, 1e-8);
  // Compared on the free degrees of freedom: the anchor is not one (moving a
  // platen node by hand moves the anchor in the differences, never in a step).
  Eigen::MatrixXd diff = Eigen::MatrixXd(K) - Kfd;
  for (Eigen::Index k = 0; k < n; ++k)
    if (L.fixed[static_cast<size_t>(k)]) {
      diff.row(k).setZero();
      diff.col(k).setZero();
      Kfd.row(k).setZero();
      Kfd.col(k).setZero();
    }
  EXPECT_LT(diff.cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
}

TEST(Implicit, AssembledJacobiansOfTheSkinMembraneMatchFiniteDifferences) {
  // The free block wrapped in a skin on its boundary faces, ten times stiffer
  // per unit width than a centimetre of the block (E h = 300 N/m against
  // 3 kPa x 1 cm), squeezed to 0.8 of its height and jittered by 2 mm: Newton's matrix against central
  // differences of the forces, with the skin's share checked to matter.
  msd::Model m = block(kAll);
  std::vector<msd::Tet> tets;
  for (const msd::Element& e : m.elements) tets.push_back(e.nodes);
  const std::vector<msd::Tri> faces = msd::boundary_faces(tets);
  m.skin = msd::make_skin_membrane(m.rest_positions, faces, 3.0e5, 1.0e-3);
  ASSERT_EQ(m.skin.triangles.size(), faces.size());
  msd::Points x, v;
  deform(m, 0.8, 0.002, x, v);
  msd::State s = msd::rest_state(m);
  s.x = x;
  const msd::Controls c = at_rest(m);
  const msd::SystemLayout L = msd::make_system_layout(m);
  Eigen::SparseMatrix<double> K = L.pattern;
  msd::assemble_system(m, L, s.x, s.v, s.joints, c, 0.0, 0.0, 1.0, K);
  const Eigen::MatrixXd Kfd = fd_jacobian_with_parts(m, s, c, false, 1e-8);
  EXPECT_LT((Eigen::MatrixXd(K) - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
  msd::Model bare = m;
  bare.skin = {};
  EXPECT_GT((Kfd - fd_jacobian_with_parts(bare, s, c, false, 1e-8)).cwiseAbs().maxCoeff(),
            0.2 * Kfd.cwiseAbs().maxCoeff());  // the skin matters
}

TEST(Implicit, AStiffStrandStaysBoundedAtAStepWhereSymplecticEulerBlowsUp) {
  // Tendon-like stiffness: k_t = E A / L0 with E = 1.2 GPa, A = 2e-5 m^2 and
  // L0 = 2 cm, on nodes of about 0.1 g: sqrt(m / k) is about 14 microseconds.
  const msd::Model m = block_with_parts(1.2e9 * 2e-5 / 0.02);
  const msd::Controls c = pulling(m, 0.002);
  const double dt = 1e-3;
  msd::State be = msd::rest_state(m), se = msd::rest_state(m);
  msd::Scratch s1, s2;
  for (int i = 0; i < 50; ++i) msd::step(m, be, c, dt, msd::Integrator::BackwardEuler, s1);
  EXPECT_TRUE(be.x.allFinite());
  EXPECT_LT((be.x - m.rest_positions).cwiseAbs().maxCoeff(), 0.01);  // under a centimetre in a 4 cm block
  EXPECT_GT(s1.strand_tension[1], 0.0);  // the free strand, pre-tensioned, still pulls
  EXPECT_THROW(
      for (int i = 0; i < 50; ++i) msd::step(m, se, c, dt, msd::Integrator::SymplecticEuler, s2),
      msd::SimulationFailure);
}

TEST(Implicit, ModifiedNewtonReusesItsFactorisationAndConvergesToTheSameSteps) {
  // The squeezed block released with every term on, 40 steps of 5 ms: with
  // reuse the steps meet the same tolerance with fewer factorisations.
  msd::Points x, v;
  double total[2] = {0.0, 0.0};
  long factorizations[2] = {0, 0}, iterations[2] = {0, 0};
  msd::Points end[2];
  for (int reuse = 0; reuse < 2; ++reuse) {
    msd::Model m = block(kAll);
    m.newton.reuse_factorization = reuse == 1;
    deform(m, 0.7, 0.0005, x, v);
    msd::State s = msd::rest_state(m);
    s.x = x;
    s.v = v;
    msd::Scratch scratch;
    for (int k = 0; k < 40; ++k) msd::step(m, s, at_rest(m), 5e-3, msd::Integrator::BackwardEuler, scratch);
    end[reuse] = s.x;
    total[reuse] = (s.x - m.rest_positions).norm();
    factorizations[reuse] = scratch.factorizations;
    iterations[reuse] = scratch.newton_iterations;
  }
  EXPECT_EQ(factorizations[0], iterations[0]);  // full Newton: one per iteration
  EXPECT_LT(factorizations[1], iterations[1]);
  EXPECT_LT(factorizations[1], factorizations[0] / 2);
  // Both solve G = 0 to 1e-8 of the balance's largest term: the trajectories
  // agree far below the motion itself.
  EXPECT_LT((end[1] - end[0]).cwiseAbs().maxCoeff(), 1e-6 * total[0]);
}

// --- BDF2 ----------------------------------------------------------------------

namespace {

// The oscillator of run_oscillator stepped through a repeating pattern of
// step lengths (scaled by `scale`), to t_end; returns z - 1 of the free node.
double run_pattern(msd::Integrator integ, const std::vector<double>& pattern, double scale, double t_end) {
  const msd::Model m = oscillator();
  msd::State s = msd::rest_state(m);
  s.x(2, 3) += 1e-3;
  msd::Scratch scratch;
  for (size_t k = 0; s.t < t_end - 1e-12; ++k)
    msd::step(m, s, at_rest(m), std::min(scale * pattern[k % pattern.size()], t_end - s.t), integ, scratch);
  return s.x(2, 3) - 1.0;
}

}  // namespace

TEST(Implicit, Bdf2ConvergesAtSecondOrder) {
  // Halving the step quarters the error (the first, backward-Euler step adds
  // an O(dt^2) error once, so the order holds).
  const double ref = run_oscillator(msd::Integrator::VelocityVerlet, 1e-5, 0.5);
  const double e1 = std::abs(run_oscillator(msd::Integrator::Bdf2, 2e-3, 0.5) - ref);
  const double e2 = std::abs(run_oscillator(msd::Integrator::Bdf2, 1e-3, 0.5) - ref);
  EXPECT_NEAR(e1 / e2, 4.0, 0.6);
  // And at the same step it is far closer than backward Euler.
  EXPECT_LT(e1, 0.1 * std::abs(run_oscillator(msd::Integrator::BackwardEuler, 2e-3, 0.5) - ref));
}

TEST(Implicit, Bdf2KeepsSecondOrderWhenTheStepChangesEveryStep) {
  // Steps alternating between h and 1.7 h (ratios 1.7 and 1/1.7): the
  // variable-step coefficients keep the order; the constant-step ones
  // (4/3, 1/3, 2/3) would not.
  const std::vector<double> pattern{1.0, 1.7};
  const double ref = run_oscillator(msd::Integrator::VelocityVerlet, 1e-5, 0.5);
  const double e1 = std::abs(run_pattern(msd::Integrator::Bdf2, pattern, 2e-3, 0.5) - ref);
  const double e2 = std::abs(run_pattern(msd::Integrator::Bdf2, pattern, 1e-3, 0.5) - ref);
  EXPECT_NEAR(e1 / e2, 4.0, 0.8);
}

TEST(Implicit, Bdf2DampsAResolvedFreeVibrationFarLessThanBackwardEuler) {
  // Springs only: the exact motion keeps its energy. At omega dt = 0.057
  // (4.5 Hz, 2 ms) backward Euler's amplitude falls by 1/sqrt(1 + (omega
  // dt)^2) a step - its energy to e^-1.6 = 0.2 in 500 steps - while BDF2's
  // damping per step is of order (omega dt)^4 / 4: under 1 % in 500 steps.
  double end[2];
  int k = 0;
  for (msd::Integrator integ : {msd::Integrator::BackwardEuler, msd::Integrator::Bdf2}) {
    const msd::Model m = oscillator();
    msd::State s = msd::rest_state(m);
    s.x(2, 3) += 1e-2;
    msd::Scratch scratch;
    const double e0 = spring_energy(m, s);
    double peak = 0.0;
    for (int i = 0; i < 500; ++i) {
      msd::step(m, s, at_rest(m), 2e-3, integ, scratch);
      peak = std::max(peak, spring_energy(m, s));
    }
    EXPECT_LE(peak, e0 * (1 + 1e-3)) << msd::to_string(integ);  // never gains energy
    end[k++] = spring_energy(m, s) / e0;
  }
  EXPECT_LT(end[0], 0.3);
  EXPECT_GT(end[1], 0.99);
}

TEST(Implicit, Bdf2StaysBoundedFarBeyondTheExplicitStabilityLimitAndDampsWhatItCannotResolve) {
  // dt = 0.2 s, omega dt about 5.6: L-stable, so the unresolved vibration decays.
  EXPECT_LT(std::abs(run_oscillator(msd::Integrator::Bdf2, 0.2, 10.0)), 1e-4);
}

TEST(Implicit, Bdf2StartsWithABackwardEulerStepAndRestartsAfterAnotherIntegrator) {
  const msd::Model m = oscillator();
  msd::State a = msd::rest_state(m);
  a.x(2, 3) += 1e-2;
  msd::State b = a;
  msd::Scratch sa, sb;
  msd::step(m, a, at_rest(m), 2e-3, msd::Integrator::Bdf2, sa);
  msd::step(m, b, at_rest(m), 2e-3, msd::Integrator::BackwardEuler, sb);
  EXPECT_EQ((a.x - b.x).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(a.dt_prev, 2e-3);  // the history is kept ...
  EXPECT_EQ(b.dt_prev, 0.0);   // ... only by BDF2
  // The second BDF2 step uses it: it differs from a backward-Euler step.
  msd::State a2 = a, b2 = a;
  msd::step(m, a2, at_rest(m), 2e-3, msd::Integrator::Bdf2, sa);
  msd::step(m, b2, at_rest(m), 2e-3, msd::Integrator::BackwardEuler, sb);
  EXPECT_GT((a2.x - b2.x).cwiseAbs().maxCoeff(), 0.0);
  // Another integrator's step drops it; the next BDF2 step is backward Euler.
  msd::step(m, b2, at_rest(m), 2e-3, msd::Integrator::SymplecticEuler, sb);
  EXPECT_EQ(b2.dt_prev, 0.0);
  // (Fresh scratches: a kept factorisation would change the last bits.)
  msd::State c = b2, d = b2;
  msd::Scratch sc, sd;
  msd::step(m, c, at_rest(m), 2e-3, msd::Integrator::Bdf2, sc);
  msd::step(m, d, at_rest(m), 2e-3, msd::Integrator::BackwardEuler, sd);
  EXPECT_EQ((c.x - d.x).cwiseAbs().maxCoeff(), 0.0);
  // A step more than twice the last restarts it too.
  msd::State e = c, f = c;
  msd::Scratch se, sf;
  EXPECT_EQ(c.dt_prev, 2e-3);
  msd::step(m, e, at_rest(m), 5e-3, msd::Integrator::Bdf2, se);
  msd::step(m, f, at_rest(m), 5e-3, msd::Integrator::BackwardEuler, sf);
  EXPECT_EQ((e.x - f.x).cwiseAbs().maxCoeff(), 0.0);
}

namespace {

// The platens of block(..., platens = true) at the end of step k of 5 ms:
// the top squeezes the block to -0.6 in 0.1 s and holds it there.
constexpr double kSqueezeDt = 5e-3, kSqueezeSpeed = 0.6 * 0.04 / 0.1;
msd::Controls squeezed(int k) {
  const double t = std::min(k * kSqueezeDt, 0.1);
  const double vz = k * kSqueezeDt <= 0.1 ? -kSqueezeSpeed : 0.0;
  return {{Vec3::Zero(), Vec3(0, 0, -kSqueezeSpeed * t)}, {Vec3::Zero(), Vec3(0, 0, vz)}};
}

}  // namespace

TEST(Implicit, Bdf2WithTheFullModelAndPlatensIsBitIdenticalOnAnyThreadCountAndEndsUninverted) {
  // The block squeezed to -0.6 in 0.1 s and held, every term on, 5 ms steps.
  auto run = [](int threads) {
    const msd::Model m = block(kAll, threads, true);
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    for (int k = 1; k <= 40; ++k) {
      msd::step(m, s, squeezed(k), kSqueezeDt, msd::Integrator::Bdf2, scratch);
      const double t = std::min(k * kSqueezeDt, 0.1);
      for (int node : m.groups[1].nodes) EXPECT_EQ(s.x(2, node), m.rest_positions(2, node) - kSqueezeSpeed * t);
    }
    for (const msd::Element& el : m.elements) {
      const auto& n = el.nodes;
      EXPECT_GT(msd::tet_signed_volume(s.x.col(n[0]), s.x.col(n[1]), s.x.col(n[2]), s.x.col(n[3])), 0.0);
    }
    return s.x;
  };
  const msd::Points one = run(1), again = run(1), two = run(2);
  ASSERT_TRUE(one.allFinite());
  EXPECT_EQ((one - again).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Implicit, ABdf2SolveThatDoesNotConvergeNamesItsIntegrator) {
  const msd::SimulationFailure f = failed_solve(msd::Integrator::Bdf2, 1);
  EXPECT_NE(std::string(f.what()).find("BDF2: Newton did not converge"), std::string::npos) << f.what();
}

TEST(Implicit, AStepFromRestWithNoLoadConvergesAtRoundOff) {
  // Rest positions off by round-off (as a mesher's are): forces of about
  // eps k L, no load, nothing moving. The balance's largest term is then
  // round-off itself; Newton stops at the round-off force, not asking for
  // a residual 1e-8 of it (before: "did not converge", residual 3e-18 N
  // against a tolerance of 7e-24 N on the indentation benchmark).
  for (msd::Integrator integ : {msd::Integrator::BackwardEuler, msd::Integrator::Bdf2}) {
    const msd::Model m = block(kAll);
    msd::State s = msd::rest_state(m);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (Eigen::Index i = 0; i < s.x.size(); ++i) s.x.data()[i] *= 1.0 + 4e-16 * u(rng);
    msd::Scratch scratch;
    for (int k = 0; k < 3; ++k) ASSERT_NO_THROW(msd::step(m, s, {}, 1e-2, integ, scratch)) << msd::to_string(integ);
    EXPECT_LT((s.x - m.rest_positions).cwiseAbs().maxCoeff(), 1e-12);
  }
}

namespace {

// The block with its base pinned and a stick plane (normal -z: the object
// fills z > 4 cm) resting on its top face.
msd::Model block_under_a_plane(msd::ContactResponse response = msd::ContactResponse::Stick) {
  msd::ModelOptions mo;
  const msd::TetMesh mesh = block_mesh(kAll, 1, 3000.0, mo);
  msd::KinematicGroup base{"base", {}, {true, true, true}};
  for (int i = 0; i < mesh.num_nodes(); ++i)
    if (mesh.nodes(2, i) < 1e-9) base.nodes.push_back(i);
  mo.groups = {base};
  msd::RigidObstacle ob;
  ob.name = "plate";
  ob.shape = msd::ObstacleShape::Plane;
  ob.plane.point = Vec3(0, 0, 0.04);
  ob.plane.normal = Vec3(0, 0, -1);
  ob.response = response;
  mo.obstacles = {ob};
  return msd::build_model(mesh, mo);
}

msd::Controls plate_at(const msd::Model& m, double z_offset, double z_velocity) {
  msd::Controls c;
  c.group_offset.assign(m.groups.size(), Vec3::Zero());
  c.group_velocity.assign(m.groups.size(), Vec3::Zero());
  c.obstacle_offset = {Vec3(0, 0, z_offset)};
  c.obstacle_velocity = {Vec3(0, 0, z_velocity)};
  return c;
}

}  // namespace

TEST(Implicit, AStickObstacleHoldsItsContactsInsideTheSolveAndLetsGoWhereItWouldPull) {
  // The plate presses 1 mm into the block over ten steps of 10 ms. The
  // nodes on it at each step's start move with it (stick): their x and y
  // stay where they touched, z is the plate's. Before, the solve let them
  // slide with the block's bulge and the projection afterwards only put z
  // back. Then the plate is withdrawn at 10 cm/s, faster than the block's
  // surface can follow: holding would take a pull, so every top node goes
  // free and lags behind the plate.
  for (msd::Integrator integ : {msd::Integrator::BackwardEuler, msd::Integrator::Bdf2}) {
    const msd::Model m = block_under_a_plane();
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    const double dt = 1e-2;
    std::vector<int> top;
    for (int i = 0; i < m.num_nodes(); ++i)
      if (m.rest_positions(2, i) > 0.04 - 1e-9) top.push_back(i);
    ASSERT_FALSE(top.empty());
    double z = 0.0;
    for (int k = 1; k <= 10; ++k) {
      z = -1e-4 * k;
      msd::step(m, s, plate_at(m, z, -0.01), dt, integ, scratch);
      for (int n : top) {
        EXPECT_NEAR(s.x(0, n), m.rest_positions(0, n), 1e-15) << msd::to_string(integ) << " node " << n << " step " << k;
        EXPECT_NEAR(s.x(1, n), m.rest_positions(1, n), 1e-15) << msd::to_string(integ) << " node " << n << " step " << k;
        EXPECT_NEAR(s.x(2, n), 0.04 + z, 1e-15) << msd::to_string(integ) << " node " << n << " step " << k;
      }
    }
    // Withdrawn: 1 mm per 10 ms upwards.
    for (int k = 1; k <= 3; ++k) {
      z += 1e-3;
      msd::step(m, s, plate_at(m, z, 0.1), dt, integ, scratch);
    }
    for (int n : top) EXPECT_LT(s.x(2, n), 0.04 + z - 1e-3) << msd::to_string(integ) << " node " << n;
    EXPECT_TRUE(s.x.allFinite());
  }
}

TEST(Implicit, AFrictionlessObstacleHoldsOnlyItsContactsNormalMotionAndTheyStayOnItsSurface) {
  // As above with a frictionless plate: the held nodes follow it along z and
  // slide along it - the block's bulge carries the top face's edges
  // outwards - and a node that slid stays on the surface, held again at the
  // next step. Withdrawn fast, they are let go.
  for (msd::Integrator integ : {msd::Integrator::BackwardEuler, msd::Integrator::Bdf2}) {
    const msd::Model m = block_under_a_plane(msd::ContactResponse::Frictionless);
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    const double dt = 1e-2;
    std::vector<int> top;
    for (int i = 0; i < m.num_nodes(); ++i)
      if (m.rest_positions(2, i) > 0.04 - 1e-9) top.push_back(i);
    double z = 0.0;
    for (int k = 1; k <= 10; ++k) {
      z = -1e-4 * k;
      msd::step(m, s, plate_at(m, z, -0.01), dt, integ, scratch);
      for (int n : top)
        EXPECT_NEAR(s.x(2, n), 0.04 + z, 1e-15) << msd::to_string(integ) << " node " << n << " step " << k;
    }
    double slide = 0.0;
    for (int n : top) slide = std::max(slide, (s.x.col(n) - m.rest_positions.col(n)).head<2>().norm());
    EXPECT_GT(slide, 1e-6) << msd::to_string(integ);
    for (int k = 1; k <= 3; ++k) {
      z += 1e-3;
      msd::step(m, s, plate_at(m, z, 0.1), dt, integ, scratch);
    }
    for (int n : top) EXPECT_LT(s.x(2, n), 0.04 + z - 1e-3) << msd::to_string(integ) << " node " << n;
  }
}

TEST(Implicit, TheSymmetricLdltSolverConvergesToTheStepsOfSparseLuWithTheFullModelPlatensAndAFrictionlessPlate) {
  // Newton's matrix is not symmetric with every term on (the dampers'
  // position derivatives, the volume term), and its frictionless hold turns
  // the held rows to the tangent plane: factorising (A + A^T)/2 is an
  // approximate Newton. Its steps meet the same tolerance, so both runs agree
  // far below the motion; being approximate, it takes more iterations.
  struct Run {
    msd::Points x;
    long iterations = 0;
  };
  auto squeeze = [](msd::LinearSolver solver) {
    msd::Model m = block(kAll, 1, true);
    m.newton.linear_solver = solver;
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    for (int k = 1; k <= 40; ++k) msd::step(m, s, squeezed(k), kSqueezeDt, msd::Integrator::Bdf2, scratch);
    return Run{s.x, scratch.newton_iterations};
  };
  auto press = [](msd::LinearSolver solver) {
    msd::Model m = block_under_a_plane(msd::ContactResponse::Frictionless);
    m.newton.linear_solver = solver;
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    for (int k = 1; k <= 10; ++k) msd::step(m, s, plate_at(m, -1e-4 * k, -0.01), 1e-2, msd::Integrator::Bdf2, scratch);
    return Run{s.x, scratch.newton_iterations};
  };
  for (int scene = 0; scene < 2; ++scene) {
    const auto run = scene == 0 ? +squeeze : +press;
    const Run lu = run(msd::LinearSolver::sparse_lu), ldlt = run(msd::LinearSolver::symmetric_ldlt);
    const msd::Model m = block(kAll);
    ASSERT_TRUE(ldlt.x.allFinite()) << scene;
    const double motion = (lu.x - m.rest_positions).cwiseAbs().maxCoeff();
    EXPECT_GT(motion, 1e-4) << scene;
    EXPECT_LT((ldlt.x - lu.x).cwiseAbs().maxCoeff(), 1e-6 * motion) << scene;
    EXPECT_GT(ldlt.iterations, lu.iterations) << scene;
  }
}

TEST(Implicit, AndersonAcceleratedChordStepsConvergeToTheSameStepsInFewerIterations) {
  // The squeezed block with every term on, factorising the symmetric part
  // of its non-symmetric Newton matrix: the chord steps contract at the rate
  // the asymmetry leaves. Mixing in the last chord steps (Anderson) takes
  // fewer iterations to the same tolerance, so the trajectories agree far
  // below the motion; the mix is all it changes (the same factorisations or
  // fewer). Depth 0 is the plain chord step, bit for bit.
  struct Run {
    msd::Points x;
    long iterations = 0, factorizations = 0;
  };
  auto squeeze = [](int depth) {
    msd::Model m = block(kAll, 1, true);
    m.newton.linear_solver = msd::LinearSolver::symmetric_ldlt;
    m.newton.anderson_depth = depth;
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    for (int k = 1; k <= 40; ++k) msd::step(m, s, squeezed(k), kSqueezeDt, msd::Integrator::Bdf2, scratch);
    return Run{s.x, scratch.newton_iterations, scratch.factorizations};
  };
  const Run plain = squeeze(0), again = squeeze(0), mixed = squeeze(3);
  const msd::Model m = block(kAll);
  EXPECT_EQ((plain.x - again.x).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_TRUE(mixed.x.allFinite());
  const double motion = (plain.x - m.rest_positions).cwiseAbs().maxCoeff();
  EXPECT_GT(motion, 1e-4);
  EXPECT_LT((mixed.x - plain.x).cwiseAbs().maxCoeff(), 1e-6 * motion);
  EXPECT_LT(mixed.iterations, plain.iterations) << "plain " << plain.iterations << ", mixed " << mixed.iterations;
  EXPECT_LE(mixed.factorizations, plain.factorizations);
}

TEST(Implicit, AssembledJacobiansOfToeStrandsAndHillMusclesMatchFiniteDifferences) {
  // The block's strands with a toe region (one inside it, one beyond) and its
  // muscle on the Hill law: dF/dx at rest velocities (where the rate's
  // direction term, left out, vanishes) and dF/dv at random velocities.
  msd::Model m = block_with_parts(2.0e3);
  for (msd::Strand& s : m.strands) s.toe_strain = 0.03;
  m.muscles[0].hill.enabled = true;
  m.muscles[0].hill.rest_fibre_stretch = 1.1;  // the passive element pulls too
  m.muscles[0].unit_force = 0.5;
  msd::check_model_parts(m);
  msd::Points x, v;
  deform(m, 0.9, 0.0005, x, v);
  msd::Controls c = pulling(m, 0.0002);
  msd::State s = msd::rest_state(m);
  s.x = x;
  s.v.setZero();
  msd::apply_group_constraints(m, c, s.joints, s.x, s.v);
  // The anchored strand 1.5 % past its natural length (in the toe), the free one 5 % (beyond).
  double length[2] = {0.0, 0.0};
  for (size_t k = 0; k < 2; ++k) {
    const msd::Strand& st = m.strands[k];
    const Vec3 anchor = st.anchor_group >= 0 ? msd::group_point(m, st.anchor_group, st.anchor_rest, s.x, s.joints, c) : Vec3::Zero();
    length[k] = testing_support::polyline_length(s.x, st.nodes, st.anchor_group >= 0 ? &anchor : nullptr);
  }
  c.strand_natural_length = {length[0] / 1.015, length[1] / 1.05};
  msd::Scratch scratch;
  msd::evaluate_forces(m, s, c, scratch);
  ASSERT_NEAR(scratch.strand_strain[0], 0.015, 1e-12);
  ASSERT_NEAR(scratch.strand_strain[1], 0.05, 1e-12);
  const msd::SystemLayout L = msd::make_system_layout(m);
  const Eigen::Index n = 3 * m.num_nodes();
  auto fd = [&](const msd::State& y, bool velocity) {
    return fd_jacobian_with_parts(m, y, c, velocity, velocity ? 1e-6 : 1e-8);
  };
  auto free_dofs = [&](Eigen::MatrixXd a) {
    for (Eigen::Index k = 0; k < n; ++k)
      if (L.fixed[static_cast<size_t>(k)]) {
        a.row(k).setZero();
        a.col(k).setZero();
      }
    return a;
  };
  Eigen::SparseMatrix<double> K = L.pattern, D = L.pattern;
  msd::assemble_system(m, L, s.x, s.v, s.joints, c, 0.0, 0.0, 1.0, K);
  const Eigen::MatrixXd Kfd = free_dofs(fd(s, false));
  EXPECT_LT((free_dofs(Eigen::MatrixXd(K)) - Kfd).cwiseAbs().maxCoeff(), 1e-6 * Kfd.cwiseAbs().maxCoeff());
  s.v = 0.05 * v / v.cwiseAbs().maxCoeff();  // up to 5 cm/s: the units lengthen and shorten
  msd::apply_group_constraints(m, c, s.joints, s.x, s.v);
  msd::assemble_system(m, L, s.x, s.v, s.joints, c, 0.0, 1.0, 0.0, D);
  const Eigen::MatrixXd Dfd = free_dofs(fd(s, true));
  EXPECT_LT((free_dofs(Eigen::MatrixXd(D)) - Dfd).cwiseAbs().maxCoeff(), 1e-6 * Dfd.cwiseAbs().maxCoeff());
  // The muscle's force-velocity damping is there: D differs from the dampers' alone.
  msd::Model plain = m;
  plain.muscles[0].hill.force_velocity = false;
  Eigen::SparseMatrix<double> D0 = L.pattern;
  msd::assemble_system(plain, L, s.x, s.v, s.joints, c, 0.0, 1.0, 0.0, D0);
  EXPECT_GT((Eigen::MatrixXd(D) - Eigen::MatrixXd(D0)).cwiseAbs().maxCoeff(), 0.01 * Dfd.cwiseAbs().maxCoeff());
}

namespace {

// A 5 x 1 x 1 cm cantilever of the lattice (h = 5 mm), clamped at x = 0 (a
// kinematic group), a dead load of `load` N in -z spread over its free end;
// isotropic springs and the bulk term at nu = 0.495 (nearly incompressible).
msd::Model cantilever(double load, unsigned terms = msd::kSprings | msd::kDampers | msd::kBulk) {
  msd::SampleMeshOptions o;
  o.spacing = 0.005;
  const auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.05, 0.01, 0.01)), o, "beam");
  msd::TissueMaterial mat;
  mat.mode = msd::ConstantsMode::Physical;
  mat.density = 1040;
  mat.youngs_modulus = 14950;
  mat.damping_time = 4.2e-3;
  mat.poisson_ratio = 0.495;
  const double d = 3 * (14950 / (2 * 1.495)) / (msd::kLatticeStiffnessFactor * 14950);  // C44 = mu (bulk_volume.hpp)
  mat.edge_laws[0].stiffness = d / 2;
  mat.edge_laws[1].stiffness = d;
  msd::ModelOptions mo;
  mo.terms = terms;
  mo.region_materials = {mat};
  if (terms & msd::kBulk) mo.volume_group = s.info.tet_cube_id;
  msd::KinematicGroup clamp{"clamp", {}, {true, true, true}};
  std::vector<int> tip;
  for (int i = 0; i < s.mesh.num_nodes(); ++i) {
    if (s.mesh.nodes(0, i) < 1e-9) clamp.nodes.push_back(i);
    if (s.mesh.nodes(0, i) > 0.05 - 1e-9) tip.push_back(i);
  }
  mo.groups = {clamp};
  mo.external_force = msd::Points::Zero(3, s.mesh.num_nodes());
  for (int i : tip) mo.external_force(2, i) = -load / static_cast<double>(tip.size());
  return msd::build_model(s.mesh, mo);
}

}  // namespace

TEST(QuasiStatic, AModelWithJointsObstaclesOrSelfContactIsRefusedByNameAndLeftUntouched) {
  // What the quasi-static step cannot hold: a hinge's motion is dynamic, and
  // obstacle and self-contact are held through the step's velocities. Each
  // is refused before the state changes, naming the part and the steps that
  // can (implicit.hpp, step_quasi_static).
  const msd::Model base = cantilever(2e-3);
  for (int k = 0; k < 3; ++k) {
    msd::Model m = base;
    std::string expected;
    if (k == 0) {
      m.joints.push_back(msd::Joint{});
      expected = "quasi-static: the model has 1 joints, whose motion is dynamic; use backward_euler or bdf2";
    } else if (k == 1) {
      m.obstacles.push_back(msd::RigidObstacle{});
      expected = "quasi-static: the model has 1 rigid obstacles";
    } else {
      m.self_contact = msd::SelfContactRegion{};
      expected = "quasi-static: the model has self-contact";
    }
    msd::State s = msd::rest_state(m);
    const msd::Points x0 = s.x;
    msd::Scratch scratch;
    msd::Controls c = at_rest(m);
    c.load_scale = 1.0;
    try {
      msd::step(m, s, c, 0.25, msd::Integrator::QuasiStatic, scratch);
      ADD_FAILURE() << k << ": accepted";
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << k << ": " << e.what();
    }
    EXPECT_EQ(s.t, 0.0) << k;
    EXPECT_TRUE(s.x == x0) << k;
  }
}

TEST(QuasiStatic, ANearlyIncompressibleCantileverReachesItsEquilibriumAtEveryLoadStep) {
  // Four load steps to a tip load that bends it visibly. Each step ends in
  // equilibrium - f(x, 0) + load = 0 on the free nodes - at a minimum of the
  // potential energy, in a few Newton iterations: near incompressibility the
  // linearised step's rotations change volumes to second order, and the
  // energy line search (not |G| alone) lets Newton take them.
  const double load = 2e-3;
  const msd::Model m = cantilever(load);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  msd::Controls c = at_rest(m);
  double tip = 0.0;
  for (int k = 1; k <= 4; ++k) {
    c.load_scale = 0.25 * k;
    ASSERT_NO_THROW(msd::step(m, s, c, 0.25, msd::Integrator::QuasiStatic, scratch)) << k;
    EXPECT_LE(scratch.last_newton_iterations, 12) << k;
    EXPECT_EQ(scratch.last_step_cuts, 0) << k;
    msd::Points f, zero = msd::Points::Zero(3, s.x.cols());
    msd::compute_internal_forces(m, s.x, zero, f);
    const msd::Points balance = f + c.load_scale * m.external_force;
    double worst = 0.0;
    for (int i = 0; i < m.num_nodes(); ++i)
      if (std::find(m.groups[0].nodes.begin(), m.groups[0].nodes.end(), i) == m.groups[0].nodes.end())
        worst = std::max(worst, balance.col(i).cwiseAbs().maxCoeff());
    EXPECT_LT(worst, 1e-6 * c.load_scale * load) << k;
    const double now = s.x.row(2).minCoeff();
    EXPECT_LT(now, tip) << k;  // each load step bends it further
    tip = now;
  }
  EXPECT_LT(tip, -0.002);  // bent by more than 4 % of its length
  // A minimum: moving any of a few free nodes raises the potential energy.
  const auto potential = [&](const msd::Points& x) {
    return msd::conservative_energy(m, x) - (m.external_force.array() * x.array()).sum();
  };
  const double u0 = potential(s.x);
  for (int node : {m.num_nodes() - 1, m.num_nodes() / 2})
    for (int a = 0; a < 3; ++a)
      for (double e : {1e-5, -1e-5}) {
        msd::Points y = s.x;
        y(a, node) += e;
        EXPECT_GT(potential(y), u0) << node << " " << a << " " << e;
      }
  // No inertia: the same load reached in one step lands on the same equilibrium.
  msd::State once = msd::rest_state(m);
  msd::Scratch scratch1;
  ASSERT_NO_THROW(msd::step(m, once, c, 1.0, msd::Integrator::QuasiStatic, scratch1));
  EXPECT_LT((once.x - s.x).cwiseAbs().maxCoeff(), 1e-6 * std::abs(tip));
}

TEST(QuasiStatic, ItIsParsedByNameAndTheDampersDoNotActOnIt) {
  EXPECT_EQ(msd::parse_integrator("quasi_static"), msd::Integrator::QuasiStatic);
  EXPECT_EQ(msd::to_string(msd::Integrator::QuasiStatic), "quasi_static");
  EXPECT_TRUE(msd::is_implicit(msd::Integrator::QuasiStatic));
  // The equilibrium does not depend on how fast the load came: with and
  // without dampers, in 1 s or in 1 ms, the same state.
  const auto end = [](unsigned terms, double dt) {
    const msd::Model m = cantilever(1e-3, terms);
    msd::State s = msd::rest_state(m);
    msd::Scratch scratch;
    msd::Controls c = at_rest(m);
    msd::step(m, s, c, dt, msd::Integrator::QuasiStatic, scratch);
    return s.x;
  };
  const msd::Points slow = end(msd::kSprings | msd::kDampers | msd::kBulk, 1.0);
  const msd::Points fast = end(msd::kSprings | msd::kDampers | msd::kBulk, 1e-3);
  const msd::Points undamped = end(msd::kSprings | msd::kBulk, 1e-3);
  const double scale = (slow - msd::rest_state(cantilever(1e-3)).x).cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 1e-4);
  EXPECT_LT((slow - fast).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_LT((fast - undamped).cwiseAbs().maxCoeff(), 1e-6 * scale);
}
