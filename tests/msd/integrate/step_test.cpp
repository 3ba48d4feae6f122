#include "msd/integrate/step.hpp"

#include "msd/forces/parts.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

using msd::Vec3;

namespace {

// One tet with nodes 0, 1, 2 pinned: node 3 oscillates on its three springs, a
// small smooth non-linear oscillator (about 4.5 Hz for k = 100 N/m, 0.25 kg).
msd::Model oscillator(double k, double mass_density) {
  const msd::TetMesh m = testing_support::corner_tet_mesh(1.0);
  msd::TissueMaterial mat;
  mat.density = mass_density;
  mat.k_s = k;
  msd::ModelOptions o;
  o.terms = msd::kSprings;
  o.region_materials = {mat};
  o.groups = {{"base", {0, 1, 2}, {true, true, true}}};
  return msd::build_model(m, o);
}

double run(const msd::Model& model, msd::Integrator integ, double dt, double t_end, double z0) {
  msd::State s = msd::rest_state(model);
  s.x(2, 3) = 1.0 + z0;
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  const long n = std::lround(t_end / dt);
  for (long i = 0; i < n; ++i) msd::step(model, s, c, dt, integ, scratch);
  return s.x(2, 3) - 1.0;
}

}  // namespace

TEST(Step, IntegratorsConvergeAtTheirOrder) {
  // Compare against a velocity-Verlet reference with a 200x smaller step.
  const msd::Model m = oscillator(100.0, 6.0);  // mass per node = 6 * (1/6) / 4
  const double ref = run(m, msd::Integrator::VelocityVerlet, 1e-5, 0.5, 1e-3);
  auto err = [&](msd::Integrator i, double dt) { return std::abs(run(m, i, dt, 0.5, 1e-3) - ref); };
  // First order: halving dt halves the error (ratio ~2); second order: ~4.
  const double e1 = err(msd::Integrator::ExplicitEuler, 2e-3), e2 = err(msd::Integrator::ExplicitEuler, 1e-3);
  EXPECT_NEAR(e1 / e2, 2.0, 0.4);
  const double s1 = err(msd::Integrator::SymplecticEuler, 2e-3), s2 = err(msd::Integrator::SymplecticEuler, 1e-3);
  EXPECT_NEAR(s1 / s2, 2.0, 0.4);
  const double v1 = err(msd::Integrator::VelocityVerlet, 2e-3), v2 = err(msd::Integrator::VelocityVerlet, 1e-3);
  EXPECT_NEAR(v1 / v2, 4.0, 0.6);
}

TEST(Step, ExplicitEulerGainsEnergySymplecticDoesNot) {
  const msd::Model m = oscillator(100.0, 6.0);
  // Over many periods explicit Euler's amplitude grows; symplectic Euler's stays.
  const double a_exp = std::abs(run(m, msd::Integrator::ExplicitEuler, 2e-3, 5.0, 1e-3));
  double peak = 0.0;
  msd::State s = msd::rest_state(m);
  s.x(2, 3) = 1.001;
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  for (int i = 0; i < 2500; ++i) {
    msd::step(m, s, c, 2e-3, msd::Integrator::SymplecticEuler, scratch);
    peak = std::max(peak, std::abs(s.x(2, 3) - 1.0));
  }
  EXPECT_LT(peak, 1.1e-3);
  msd::State e = msd::rest_state(m);
  e.x(2, 3) = 1.001;
  double peak_e = 0.0;
  for (int i = 0; i < 2500; ++i) {
    msd::step(m, e, c, 2e-3, msd::Integrator::ExplicitEuler, scratch);
    peak_e = std::max(peak_e, std::abs(e.x(2, 3) - 1.0));
  }
  EXPECT_GT(peak_e, 1.5e-3);
  (void)a_exp;
}

