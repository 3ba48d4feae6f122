// Tests for msd/src/forces/force_engine.cpp: the plan (unique edges, summed
// constants, gather tables), the fast forces against the per-tet reference,
// bit-identical results for every thread count, and no allocation in a step.
#include "msd/forces/force_engine.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/forces/tet_frame.hpp"
#include "msd/integrate/step.hpp"
#include "msd/geometry/leg_generator.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "msd/scene/leg_model.hpp"
#include "allocation_counter.hpp"  // defines this binary's allocation functions: counts every allocation
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>
#include <random>
#include <set>

using msd::Vec3;

namespace {

constexpr unsigned kAll = msd::kSprings | msd::kDampers | msd::kRepulsion | msd::kVolume;

// A 4 x 3 x 5 cm block at h = 1 cm with physical constants (2 regions, so
// tets sharing an edge can carry different constants).
msd::Model block(unsigned terms, double threshold, int threads, bool cube_volumes = false) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.04, 0.03, 0.05)), o, "block");
  // Two layers, each a whole number of cubes (so a cube's tets share a material): the tet's centroid above 3 cm.
  for (size_t t = 0; t < s.mesh.tets.size(); ++t) {
    double z = 0.0;
    for (int i = 0; i < 4; ++i) z += 0.25 * s.mesh.nodes(2, s.mesh.tets[t][i]);
    s.mesh.region[t] = z > 0.03;
  }
  msd::TissueMaterial soft;
  soft.mode = msd::ConstantsMode::Physical;
  soft.density = 1000;
  soft.youngs_modulus = 3000;
  soft.damping_time = 0.01;
  soft.repulsion_factor = 0.5;
  soft.volume_factor = 1.6;
  soft.poisson_ratio = 0.45;  // the neo_hookean term's
  msd::TissueMaterial stiff = soft;
  stiff.youngs_modulus = 9000;
  msd::ModelOptions mo;
  mo.terms = terms;
  mo.nonlinear_threshold = threshold;
  mo.region_materials = {soft, stiff};
  mo.threads = threads;
  if (cube_volumes) mo.volume_group = s.info.tet_cube_id;
  return msd::build_model(s.mesh, mo);
}

using testing_support::deform;

double max_abs(const msd::Points& f) { return f.cwiseAbs().maxCoeff(); }

}  // namespace

TEST(ForcePlan, EachEdgeOnceWithTheConstantsOfEveryTetThatSharesIt) {
  const msd::Model m = block(kAll, 0.0, 1);
  std::set<std::pair<int, int>> edges;
  double ks = 0.0, kd = 0.0;
  for (const msd::Element& el : m.elements)
    for (int k = 0; k < 6; ++k) {
      const int a = el.nodes[msd::kTetEdges[k][0]], b = el.nodes[msd::kTetEdges[k][1]];
      edges.insert({std::min(a, b), std::max(a, b)});
      ks += el.k.k_s[k];
      kd += el.k.k_d[k];
    }
  const msd::ForcePlan& p = m.plan;
  ASSERT_EQ(p.num_edges(), static_cast<int>(edges.size()));
  // The five-tet lattice shares edges: far fewer unique edges than tet sides.
  EXPECT_LT(p.num_edges(), 6 * m.num_elements() / 3);
  double ps = 0.0, pd = 0.0;
  for (int e = 0; e < p.num_edges(); ++e) {
    EXPECT_LT(p.edge_a[e], p.edge_b[e]);
    EXPECT_NEAR(p.edge_rest[e], (m.rest_positions.col(p.edge_b[e]) - m.rest_positions.col(p.edge_a[e])).norm(), 1e-15);
    ps += p.edge_k_s[e];
    pd += p.edge_k_d[e];
  }
  EXPECT_NEAR(ps, ks, 1e-12 * ks);
  EXPECT_NEAR(pd, kd, 1e-12 * kd);
  // Gather tables: every node lists exactly the edges and corners it is in, in increasing order.
  ASSERT_EQ(p.node_edge.size(), 2 * edges.size());
  ASSERT_EQ(p.node_corner.size(), 4 * m.elements.size());
  for (int n = 0; n < m.num_nodes(); ++n) {
    for (int k = p.node_edge_offset[n]; k < p.node_edge_offset[n + 1]; ++k) {
      const int r = p.node_edge[k], e = r >> 1;
      EXPECT_EQ((r & 1) ? p.edge_b[e] : p.edge_a[e], n);
      if (k > p.node_edge_offset[n]) {
        EXPECT_LT(p.node_edge[k - 1], r);
      }
    }
    for (int k = p.node_corner_offset[n]; k < p.node_corner_offset[n + 1]; ++k)
      EXPECT_EQ(m.elements[p.node_corner[k] / 4].nodes[p.node_corner[k] % 4], n);
  }
}

