// The shipped leg's moving parts: the femur holds, the lower leg turns rigidly
// about the knee (scripted), a released lower leg starts to fall at its
// gravity torque over its inertia, shortened tendons pull with their strands'
// stiffness, and a muscle's units add no net force.
#include "msd/scene/leg_model.hpp"

#include "msd/geometry/leg_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct ShippedLeg {
  msd::LimbMesh mesh;
  std::vector<msd::TendonStrands> tendons;
};

// The shipped leg meshed at the thesis' resolution with its four tendons (the
// generator's paths: the shipped files are its output, LegGenerator tests).
const ShippedLeg& shipped() {
  static const ShippedLeg leg = [] {
    msd::LimbMeshOptions o;
    o.spacing = 0.0245;
    ShippedLeg l{msd::mesh_limb(msd::read_leg_surfaces(std::string(TISSUEBENCH_DATA_DIR) + "/leg"), o), {}};
    for (const msd::TendonPathSpec& t : msd::make_leg(msd::LegParameters{}).tendons)
      l.tendons.push_back(msd::route_tendon(l.mesh, t));
    return l;
  }();
  return leg;
}

msd::LegModelOptions options() {
  msd::LegModelOptions o;
  o.passive.density = 920;
  o.passive.mode = msd::ConstantsMode::Physical;
  o.passive.youngs_modulus = 2990;
  o.passive.damping_time = 4.2e-3;
  o.passive.repulsion_factor = 0.5;
  o.passive.volume_factor = 1.6;
  o.muscle = o.passive;
  o.muscle.density = 1040;
  o.muscle.youngs_modulus = 14950;
  o.knee_centre = msd::Vec3(0, 0, 0.50046);
  return o;
}

}  // namespace

TEST(LegModel, BonesOwnTheirNodesAndTheKneeCarriesTheLowerLegsInertia) {
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, options());
  EXPECT_GT(leg.femur_nodes.size(), 20u);
  EXPECT_GT(leg.lower_nodes.size(), 50u);
  for (int i : leg.femur_nodes) EXPECT_EQ(leg.attached[static_cast<size_t>(i)], 1);
  // The lower leg (bone + attached tissue nodes) about the knee: a few kg at
  // a few tens of cm, so 0.05-1 kg m^2 (a real shank and foot: about 0.3).
  EXPECT_GT(leg.knee.inertia, msd::moment_about_axis(leg.lower_bone, leg.knee.centre, leg.knee.axis));
  EXPECT_GT(leg.knee.inertia, 0.05);
  EXPECT_LT(leg.knee.inertia, 1.0);
  EXPECT_EQ(leg.strands.size(), 26u);
  // The joint space: the tets with nodes on both bones are left out (45 on
  // the shipped leg), and no remaining tet joins the two bones.
  EXPECT_EQ(leg.joint_space_tets, 45);
  EXPECT_EQ(static_cast<long>(leg.tets.size()) + leg.joint_space_tets, shipped().mesh.mesh.num_tets());
  for (const msd::Tet& t : leg.tets) {
    unsigned bones = 0;
    for (int v : t) bones |= leg.attached[static_cast<size_t>(v)];
    EXPECT_NE(bones, 3u);
  }
  EXPECT_FALSE(leg.front_units.empty());
  EXPECT_FALSE(leg.back_units.empty());
  // At rest nothing moves: the lower leg placed at 0 is its rest geometry.
  const msd::LegState s = msd::leg_rest_state(leg, 0.0);
  EXPECT_LT((s.tissue.x - leg.tissue.rest_positions).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(LegModel, ScriptedKneeMovesTheLowerLegRigidlyAndTheFemurHolds) {
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, options());
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  // Kinematic override (thesis 3.7.2): a slow ramp to 20 degrees over 0.2 s.
  const double dt = 1e-4, rate = 100.0 * kDeg;
  msd::LegControls c;
  for (int k = 1; k <= 2000; ++k) {
    c.scripted_knee = msd::HingeState{rate * k * dt, rate};
    msd::step_leg(leg, s, c, dt, scratch);
  }
  EXPECT_NEAR(s.knee.angle, 20.0 * kDeg, 1e-12);
  const msd::Mat3 r = msd::hinge_rotation(leg.knee, 20.0 * kDeg);
  const msd::Vec3 w = rate * leg.knee.axis;
  for (int i : leg.lower_nodes) {
    const msd::Vec3 expected = leg.knee.centre + r * (leg.tissue.rest_positions.col(i) - leg.knee.centre);
    EXPECT_LT((s.tissue.x.col(i) - expected).norm(), 1e-12);
    EXPECT_LT((s.tissue.v.col(i) - w.cross(expected - leg.knee.centre)).norm(), 1e-12);
  }
  for (int i : leg.femur_nodes) EXPECT_EQ(s.tissue.x.col(i), leg.tissue.rest_positions.col(i));
  // Flexion carries the foot backwards (-x) and up.
  const int toe = leg.lower_nodes.front();
  EXPECT_LT(s.tissue.x(0, toe), leg.tissue.rest_positions(0, toe));
}