TEST(Step, ConstraintsHoldPrescribedMotion) {
  const msd::Model m = oscillator(100.0, 6.0);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  msd::Controls c{{Vec3(0.1, 0, 0)}, {Vec3(1, 0, 0)}};
  msd::step(m, s, c, 1e-3, msd::Integrator::SymplecticEuler, scratch);
  for (int n : {0, 1, 2}) {
    EXPECT_DOUBLE_EQ(s.x(0, n), m.rest_positions(0, n) + 0.1);
    EXPECT_DOUBLE_EQ(s.v(0, n), 1.0);
  }
  EXPECT_EQ(s.step, 1);
  EXPECT_DOUBLE_EQ(s.t, 1e-3);
}

TEST(Step, GravityAcceleratesFreeNodes) {
  msd::Model m = oscillator(1e-9, 6.0);
  m.terms |= msd::kGravity;
  m.gravity = Vec3(0, 0, -9.81);
  msd::State s = msd::rest_state(m);
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  for (int i = 0; i < 100; ++i) msd::step(m, s, c, 1e-3, msd::Integrator::VelocityVerlet, scratch);
  EXPECT_NEAR(s.v(2, 3), -9.81 * 0.1, 1e-6);
  EXPECT_NEAR(s.x(2, 3) - 1.0, -0.5 * 9.81 * 0.01, 1e-6);
}

TEST(Step, NonFiniteValueStopsWithTimeStepAndElement) {
  const msd::Model m = oscillator(100.0, 6.0);
  msd::State s = msd::rest_state(m);
  s.x.col(3) = s.x.col(0);  // zero-length edge: 0/0 in the spring direction
  msd::Scratch scratch;
  msd::Controls c{{Vec3::Zero()}, {Vec3::Zero()}};
  try {
    msd::step(m, s, c, 1e-3, msd::Integrator::SymplecticEuler, scratch);
    FAIL() << "expected a SimulationFailure";
  } catch (const msd::SimulationFailure& f) {
    EXPECT_EQ(f.element, 0);
    EXPECT_EQ(f.step, 0);
    EXPECT_NE(std::string(f.what()).find("non-finite"), std::string::npos) << f.what();
    EXPECT_NE(std::string(f.what()).find("t = "), std::string::npos) << f.what();
  }
}

TEST(Step, IntegratorNames) {
  for (auto i : {msd::Integrator::ExplicitEuler, msd::Integrator::SymplecticEuler, msd::Integrator::VelocityVerlet,
                 msd::Integrator::BackwardEuler, msd::Integrator::Bdf2})
    EXPECT_EQ(msd::parse_integrator(msd::to_string(i)), i);
  EXPECT_EQ(msd::parse_integrator("bdf2"), msd::Integrator::Bdf2);
  EXPECT_TRUE(msd::is_implicit(msd::Integrator::Bdf2));
  EXPECT_TRUE(msd::is_implicit(msd::Integrator::BackwardEuler));
  EXPECT_FALSE(msd::is_implicit(msd::Integrator::VelocityVerlet));
  EXPECT_EQ(msd::parse_integrator("semi_implicit_euler"), msd::Integrator::SymplecticEuler);
  EXPECT_THROW(msd::parse_integrator("rk4"), msd::Error);
}

// --- Joints: a kinematic group turned by a hinge (msd::Joint) -----------------

namespace {

// The corner tet (1 m edges) with all four nodes on a hinge about the x axis
// through the origin, under gravity: a rigid pendulum.
msd::Model pendulum() {
  msd::TissueMaterial mat;
  mat.density = 6.0;
  mat.k_s = 100.0;
  msd::ModelOptions o;
  o.terms = msd::kSprings | msd::kGravity;
  o.gravity = Vec3(0, 0, -9.81);
  o.region_materials = {mat};
  o.groups = {{"body", {0, 1, 2, 3}, {true, true, true}}};
  msd::Model m = msd::build_model(testing_support::corner_tet_mesh(1.0), o);
  msd::Joint j;
  j.name = "hinge";
  j.group = 0;
  j.hinge.axis = Vec3::UnitX();
  j.hinge.min_angle = -3.0;
  j.hinge.max_angle = 3.0;
  j.hinge.inertia = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Vec3 r = m.rest_positions.col(i);
    j.hinge.inertia += m.mass[i] * (r - r.dot(j.hinge.axis) * j.hinge.axis).squaredNorm();
  }
  m.joints = {j};
  msd::check_model_parts(m);
  return m;
}