TEST(ForceEngine, EqualsTheReferenceLoopForEachTermAndAllTogether) {
  for (unsigned terms : {unsigned(msd::kSprings), unsigned(msd::kDampers), unsigned(msd::kRepulsion),
                         unsigned(msd::kVolume), unsigned(msd::kNeoHookean), kAll, kAll | msd::kNeoHookean}) {
    for (double threshold : {0.0, 0.7}) {
      SCOPED_TRACE(msd::force_terms_to_string(terms) + ", threshold " + std::to_string(threshold));
      const msd::Model m = block(terms, threshold, 1);
      msd::Points x, v, fast, ref;
      deform(m, 0.75, 0.002, x, v);
      msd::Scratch s;
      const long active = msd::compute_forces_fast(m, x, v, fast, s);
      EXPECT_EQ(active, msd::compute_internal_forces_reference(m, x, v, ref));
      ASSERT_GT(max_abs(ref), 0.0);
      EXPECT_LE(max_abs(fast - ref), 1e-12 * max_abs(ref));
      if (threshold > 0 && (terms & (msd::kRepulsion | msd::kVolume))) {
        EXPECT_GT(active, 0);  // the squeeze makes the threshold matter both ways
        EXPECT_LT(active, m.num_elements());
      }
    }
  }
}

TEST(ForceEngine, TheVectorisedTetPassGivesTheScalarElementsBitsAcrossTheFloorAndInversion) {
  // The tets whose non-linear terms are on run in batches of eight lanes
  // (force_engine.cpp, nonlinear_batch_pass, on the CPU's widest instruction
  // set). Without the edge terms, each node's force
  // is its corners' sum in element order in both paths, so the batched
  // engine must give the scalar reference loop's bits exactly - crushed
  // below the repulsion floor (h < 0.01 h0) and inverted tets included, and
  // with a tet count that leaves spare lanes.
  for (unsigned terms : {unsigned(msd::kRepulsion), unsigned(msd::kVolume), unsigned(msd::kRepulsion | msd::kVolume)}) {
    for (int threads : {1, 2}) {
      SCOPED_TRACE(msd::force_terms_to_string(terms) + ", threads " + std::to_string(threads));
      // Thesis 5.8's threshold: only the tets it leaves on are batched, the others' corners are zero.
      {
        const msd::Model t = block(terms, 0.7, threads);
        msd::Points x, v, fast, ref;
        deform(t, 0.75, 0.002, x, v);
        msd::Scratch s;
        const long active = msd::compute_forces_fast(t, x, v, fast, s);
        EXPECT_EQ(active, msd::compute_internal_forces_reference(t, x, v, ref));
        EXPECT_GT(active, 0);
        EXPECT_LT(active, t.num_elements());
        EXPECT_TRUE((fast.array() == ref.array()).all()) << "largest difference " << max_abs(fast - ref);
      }
      const msd::Model m = block(terms, 0.0, threads);
      ASSERT_NE(m.num_elements() % 8, 0);
      msd::Points x, v, fast, ref;
      deform(m, 0.004, 0.0003, x, v, 5);
      long floored = 0, inverted = 0;
      for (const msd::Element& el : m.elements) {
        msd::Vec3 xe[4];
        for (int i = 0; i < 4; ++i) xe[i] = x.col(el.nodes[static_cast<size_t>(i)]);
        const msd::TetFrame g = msd::tet_frame(xe);
        bool below = false;
        for (int i = 0; i < 4; ++i) below = below || g.height[i] < el.floor * el.rest_height[i];
        floored += below;
        inverted += g.volume < 0.0;
      }
      EXPECT_GT(floored, 0);
      EXPECT_GT(inverted, 0);
      msd::Scratch s;
      EXPECT_EQ(msd::compute_forces_fast(m, x, v, fast, s), m.num_elements());
      msd::compute_internal_forces_reference(m, x, v, ref);
      ASSERT_TRUE(ref.allFinite());
      EXPECT_TRUE((fast.array() == ref.array()).all()) << "largest difference " << max_abs(fast - ref);
    }
  }
  EXPECT_NE(std::string(msd::force_engine_isa()), "");
}