TEST(LegModel, KneeBentToNinetyDegreesCreasesTheSkinBehindIt) {
  // Thesis 6.3: bending the knee brings the skin above and below the back of
  // the knee into contact. A scripted flexion at 50 degrees/s to 90 degrees,
  // with the collision region behind the knee.
  msd::LegModelOptions o = options();
  o.knee_contact_box = std::make_pair(msd::Vec3(-0.15, -0.12, 0.38), msd::Vec3(0.0, 0.12, 0.62));
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  ASSERT_TRUE(leg.knee_contact.has_value());
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  const double dt = 2e-4, rate = 50.0 * kDeg;
  msd::LegControls c;
  int contacts_below_60 = 0, contacts_at_90 = 0;
  double area_at_90 = 0.0;
  for (int k = 1; k <= 9500; ++k) {
    const double angle = std::min(rate * k * dt, 90.0 * kDeg);
    c.scripted_knee = msd::HingeState{angle, angle < 90.0 * kDeg ? rate : 0.0};
    msd::step_leg(leg, s, c, dt, scratch);  // throws on a blow-up
    if (angle < 60.0 * kDeg) contacts_below_60 += scratch.knee_contact.contacts;
    if (angle >= 90.0 * kDeg) {
      contacts_at_90 = std::max(contacts_at_90, scratch.knee_contact.contacts);
      area_at_90 = std::max(area_at_90, scratch.knee_contact.area);
    }
  }
  EXPECT_NEAR(s.knee.angle, 90.0 * kDeg, 1e-12);
  EXPECT_EQ(contacts_below_60, 0);  // a straight-ish knee has no crease
  EXPECT_GT(contacts_at_90, 0);     // a bent one has
  EXPECT_GT(area_at_90, 1e-4);      // at least a square centimetre
}

TEST(LegModel, ReleasedLowerLegStartsToFallAtTheGravityTorqueOverItsInertia) {
  // Lying on the back with the knee at a table's edge (drop.yaml's set-up): the
  // leg's front faces up, gravity along -x; the straight lower leg is released.
  msd::LegModelOptions o = options();
  o.gravity = msd::Vec3(-9.81, 0, 0);
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  // At rest the tissue pulls nothing: the torque is the lower leg's weight, the
  // attached nodes' and the bone's, about the knee.
  msd::Vec3 torque = msd::Vec3::Zero();
  for (int i : leg.lower_nodes)
    torque += (leg.tissue.rest_positions.col(i) - leg.knee.centre).cross(leg.tissue.mass[i] * o.gravity);
  torque += (leg.lower_bone.centre - leg.knee.centre).cross(leg.lower_bone.mass * o.gravity);
  const double alpha = leg.knee.axis.dot(torque) / leg.knee.inertia;
  EXPECT_GT(alpha, 0.0);  // towards flexion
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  const double dt = 1e-4;
  for (int k = 0; k < 20; ++k) msd::step_leg(leg, s, {}, dt, scratch);
  // theta = alpha t^2 / 2 for the first 2 ms (semi-implicit Euler: t^2 (1 + 1/n) / 2).
  const double t = 20 * dt;
  EXPECT_NEAR(s.knee.angle, 0.5 * alpha * t * t * (1.0 + 1.0 / 20), 0.05 * 0.5 * alpha * t * t);
  // And it keeps falling.
  for (int k = 0; k < 1500; ++k) msd::step_leg(leg, s, {}, dt, scratch);
  EXPECT_GT(s.knee.angle, 5.0 * kDeg);
  EXPECT_GT(s.knee.velocity, 0.0);
}

TEST(LegModel, ShortenedTendonsPullWithTheirStrandsStiffnessAndMusclesAddNoNetForce) {
  msd::LegModelOptions o = options();
  o.terms &= ~static_cast<unsigned>(msd::kGravity);
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  // Natural lengths 10 % short (pre-tension, thesis 5.3): at rest each strand
  // pulls k_t (L0 - 0.9 L0) = E A 0.1.
  msd::LegControls c;
  c.tendon_length_scale = {0.9, 0.9, 1.0, 1.0};
  c.back_activation = 1.0;
  msd::step_leg(leg, s, c, 1e-4, scratch);
  const double per_strand = o.tendon_modulus * o.strand_area * 0.1;
  EXPECT_NEAR(scratch.tendon_tension[0], 8 * per_strand, 1e-9);  // back_upper, 8 strands
  EXPECT_NEAR(scratch.tendon_tension[1], 6 * per_strand, 1e-9);  // back_lower
  EXPECT_EQ(scratch.tendon_tension[2], 0.0);                     // at their natural length: slack
  EXPECT_EQ(scratch.tendon_tension[3], 0.0);
  // The muscle's units pull in pairs: the active back muscle adds no net force
  // to the tissue (the tendons' pulls are what it passes on to the bones).
  msd::Scratch rest;
  msd::evaluate_forces(leg.tissue, msd::leg_rest_state(leg, 0.0).tissue, rest);
  msd::Points f = rest.f;
  msd::add_muscle_forces(leg.tissue.rest_positions, leg.back_units, leg.back_unit_force, f);
  EXPECT_LT((f - rest.f).rowwise().sum().norm(), 1e-9 * leg.back_unit_force);
  EXPECT_GT((f - rest.f).cwiseAbs().maxCoeff(), 0.1 * leg.back_unit_force);
}