msd::Controls still(const msd::Model& m) {
  msd::Controls c;
  c.group_offset.assign(m.groups.size(), Vec3::Zero());
  c.group_velocity.assign(m.groups.size(), Vec3::Zero());
  return c;
}

}  // namespace

TEST(Step, AJointTurnsItsGroupRigidlyUnderTheTorqueOfItsWeight) {
  const msd::Model m = pendulum();
  msd::State s = msd::rest_state(m);
  s.joints[0].angle = 0.3;
  const msd::Controls c = still(m);
  msd::apply_constraints(m, c, s);
  // The torque of the weights about the x axis, by hand: sum m_i (r_i x g) . x.
  double tau = 0.0;
  for (int i = 0; i < 4; ++i) tau += m.mass[i] * Vec3(s.x.col(i)).cross(m.gravity).x();
  const double dt = 1e-3, I = m.joints[0].hinge.inertia;
  msd::Scratch scratch;
  msd::step(m, s, c, dt, msd::Integrator::SymplecticEuler, scratch);
  EXPECT_NEAR(scratch.joints[0].torque, tau, 1e-12 * std::abs(tau));
  EXPECT_NEAR(s.joints[0].velocity, dt * tau / I, 1e-12);
  EXPECT_NEAR(s.joints[0].angle, 0.3 + dt * dt * tau / I, 1e-12);
  // Rigid: every node where R(theta) puts it, edges unchanged, velocity omega x r.
  const Eigen::Matrix3d R = msd::hinge_rotation(m.joints[0].hinge, s.joints[0].angle);
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((Vec3(s.x.col(i)) - R * Vec3(m.rest_positions.col(i))).norm(), 1e-14);
    const Vec3 w = s.joints[0].velocity * Vec3::UnitX();
    EXPECT_LT((Vec3(s.v.col(i)) - w.cross(Vec3(s.x.col(i)))).norm(), 1e-14);
  }
  // The weight turns the body back towards hanging (its centre is on the +y side of the axis).
  EXPECT_LT(tau, 0.0);
}

TEST(Step, AJointTakesAnAddedTorqueItsPassiveDampingAndAScriptedOverride) {
  msd::Model m = pendulum();
  m.terms &= ~static_cast<unsigned>(msd::kGravity);
  m.joints[0].damping = 2.0;
  msd::State s = msd::rest_state(m);
  s.joints[0].velocity = 1.5;
  msd::Controls c = still(m);
  c.joint_torque = {4.0};
  msd::Scratch scratch;
  msd::step(m, s, c, 1e-3, msd::Integrator::SymplecticEuler, scratch);
  EXPECT_DOUBLE_EQ(scratch.joints[0].passive_torque, -2.0 * 1.5);
  EXPECT_NEAR(scratch.joints[0].torque, 4.0 - 3.0, 1e-12);  // no other force: the rest state is force-free
  EXPECT_NEAR(s.joints[0].velocity, 1.5 + 1e-3 * 1.0 / m.joints[0].hinge.inertia, 1e-12);
  c.scripted_joint = {msd::HingeState{0.7, -0.25}};
  msd::step(m, s, c, 1e-3, msd::Integrator::BackwardEuler, scratch);
  EXPECT_EQ(s.joints[0].angle, 0.7);
  EXPECT_EQ(s.joints[0].velocity, -0.25);
  const Eigen::Matrix3d R = msd::hinge_rotation(m.joints[0].hinge, 0.7);
  EXPECT_LT((Vec3(s.x.col(3)) - R * Vec3(m.rest_positions.col(3))).norm(), 1e-14);
}