TEST(ForceEngine, BitIdenticalForOneTwoAndThreeThreadsAndRepeatedCalls) {
  for (unsigned terms : {kAll, kAll | msd::kNeoHookean}) {
    SCOPED_TRACE(msd::force_terms_to_string(terms));
    msd::Points x, v, f1, again, f2, f3;
    const msd::Model m1 = block(terms, 0.7, 1), m2 = block(terms, 0.7, 2), m3 = block(terms, 0.7, 3);
    deform(m1, 0.8, 0.002, x, v, 11);
    msd::Scratch s;
    const long a1 = msd::compute_forces_fast(m1, x, v, f1, s);
    msd::compute_forces_fast(m1, x, v, again, s);
    EXPECT_EQ(a1, msd::compute_forces_fast(m2, x, v, f2, s));
    EXPECT_EQ(a1, msd::compute_forces_fast(m3, x, v, f3, s));
    EXPECT_TRUE((f1.array() == again.array()).all());
    EXPECT_TRUE((f1.array() == f2.array()).all());
    EXPECT_TRUE((f1.array() == f3.array()).all());
  }
}

TEST(ForceEngine, TheNeoHookeanElementWithCubeVolumesEqualsTheReferenceIsBitIdenticalOnAnyThreadCountAndIsMinusTheEnergysGradient) {
  const unsigned terms = msd::kNeoHookean | msd::kDampers;
  const msd::Model m1 = block(terms, 0.0, 1, true), m2 = block(terms, 0.0, 2, true);
  ASSERT_EQ(m1.volume_groups.size() * 5, m1.num_elements());  // five tets per cube
  msd::Points x, v, fast, fast2, ref;
  deform(m1, 0.75, 0.002, x, v);
  msd::Scratch s;
  msd::compute_forces_fast(m1, x, v, fast, s);
  msd::compute_forces_fast(m2, x, v, fast2, s);
  msd::compute_internal_forces_reference(m1, x, v, ref);
  ASSERT_GT(max_abs(ref), 0.0);
  EXPECT_LE(max_abs(fast - ref), 1e-12 * max_abs(ref));
  EXPECT_TRUE((fast.array() == fast2.array()).all());
  // Elastic forces only (no dampers): minus the gradient of conservative_energy, by central differences.
  const msd::Model elastic = block(msd::kNeoHookean, 0.0, 1, true);
  msd::Points f;
  msd::compute_forces_fast(elastic, x, v, f, s);
  const double h = 1e-8;
  double worst = 0.0;
  for (Eigen::Index k = 0; k < x.size(); k += 7) {
    msd::Points y = x;
    y.data()[k] += h;
    const double up = msd::conservative_energy(elastic, y);
    y.data()[k] -= 2 * h;
    const double down = msd::conservative_energy(elastic, y);
    worst = std::max(worst, std::abs(f.data()[k] + (up - down) / (2 * h)));
  }
  EXPECT_LT(worst, 1e-5 * max_abs(f));
}