TEST(Step, BadPartsAreRefusedByName) {
  msd::Model m = pendulum();
  m.groups[0].axes[2] = false;
  try {
    msd::check_model_parts(m);
    FAIL() << "a joint on a group that frees an axis was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("joint 'hinge'"), std::string::npos) << e.what();
  }
  msd::Model m2 = pendulum();
  m2.strands = {msd::Strand{{0, 7}, 1.0, 10.0, -1, Vec3::Zero()}};
  EXPECT_THROW(msd::check_model_parts(m2), msd::Error);
  msd::Model m3 = pendulum();
  m3.muscles = {msd::Muscle{"biceps", {{0, 1, 1.0}}, -1.0, {}, {}}};
  try {
    msd::check_model_parts(m3);
    FAIL() << "a negative unit force was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("muscle 'biceps'"), std::string::npos) << e.what();
  }
  // A state without the model's joints is refused by step.
  const msd::Model ok = pendulum();
  msd::State s = msd::rest_state(ok);
  s.joints.clear();
  msd::Scratch scratch;
  EXPECT_THROW(msd::step(ok, s, still(ok), 1e-3, msd::Integrator::SymplecticEuler, scratch), msd::Error);
}

// --- A hinge on a moving parent (Joint::parent, Controls::group_motion) -------

namespace {

// A 1 mm tet hanging 1 m below a hinge about x through the origin - a point
// mass on a massless rod, to O(1e-6) - whose frame is group 0 (no nodes of its
// own: it only carries the hinge). Joint damping b lets it settle.
msd::Model hanging_bob(double damping) {
  msd::TetMesh mesh = testing_support::corner_tet_mesh(1e-3);
  mesh.nodes.row(2).array() -= 1.0;
  msd::TissueMaterial mat;
  mat.density = 1000.0;
  mat.k_s = 100.0;
  msd::ModelOptions o;
  o.terms = msd::kSprings | msd::kGravity;
  o.gravity = Vec3(0, 0, -9.81);
  o.region_materials = {mat};
  o.groups = {{"thigh", {}, {true, true, true}}, {"bob", {0, 1, 2, 3}, {true, true, true}}};
  msd::Model m = msd::build_model(mesh, o);
  msd::Joint j;
  j.name = "knee";
  j.group = 1;
  j.parent = 0;
  j.hinge.axis = Vec3::UnitX();
  j.hinge.min_angle = -3.0;
  j.hinge.max_angle = 3.0;
  for (int i = 0; i < 4; ++i) {
    const Vec3 r = m.rest_positions.col(i);
    j.hinge.inertia += m.mass[i] * (r - r.dot(j.hinge.axis) * j.hinge.axis).squaredNorm();
  }
  j.damping = damping * j.hinge.inertia;
  m.joints = {j};
  msd::check_model_parts(m);
  return m;
}

// Runs the bob for `duration` with the parent's motion `motion(t)` at each
// step's end; returns the settled angle.
template <class Motion>
double settle(const msd::Model& m, msd::Integrator integ, double duration, Motion motion, msd::Scratch& scratch,
              msd::State& s) {
  s = msd::rest_state(m);
  s.joints[0].angle = 0.1;
  msd::Controls c = still(m);
  c.group_motion.assign(2, std::nullopt);
  const double dt = 1e-3;
  c.group_motion[0] = motion(0.0);
  msd::apply_constraints(m, c, s);
  for (long k = 0; k < std::lround(duration / dt); ++k) {
    c.group_motion[0] = motion((k + 1) * dt);
    msd::step(m, s, c, dt, integ, scratch);
  }
  return s.joints[0].angle;
}

}  // namespace

TEST(Step, AHingeOnASpinningParentSettlesWhereTheCentrifugalTorqueBalancesTheWeight) {
  // The parent spins about the vertical at omega = 2 sqrt(g/L): the hanging
  // bob (a conical pendulum, the flyball governor) settles at
  // cos theta = g / (omega^2 L) = 1/4, theta = 75.5 deg (closed form).
  const msd::Model m = hanging_bob(3.0);
  const double L = 1.0 - 0.25e-3;  // the tet's centre below the axis
  const double omega = 2.0 * std::sqrt(9.81 / L);
  auto spin = [&](double t) {
    msd::RigidMotion p;
    p.rotation = Eigen::AngleAxisd(omega * t, Vec3::UnitZ()).toRotationMatrix();
    p.angular_velocity = Vec3(0, 0, omega);
    return p;
  };
  for (msd::Integrator integ : {msd::Integrator::SymplecticEuler, msd::Integrator::Bdf2}) {
    msd::Scratch scratch;
    msd::State s;
    const double theta = settle(m, integ, 8.0, spin, scratch, s);
    EXPECT_NEAR(std::abs(theta), std::acos(0.25), 2e-3) << msd::to_string(integ);
    // The nodes ride with the parent: each where R_p R(theta) X puts it, moving with Omega x x.
    const msd::RigidMotion p = spin(s.t);
    const Eigen::Matrix3d R = p.rotation * msd::hinge_rotation(m.joints[0].hinge, theta);
    const Vec3 big_w = p.angular_velocity + s.joints[0].velocity * (p.rotation * Vec3::UnitX());
    for (int i = 0; i < 4; ++i) {
      EXPECT_LT((Vec3(s.x.col(i)) - R * Vec3(m.rest_positions.col(i))).norm(), 1e-10);  // (8 s of round-off)
      EXPECT_LT((Vec3(s.v.col(i)) - big_w.cross(Vec3(s.x.col(i)))).norm(), 1e-9);
    }
    // The bob flies out sideways: 1 m * sin(75.5 deg) from the spin axis.
    EXPECT_NEAR(Vec3(s.x.col(0)).head<2>().norm(), std::sin(std::acos(0.25)), 3e-3);
  }
  // A parent at rest changes nothing: the bob hangs.
  msd::Scratch scratch;
  msd::State s;
  EXPECT_NEAR(settle(m, msd::Integrator::SymplecticEuler, 8.0, [](double) { return msd::RigidMotion{}; }, scratch, s),
              0.0, 1e-3);
}

TEST(Step, AHingeOnAnAcceleratingParentTrailsAtTheAngleOfTheApparentGravity) {
  // The parent accelerates at a = g/2 along +y: the bob trails at
  // tan theta = a / g (26.6 deg), behind (y < 0 of the hinge), and the hinge
  // pulls it with M (a - g) (closed form).
  const msd::Model m = hanging_bob(3.0);
  const double a = 0.5 * 9.81;
  auto push = [&](double t) {
    msd::RigidMotion p;
    p.offset = Vec3(0, 0.5 * a * t * t, 0);
    p.velocity = Vec3(0, a * t, 0);
    p.acceleration = Vec3(0, a, 0);
    return p;
  };
  for (msd::Integrator integ : {msd::Integrator::SymplecticEuler, msd::Integrator::Bdf2}) {
    msd::Scratch scratch;
    msd::State s;
    const double theta = settle(m, integ, 8.0, push, scratch, s);
    EXPECT_NEAR(std::abs(theta), std::atan(0.5), 2e-3) << msd::to_string(integ);
    const Vec3 hinge = push(s.t).offset;
    EXPECT_LT(s.x(1, 0) - hinge.y(), -0.4) << msd::to_string(integ);
    double mass = 0.0;
    for (int i = 0; i < 4; ++i) mass += m.mass[i];
    const Vec3 expected = mass * (Vec3(0, a, 0) - m.gravity);
    EXPECT_LT((scratch.joints[0].reaction - expected).norm(), 2e-3 * expected.norm()) << msd::to_string(integ);
  }
}