TEST(ForceEngine, UnderAHomogeneousDeformationCubeVolumesGiveThePerTetForces) {
  // Every tet of a cube has the cube's volume ratio when the deformation is affine.
  const unsigned terms = msd::kNeoHookean;
  const msd::Model tets = block(terms, 0.0, 1), cubes = block(terms, 0.0, 1, true);
  msd::Mat3 A;
  A << 1.1, 0.2, -0.05, 0.03, 0.85, 0.1, 0.0, -0.15, 1.2;
  const msd::Points x = A * tets.rest_positions, v = msd::Points::Zero(3, tets.num_nodes());
  msd::Points f_tets, f_cubes;
  msd::Scratch s;
  msd::compute_forces_fast(tets, x, v, f_tets, s);
  msd::compute_forces_fast(cubes, x, v, f_cubes, s);
  ASSERT_GT(max_abs(f_tets), 0.0);
  EXPECT_LE(max_abs(f_tets - f_cubes), 1e-10 * max_abs(f_tets));
}

TEST(ForceEngine, ZeroNetForceAndTorque) {
  const msd::Model m = block(kAll, 0.0, 2);
  msd::Points x, v, f;
  deform(m, 0.7, 0.003, x, v);
  msd::Scratch s;
  msd::compute_forces_fast(m, x, v, f, s);
  Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    net += f.col(i);
    torque += Vec3(x.col(i)).cross(Vec3(f.col(i)));
  }
  EXPECT_LE(net.norm(), 1e-11 * max_abs(f));
  EXPECT_LE(torque.norm(), 1e-11 * max_abs(f) * 0.05);
}