TEST(Step, ARigidMotionPlacesItsGroupAndCarriesTheAnchorsOnIt) {
  msd::Model m = hanging_bob(0.0);
  msd::State s = msd::rest_state(m);
  s.joints[0].angle = 0.4;
  msd::Controls c = still(m);
  msd::RigidMotion p;
  p.rotation = Eigen::AngleAxisd(0.3, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  p.offset = Vec3(0.1, 0.2, 0.3);
  p.velocity = Vec3(1, 0, 0);
  p.angular_velocity = Vec3(0, 2, 0);
  c.group_motion = {p, std::nullopt};
  msd::apply_constraints(m, c, s);
  const Eigen::Matrix3d R = p.rotation * msd::hinge_rotation(m.joints[0].hinge, 0.4);
  const Vec3 X(0.0, 0.0, -0.5);  // a point on the bob's rod
  EXPECT_LT((msd::group_point(m, 1, X, s.x, s.joints, c) - (R * X + p.offset)).norm(), 1e-14);
  EXPECT_LT((Vec3(s.x.col(3)) - (R * Vec3(m.rest_positions.col(3)) + p.offset)).norm(), 1e-14);
  // The bob's group with a motion of its own and no joint: placed by it.
  m.joints.clear();
  m.groups[1].joint = -1;
  c.group_motion = {std::nullopt, p};
  msd::apply_constraints(m, c, s);
  for (int i = 0; i < 4; ++i) {
    const Vec3 x = p.place(m.rest_positions.col(i));
    EXPECT_LT((Vec3(s.x.col(i)) - x).norm(), 1e-14);
    EXPECT_LT((Vec3(s.v.col(i)) - p.velocity_at(x)).norm(), 1e-14);
  }
  EXPECT_LT((msd::group_point(m, 1, X, s.x, s.joints, c) - p.place(X)).norm(), 1e-14);
}

TEST(Step, AHingeTurnedAboutItsOwnAxisByItsParentKeepsItsBodyStillInSpace) {
  // No gravity, no joint damping: the parent turns about the hinge's own axis
  // (x, through the centre) with constant angular acceleration alpha. Nothing
  // exerts a torque on the body about that axis, so it does not turn in space:
  // relative to the parent theta' = -alpha t (the n . (I_c alpha) term; exact
  // for semi-implicit Euler's velocity).
  msd::Model m = hanging_bob(0.0);
  m.terms &= ~static_cast<unsigned>(msd::kGravity);
  const double alpha = 3.0;
  auto turn = [&](double t) {
    msd::RigidMotion p;
    p.rotation = Eigen::AngleAxisd(0.5 * alpha * t * t, Vec3::UnitX()).toRotationMatrix();
    p.angular_velocity = Vec3(alpha * t, 0, 0);
    p.angular_acceleration = Vec3(alpha, 0, 0);
    return p;
  };
  msd::Scratch scratch;
  msd::State s;
  const double theta = settle(m, msd::Integrator::SymplecticEuler, 0.5, turn, scratch, s);
  EXPECT_NEAR(s.joints[0].velocity, -alpha * s.t, 1e-9 * alpha * s.t);
  // The body's absolute angle, parent's plus relative, stays at its start (0.1
  // rad) to the first-order error of the steps in theta.
  EXPECT_NEAR(0.5 * alpha * s.t * s.t + theta, 0.1, alpha * s.t * 1e-3);
}

TEST(Step, ARigidMotionOnAJointsGroupOrOnAGroupWithAFreeAxisIsRefused) {
  msd::Model m = hanging_bob(0.0);
  msd::State s = msd::rest_state(m);
  msd::Controls c = still(m);
  c.group_motion = {std::nullopt, msd::RigidMotion{}};  // the bob's group: its joint turns it
  EXPECT_THROW(msd::apply_constraints(m, c, s), msd::Error);
  m.joints.clear();
  m.groups[1].joint = -1;
  m.groups[1].axes[2] = false;
  EXPECT_THROW(msd::apply_constraints(m, c, s), msd::Error);
  m.groups[1].axes[2] = true;
  EXPECT_NO_THROW(msd::apply_constraints(m, c, s));
}

TEST(Step, AHingesParentMustBeAnotherUnjointedGroupPrescribingAllAxes) {
  for (int bad = 0; bad < 3; ++bad) {
    msd::Model m = hanging_bob(0.0);
    m.groups[1].joint = -1;
    if (bad == 0) m.joints[0].parent = 1;                     // itself
    if (bad == 1) m.joints[0].parent = 5;                     // out of range
    if (bad == 2) m.groups[0].axes[1] = false;                // frees an axis
    try {
      msd::check_model_parts(m);
      FAIL() << "case " << bad << " was accepted";
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find("joint 'knee': its parent"), std::string::npos) << e.what();
    }
  }
}