TEST(ForceEngine, AStepOnTheReferencePathMatchesTheEngine) {
  msd::Model engine = block(kAll, 0.7, 2), reference = block(kAll, 0.7, 1);
  reference.reference_forces = true;
  msd::State a = msd::rest_state(engine), b;
  msd::Points v;
  deform(engine, 0.8, 0.001, a.x, v);
  b = a;
  msd::Scratch sa, sb;
  const msd::Controls c{};
  for (int k = 0; k < 10; ++k) {
    msd::step(engine, a, c, 1e-5, msd::Integrator::SymplecticEuler, sa);
    msd::step(reference, b, c, 1e-5, msd::Integrator::SymplecticEuler, sb);
  }
  EXPECT_EQ(sa.nonlinear_active, sb.nonlinear_active);
  EXPECT_LE((sa.f - sb.f).cwiseAbs().maxCoeff(), 1e-11 * sb.f.cwiseAbs().maxCoeff());
  EXPECT_LE((a.x - b.x).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(ForceEngine, AModelWithoutItsPlanIsRefused) {
  msd::Model m = block(kAll, 0.0, 1);
  m.plan = msd::ForcePlan{};
  msd::Points x = m.rest_positions, v = msd::Points::Zero(3, x.cols()), f;
  msd::Scratch s;
  EXPECT_THROW(msd::compute_forces_fast(m, x, v, f, s), msd::Error);
  msd::ModelOptions bad;
  bad.threads = 0;
  bad.region_materials = {msd::TissueMaterial{}};
  EXPECT_THROW(msd::build_model(testing_support::corner_tet_mesh(0.01), bad), msd::Error);
}

TEST(ForceEngine, AStepAllocatesNothingAfterTheFirst) {
  {
    const long before = testing_support::allocations();
    auto probe = std::make_unique<double>(1.0);  // the counter sees an allocation
    EXPECT_EQ(testing_support::allocations() - before, 1);
  }
#if !defined(__SANITIZE_ADDRESS__)
  {
    const long before = testing_support::allocations();
    Eigen::VectorXd probe(1000);  // and Eigen's (std::malloc; not counted under the sanitizer)
    probe.setZero();
    EXPECT_EQ(testing_support::allocations() - before, 1);
  }
#endif
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    const msd::Model m = block(kAll | msd::kGravity, 0.7, threads);
    msd::State st = msd::rest_state(m);
    msd::Points v;
    deform(m, 0.9, 0.001, st.x, v);
    msd::Scratch scratch;
    const msd::Controls c{};
    for (msd::Integrator integ : {msd::Integrator::SymplecticEuler, msd::Integrator::VelocityVerlet}) {
      msd::step(m, st, c, 1e-5, integ, scratch);  // sizes the buffers
      const long before = testing_support::allocations();
      for (int k = 0; k < 20; ++k) msd::step(m, st, c, 1e-5, integ, scratch);
      EXPECT_EQ(testing_support::allocations() - before, 0) << msd::to_string(integ);
    }
  }
}

TEST(ForceEngine, TheLegsStepAllocatesNothingAfterTheFirst) {
  // The shipped leg with every moving part at work: anchored, pre-tensioned
  // tendons, both muscles active, the knee dynamic, skin against skin behind
  // the knee, a rigid plane under the sole and the skin membrane.
  msd::LimbMeshOptions mo;
  mo.spacing = 0.0245;
  const msd::MeshedLeg meshed = msd::mesh_leg(std::string(TISSUEBENCH_DATA_DIR) + "/leg", mo);
  msd::LegModelOptions o;
  o.passive.density = 920;
  o.passive.mode = msd::ConstantsMode::Physical;
  o.passive.youngs_modulus = 2990;
  o.passive.damping_time = 4.2e-3;
  o.muscle = o.passive;
  o.knee_centre = msd::Vec3(0, 0, 0.50046);
  o.tendon_insertions.assign(meshed.tendons.size(), std::nullopt);
  for (size_t t = 0; t < meshed.tendons.size(); ++t) {
    const auto& strand = meshed.tendons[t].strands.front();
    o.tendon_insertions[t] = meshed.mesh.mesh.nodes.col(strand.back());  // at the route's bone node
  }
  o.knee_contact_box = std::make_pair(msd::Vec3(-0.15, -0.12, 0.38), msd::Vec3(0.0, 0.12, 0.62));
  msd::LegModelOptions::Obstacle floor;
  floor.object.name = "floor";
  floor.object.shape = msd::ObstacleShape::Plane;
  // 1 mm below the sole: every free surface node is tested, none pushed.
  floor.object.plane.point = msd::Vec3(0, 0, meshed.mesh.mesh.nodes.row(2).minCoeff() - 0.001);
  floor.object.plane.normal = msd::Vec3::UnitZ();
  o.obstacles = {floor};
  o.skin = msd::LegModelOptions::Skin{129e3, 1.55e-3};  // benchmarks/materials.yaml's skin
  const msd::LegModel leg = msd::build_leg_model(meshed.mesh, meshed.tendons, o);
  ASSERT_TRUE(leg.tissue.self_contact.has_value());
  ASSERT_FALSE(leg.tissue.skin.empty());
  ASSERT_TRUE(std::any_of(leg.strands.begin(), leg.strands.end(), [](const msd::LegStrand& s) { return s.anchored; }));
  msd::LegState s = msd::leg_rest_state(leg, 0.3);
  msd::LegControls c;
  c.tendon_length_scale = {0.95, 0.95, 0.95, 0.95};
  c.front_activation = 0.3;
  c.back_activation = 0.6;
  c.joint_torque = 1.0;
  msd::LegScratch scratch;
  msd::step_leg(leg, s, c, 1e-4, scratch);  // sizes the buffers
  const long before = testing_support::allocations();
  for (int k = 0; k < 20; ++k) msd::step_leg(leg, s, c, 1e-4, scratch);
  EXPECT_EQ(testing_support::allocations() - before, 0);
  EXPECT_GT(scratch.tendon_tension[0], 0.0);
  // With a scripted hip turning the femur (the controls taken back to each
  // step's start, the knee on its moving parent): nothing either.
  msd::RigidMotion hip;
  hip.angular_velocity = msd::Vec3(0, -1.0, 0);
  hip.angular_acceleration = msd::Vec3(0, -2.0, 0);
  auto femur_at = [&](int k) {
    msd::RigidMotion m = hip;
    m.rotation = Eigen::AngleAxisd(-1.0 * k * 1e-4, msd::Vec3::UnitY()).toRotationMatrix();
    return m;
  };
  c.femur = femur_at(1);
  msd::step_leg(leg, s, c, 1e-4, scratch);  // sizes the motion's buffers
  const long with_hip = testing_support::allocations();
  for (int k = 2; k < 22; ++k) {
    c.femur = femur_at(k);
    msd::step_leg(leg, s, c, 1e-4, scratch);
  }
  EXPECT_EQ(testing_support::allocations() - with_hip, 0);
  // The IMEX step (the strands' systems, imex_strands.hpp): nothing after its first.
  msd::step_leg(leg, s, c, 1e-4, scratch, msd::Integrator::ImexEuler);  // sizes the strands' systems
  const long with_imex = testing_support::allocations();
  for (int k = 22; k < 42; ++k) {
    c.femur = femur_at(k);
    msd::step_leg(leg, s, c, 1e-4, scratch, msd::Integrator::ImexEuler);
  }
  EXPECT_EQ(testing_support::allocations() - with_imex, 0);
  EXPECT_GT(scratch.tendon_tension[0], 0.0);
  // BDF2 with the symmetric part's LDLT (msd/integrate/implicit.hpp): Newton's
  // assembly, factorisations and solves allocate nothing after the first step.
  msd::LegModel ldlt_leg = leg;
  ldlt_leg.tissue.newton.linear_solver = msd::LinearSolver::symmetric_ldlt;
  msd::LegScratch implicit_scratch;
  msd::step_leg(ldlt_leg, s, c, 1e-3, implicit_scratch, msd::Integrator::Bdf2);  // sizes the system
  const long with_bdf2 = testing_support::allocations();
  const long factorizations = implicit_scratch.tissue.factorizations, cuts = implicit_scratch.tissue.step_cuts;
  for (int k = 42; k < 52; ++k) {
    c.femur = femur_at(k);
    msd::step_leg(ldlt_leg, s, c, 1e-3, implicit_scratch, msd::Integrator::Bdf2);
  }
  EXPECT_EQ(testing_support::allocations() - with_bdf2, 0);
  EXPECT_GT(implicit_scratch.tissue.factorizations, factorizations);
  // At 1 ms Newton fails on some of these steps and they are cut in halves:
  // the retry path (its halfway controls and joints) is covered too.
  EXPECT_GT(implicit_scratch.tissue.step_cuts, cuts);
}

TEST(ForceEngine, TheImplicitStepsWithTheSymmetricLdltAllocateNothingAfterTheFirst) {
  // Every term of the thesis element (springs, dampers, repulsion, volume),
  // backward Euler and BDF2, on 1 and 2 threads: the Jacobian's assembly, the
  // symmetric part's factorisation and its solves allocate nothing after the
  // first step; nor do the Anderson-accelerated chord steps (depth 3).
  for (int threads : {1, 2}) {
    for (int depth : {0, 3}) {
      SCOPED_TRACE(threads);
      SCOPED_TRACE(depth);
      msd::Model m = block(kAll | msd::kGravity, 0.7, threads);
      m.newton.linear_solver = msd::LinearSolver::symmetric_ldlt;
      m.newton.anderson_depth = depth;
      for (msd::Integrator integ : {msd::Integrator::BackwardEuler, msd::Integrator::Bdf2}) {
        msd::State st = msd::rest_state(m);
        msd::Points v;
        deform(m, 0.9, 0.001, st.x, v);
        msd::Scratch scratch;
        const msd::Controls c{};
        msd::step(m, st, c, 1e-3, integ, scratch);  // sizes the system and analyses its pattern
        const long before = testing_support::allocations();
        const long factorizations = scratch.factorizations;
        for (int k = 0; k < 10; ++k) msd::step(m, st, c, 1e-3, integ, scratch);
        EXPECT_EQ(testing_support::allocations() - before, 0) << msd::to_string(integ);
        EXPECT_GT(scratch.factorizations, factorizations) << msd::to_string(integ);
      }
    }
  }
}
