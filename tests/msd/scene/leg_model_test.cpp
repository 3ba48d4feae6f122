// The shipped leg's moving parts: the femur holds, the lower leg turns rigidly
// about the knee (scripted), a released lower leg starts to fall at its
// gravity torque over its inertia, shortened tendons pull with their strands'
// stiffness, and a muscle's units add no net force.
#include "msd/scene/leg_model.hpp"

#include "msd/control/pose_keyframes.hpp"
#include "msd/geometry/leg_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The shipped leg meshed at the thesis' resolution with its four tendons (the
// generator's paths: the shipped files are its output, LegGenerator tests).
const msd::MeshedLeg& shipped() {
  static const msd::MeshedLeg leg = [] {
    msd::LimbMeshOptions o;
    o.spacing = 0.0245;
    return msd::mesh_leg(std::string(TISSUEBENCH_DATA_DIR) + "/leg", o);
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

// The knee cap's tendon's insertion on the lower bone (tendon 3, front_lower).
const msd::Vec3 kKneeCapInsertion(0.0412, 0.0, 0.53046);

// options() without gravity, the knee cap's tendon inserted at kKneeCapInsertion.
msd::LegModelOptions knee_cap_inserted() {
  msd::LegModelOptions o = options();
  o.terms &= ~static_cast<unsigned>(msd::kGravity);
  o.tendon_insertions = {std::nullopt, std::nullopt, std::nullopt, kKneeCapInsertion};
  return o;
}

// One step of `leg` from rest, the knee held straight and the knee cap's
// tendon shortened by 10 %; its tension and the knee's torque in `scratch`.
void step_with_the_knee_cap_tendon_shortened(const msd::LegModel& leg, msd::LegScratch& scratch) {
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegControls c;
  c.tendon_length_scale = {1.0, 1.0, 1.0, 0.9};
  c.scripted_knee = msd::HingeState{0.0, 0.0};
  msd::step_leg(leg, s, c, 1e-4, scratch);
}

// What build_leg_model says when it refuses `o` on `mesh` (empty if it builds).
std::string refusal_of(const msd::LimbMesh& mesh, const msd::LegModelOptions& o) {
  try {
    msd::build_leg_model(mesh, shipped().tendons, o);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
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

TEST(LegModel, APublishedCrossSectionSetsTheMusclesForceInPlaceOfTheMeshs) {
  // The hamstrings' PCSA (88 cm^2) on the back muscle: each unit's force is
  // max_stress x PCSA x L / Lambda (unit_force_for_area); the front muscle
  // keeps the mesh's section. Twice the section, twice the force.
  msd::LegModelOptions o = options();
  o.back_pcsa = 0.0088;
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  const msd::LegModel plain = msd::build_leg_model(shipped().mesh, shipped().tendons, options());
  EXPECT_DOUBLE_EQ(leg.back_unit_force, msd::unit_force_for_area(shipped().mesh.mesh, msd::kBackMuscle, leg.back_units,
                                                                 o.back_line, 1.0, o.max_muscle_stress, 0.0088));
  EXPECT_DOUBLE_EQ(leg.front_unit_force, plain.front_unit_force);
  o.back_pcsa = 0.0176;
  EXPECT_NEAR(msd::build_leg_model(shipped().mesh, shipped().tendons, o).back_unit_force, 2.0 * leg.back_unit_force,
              1e-12 * leg.back_unit_force);
  // The thesis leg's back muscle has about 17 cm^2 of meshed section (docs/leg-geometry.md), so 88 cm^2 pulls
  // more than three times as hard.
  EXPECT_GT(leg.back_unit_force, 3.0 * plain.back_unit_force);
}

TEST(LegModel, PassiveJointTorqueDampsAndStiffensOnlyBeyondItsRange) {
  msd::LegModelOptions o = options();
  o.joint_damping = 0.25;
  o.limit_stiffness = 100.0;
  o.passive_lo = 0.0;
  o.passive_hi = 130.0 * kDeg;
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  EXPECT_DOUBLE_EQ(msd::passive_joint_torque(leg, {60.0 * kDeg, 2.0}), -0.5);          // -b omega
  EXPECT_NEAR(msd::passive_joint_torque(leg, {140.0 * kDeg, 0.0}), -100.0 * 10.0 * kDeg, 1e-12);  // past 130
  EXPECT_NEAR(msd::passive_joint_torque(leg, {-5.0 * kDeg, 0.0}), 100.0 * 5.0 * kDeg, 1e-12);  // hyperextended
  o.passive_lo = 1.0;
  o.passive_hi = 0.5;
  EXPECT_THROW(msd::build_leg_model(shipped().mesh, shipped().tendons, o), msd::Error);
}

TEST(LegModel, AtRestTheFemurCarriesTheLowerLegsWeight) {
  // The knee held straight and still; no tissue force at rest: the joint
  // reaction is minus the lower leg's weight (bone + the nodes on it).
  msd::LegModelOptions o = options();
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  msd::LegControls c;
  c.scripted_knee = msd::HingeState{0.0, 0.0};
  msd::step_leg(leg, s, c, 1e-4, scratch);
  double mass = leg.lower_bone.mass;
  for (int i : leg.lower_nodes) mass += leg.tissue.mass[i];
  EXPECT_LT((scratch.joint_reaction + mass * o.gravity).norm(), 1e-9 * mass * 9.81);
}

TEST(LegModel, AnchoredTendonsEndAtTheirInsertionAndTurnTheKneeThroughIt) {
  // The knee cap's tendon (front_lower) inserted at a point on the lower bone
  // instead of its last node: the strand runs to the point, its natural length
  // includes it, and a shortened strand pulls the point - a torque about the knee.
  msd::LegModelOptions o = knee_cap_inserted();
  const msd::Vec3& insertion = kKneeCapInsertion;
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  int anchored = 0;
  for (const msd::LegStrand& s : leg.strands) {
    if (s.tendon != 3) {
      EXPECT_FALSE(s.anchored);
      continue;
    }
    ++anchored;
    EXPECT_TRUE(s.anchored);
    EXPECT_EQ(s.anchor_bone, 2);
    const msd::Points p = msd::leg_strand_points(leg, s, leg.tissue.rest_positions, 0.0);
    EXPECT_EQ(p.col(p.cols() - 1), insertion);
    double length = 0.0;
    for (Eigen::Index k = 1; k < p.cols(); ++k) length += (p.col(k) - p.col(k - 1)).norm();
    EXPECT_NEAR(s.natural_length, length, 1e-15);
    // With the knee at 90 degrees the point has turned with the bone.
    const msd::Points q = msd::leg_strand_points(leg, s, leg.tissue.rest_positions, 90.0 * kDeg);
    const msd::Vec3 expected =
        leg.knee.centre + msd::hinge_rotation(leg.knee, 90.0 * kDeg) * (insertion - leg.knee.centre);
    EXPECT_LT((q.col(q.cols() - 1) - expected).norm(), 1e-15);
    // The length and energy helpers are the polyline's; the in-place form fills a reused buffer.
    double bent = 0.0;
    for (Eigen::Index k = 1; k < q.cols(); ++k) bent += (q.col(k) - q.col(k - 1)).norm();
    EXPECT_NEAR(msd::leg_strand_length(leg, s, leg.tissue.rest_positions, 90.0 * kDeg), bent, 1e-15);
    EXPECT_GT(std::abs(bent - length), 1e-4);  // the anchor moved: the length sees it
    EXPECT_NEAR(msd::leg_strand_energy(leg, s, leg.tissue.rest_positions, 90.0 * kDeg, 0.9 * bent),
                0.5 * s.k_t * (0.1 * bent) * (0.1 * bent), 1e-12 * s.k_t * bent * bent);
    EXPECT_EQ(msd::leg_strand_energy(leg, s, leg.tissue.rest_positions, 90.0 * kDeg, 1.1 * bent), 0.0);
    msd::Points buffer(3, 1);
    msd::leg_strand_points(leg, s, leg.tissue.rest_positions, 90.0 * kDeg, buffer);
    EXPECT_EQ(buffer, q);
  }
  EXPECT_EQ(anchored, 6);
  // Shortened by 10 %: 6 strands pull E A 0.1 each; the point lies in front
  // of the knee's centre and the pull runs up the thigh, so it extends the knee.
  msd::LegScratch scratch;
  step_with_the_knee_cap_tendon_shortened(leg, scratch);
  EXPECT_NEAR(scratch.tendon_tension[3], 6 * o.tendon_modulus * o.strand_area * 0.1, 1e-9);
  EXPECT_LT(scratch.knee_torque, 0.0);
  // An insertion list of the wrong length is refused.
  o.tendon_insertions = {insertion};
  EXPECT_THROW(msd::build_leg_model(shipped().mesh, shipped().tendons, o), msd::Error);
}

TEST(LegModel, ObstaclesTestOnlyTheFreeSkinNodesInTheirBox) {
  msd::LegModelOptions o = options();
  msd::LegModelOptions::Obstacle rod;
  rod.object.name = "rod";
  rod.object.cylinder.point = msd::Vec3(0.12, 0, 0.17);
  rod.object.cylinder.axis = msd::Vec3::UnitY();
  rod.object.cylinder.radius = 0.04;
  rod.box = std::make_pair(msd::Vec3(0.0, -0.08, 0.08), msd::Vec3(0.12, 0.08, 0.3));
  o.obstacles = {rod};
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  ASSERT_EQ(leg.obstacles.size(), 1u);
  ASSERT_FALSE(leg.obstacles[0].nodes.empty());
  for (int i : leg.obstacles[0].nodes) {
    EXPECT_EQ(leg.attached[static_cast<size_t>(i)], 0);
    const msd::Vec3 x = leg.tissue.rest_positions.col(i);
    EXPECT_TRUE((x.array() >= rod.box->first.array()).all() && (x.array() <= rod.box->second.array()).all());
  }
  // Moved 5 cm back into the shin, the rod pushes the skin it meets out of
  // itself and reports the contacts and a force on the leg.
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  msd::LegControls c;
  c.scripted_knee = msd::HingeState{0.0, 0.0};
  c.obstacle_offset = {msd::Vec3(-0.05, 0, 0)};
  c.obstacle_velocity = {msd::Vec3::Zero()};
  msd::step_leg(leg, s, c, 1e-4, scratch);
  ASSERT_EQ(scratch.obstacles.size(), 1u);
  EXPECT_GT(scratch.obstacles[0].contacts, 0);
  for (int i : leg.obstacles[0].nodes)
    EXPECT_LE(msd::obstacle_gap(leg.obstacles[0], c.obstacle_offset[0], s.tissue.x.col(i)).depth, 1e-12);
  // A box holding no skin is refused by name.
  o.obstacles[0].box = std::make_pair(msd::Vec3(5, 5, 5), msd::Vec3(6, 6, 6));
  const std::string no_skin = refusal_of(shipped().mesh, o);
  EXPECT_NE(no_skin.find("obstacle 'rod'"), std::string::npos) << no_skin;
}

TEST(LegModel, ARestStateAtAnAngleTurnsTheLowerLegsFleshWithItsBone) {
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, options());
  const double angle = 30.0 * kDeg, h = 0.0245;
  const msd::LegState s = msd::leg_rest_state(leg, angle, h);
  const msd::Mat3 r = msd::hinge_rotation(leg.knee, angle);
  for (int i = 0; i < leg.tissue.num_nodes(); ++i) {
    const msd::Vec3 X = leg.tissue.rest_positions.col(i);
    const double height = (X - leg.knee.centre).dot(leg.leg_axis);
    if (leg.attached[static_cast<size_t>(i)] == 1 || (height > h && !leg.attached[static_cast<size_t>(i)])) {
      EXPECT_EQ(s.tissue.x.col(i), X);  // the thigh stays
    }
    if (leg.attached[static_cast<size_t>(i)] == 2 || (height < -h && !leg.attached[static_cast<size_t>(i)])) {
      EXPECT_LT((s.tissue.x.col(i) - (leg.knee.centre + r * (X - leg.knee.centre))).norm(), 1e-12);
    }
  }
}

TEST(LegModel, AWiderJointSpaceLeavesOutTheTissueBetweenTheBonesButNoNode) {
  msd::LegModelOptions o = options();
  o.joint_space_radius = 0.09;
  const msd::LegModel wide = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  EXPECT_GT(wide.joint_space_tets, 45);
  EXPECT_EQ(static_cast<long>(wide.tets.size()) + wide.joint_space_tets, shipped().mesh.mesh.num_tets());
  std::vector<int> uses(static_cast<size_t>(wide.tissue.num_nodes()), 0);
  for (const msd::Tet& t : wide.tets)
    for (int v : t) ++uses[static_cast<size_t>(v)];
  EXPECT_EQ(std::count(uses.begin(), uses.end(), 0), 0);  // every node keeps a tet (and its mass)
  for (size_t e = 0; e < wide.tets.size(); ++e) {
    unsigned bones = 0;
    for (int v : wide.tets[e]) bones |= wide.attached[static_cast<size_t>(v)];
    EXPECT_NE(bones, 3u);
  }
}

TEST(LegModel, AnAddedJointTorqueTurnsTheKneeAtTorqueOverInertia) {
  // Third control mode (thesis 3.7.2): no gravity, the leg at rest (no tissue
  // force), 2 N m added about the axis: after n steps of dt the angle is
  // alpha t^2 (1 + 1/n) / 2 with alpha = tau / I (semi-implicit Euler), before
  // the flesh has moved enough to push back.
  msd::LegModelOptions o = options();
  o.terms &= ~static_cast<unsigned>(msd::kGravity);
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  msd::LegControls c;
  c.joint_torque = 2.0;
  const int n = 10;
  const double dt = 1e-4, alpha = 2.0 / leg.knee.inertia, t = n * dt;
  for (int k = 0; k < n; ++k) msd::step_leg(leg, s, c, dt, scratch);
  EXPECT_NEAR(s.knee.angle, 0.5 * alpha * t * t * (1.0 + 1.0 / n), 0.02 * 0.5 * alpha * t * t);
  // The opposite torque pushes a straight knee into its stop at 0: it holds.
  msd::LegState back = msd::leg_rest_state(leg, 0.0);
  c.joint_torque = -2.0;
  for (int k = 0; k < n; ++k) msd::step_leg(leg, back, c, dt, scratch);
  EXPECT_EQ(back.knee.angle, 0.0);
  EXPECT_EQ(back.knee.velocity, 0.0);
}

TEST(LegModel, RealTendonStiffnessRunsWithBackwardEulerAtAStepWhereSymplecticEulerBlowsUp) {
  // Tendons at the linear modulus of real tendon, about 1.2 GPa (issue 18;
  // Maganaris & Paul 1999, human tendon in vivo): k_t = E A / L0 is
  // about 2.4e5 N/m on a strand of 10 cm, so on a node of about 15 g
  // symplectic Euler is stable only below dt = 2 sqrt(m / k), about 0.5 ms.
  // The thesis' switch of the non-linear terms (threshold 0.7) makes the forces
  // jump, which Newton's method cannot follow: the terms act everywhere here.
  msd::LegModelOptions o = options();
  o.tendon_modulus = 1.2e9;
  o.nonlinear_threshold = 0.0;
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  msd::LegControls c;
  c.tendon_length_scale = {0.99, 0.99, 1.0, 1.0};  // the back tendons pre-tensioned by 1 %
  c.back_activation = 0.5;
  const double dt = 1e-3;
  msd::LegState be = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch s1;
  for (int k = 0; k < 20; ++k) msd::step_leg(leg, be, c, dt, s1, msd::Integrator::BackwardEuler);
  EXPECT_TRUE(be.tissue.x.allFinite());
  EXPECT_GT(s1.tendon_tension[0], 0.0);
  // Every strand's strain stays below 1.5 %: stiff tendons barely stretch.
  for (size_t k = 0; k < leg.strands.size(); ++k) {
    const double l0 = leg.strands[k].natural_length * (leg.strands[k].tendon < 2 ? 0.99 : 1.0);
    EXPECT_LT(msd::leg_strand_length(leg, leg.strands[k], be.tissue.x, be.knee.angle) / l0 - 1.0, 0.015) << k;
  }
  EXPECT_GT(s1.tissue.newton_iterations, 0);
  msd::LegState se = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch s2;
  EXPECT_THROW(for (int k = 0; k < 20; ++k) msd::step_leg(leg, se, c, dt, s2), msd::SimulationFailure);
}

TEST(LegModel, AHillLegWithRealToeTendonsFollowsItsExcitationThroughActivationDynamics) {
  // Issue 18: the Hill law (Zajac 1989) at a specific tension of 0.25 MPa
  // (within the published 0.2-0.35 MPa), tendons at 1.2 GPa beyond a 3 %
  // toe, activation time constants 10 / 40 ms, on BDF2 at 1 ms.
  msd::LegModelOptions o = options();
  o.tendon_modulus = 1.2e9;
  o.tendon_toe_strain = 0.03;
  o.nonlinear_threshold = 0.0;
  o.hill.enabled = true;
  o.max_muscle_stress = 2.5e5;
  o.activation_time = 0.01;
  o.deactivation_time = 0.04;
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  ASSERT_TRUE(leg.tissue.muscles[msd::kBackMuscleIndex].hill.enabled);
  msd::LegControls c;
  c.tendon_length_scale = {0.99, 0.99, 1.0, 1.0};
  c.back_activation = 1.0;  // an excitation from rest
  msd::LegState s = msd::leg_rest_state(leg, 0.0);  // no activation state yet: the first step starts it at rest
  msd::LegScratch scratch;
  const double dt = 1e-3;
  msd::step_leg(leg, s, c, dt, scratch, msd::Integrator::Bdf2);
  const double back_pull_first = scratch.tendon_tension[0] + scratch.tendon_tension[1];  // at a = 0.095
  for (int k = 1; k < 20; ++k) msd::step_leg(leg, s, c, dt, scratch, msd::Integrator::Bdf2);
  const double back_pull_active = scratch.tendon_tension[0] + scratch.tendon_tension[1];  // at a = 0.86
  EXPECT_TRUE(s.tissue.x.allFinite());
  // The activation is the closed form of its first-order law: 1 - exp(-t / tau_a).
  EXPECT_NEAR(s.activation[msd::kBackMuscleIndex], 1.0 - std::exp(-0.02 / 0.01), 1e-12);
  EXPECT_EQ(s.activation[msd::kFrontMuscleIndex], 0.0);
  // Released, it falls with tau_d.
  c.back_activation = 0.0;
  const double a0 = s.activation[msd::kBackMuscleIndex];
  for (int k = 0; k < 10; ++k) msd::step_leg(leg, s, c, dt, scratch, msd::Integrator::Bdf2);
  EXPECT_NEAR(s.activation[msd::kBackMuscleIndex], a0 * std::exp(-0.01 / 0.04), 1e-12);
  // The back tendons carry the muscle's pull (beyond their 1 % pre-tension),
  // and their strain is reported per tendon.
  EXPECT_GT(back_pull_active, 1.5 * back_pull_first);
  ASSERT_EQ(scratch.tendon_strain.size(), 4u);
  EXPECT_GT(std::max(scratch.tendon_strain[0], scratch.tendon_strain[1]), 0.0);
  EXPECT_LT(std::max(scratch.tendon_strain[0], scratch.tendon_strain[1]), 0.05);
}

TEST(LegModel, AFemurMovingAtConstantVelocityCarriesTheLegWithoutChangingItsMotion) {
  // Galilean invariance: standing, the knee bent 17 deg and let go, once with
  // the femur held and once with the whole leg carried at 0.5 m/s (the femur
  // scripted, LegControls::femur). Relative to the femur, the same motion to
  // round-off, with the explicit step and with BDF2 (exact for motion linear
  // in time; Newton's solve on the carried leg): a moving frame that is not
  // inertial would show.
  msd::LegModelOptions o = options();
  o.gravity = msd::Vec3(0, 0, -9.81);
  const msd::Vec3 V(0.5, 0.2, -0.3);
  auto carried = [&](double t) {
    msd::RigidMotion m;
    m.offset = V * t;
    m.velocity = V;
    return m;
  };
  struct Run {
    msd::Integrator integrator;
    double dt;
    int steps;
    double tolerance;  // m
    double nonlinear_threshold;
  };
  // (BDF2 with the non-linear terms always on: switched on and off at the
  // thesis' 0.7 threshold they stall its Newton solve, held leg or carried.)
  for (const Run& r : {Run{msd::Integrator::SymplecticEuler, 1e-4, 400, 1e-9, o.nonlinear_threshold},
                       Run{msd::Integrator::Bdf2, 1e-3, 40, 1e-8, 0.0}}) {
    const std::string name = msd::to_string(r.integrator);
    o.nonlinear_threshold = r.nonlinear_threshold;
    const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
    msd::LegState held = msd::leg_rest_state(leg, 0.3), moving = held;
    msd::place_leg_on_femur(moving, carried(0.0));
    msd::LegScratch a, b;
    msd::LegControls c;
    for (int k = 1; k <= r.steps; ++k) {
      msd::step_leg(leg, held, {}, r.dt, a, r.integrator);
      c.femur = carried(k * r.dt);
      msd::step_leg(leg, moving, c, r.dt, b, r.integrator);
    }
    EXPECT_GT(std::abs(held.knee.angle - 0.3), 0.003) << name;  // it did move (0.3 deg in 40 ms)
    EXPECT_NEAR(moving.knee.angle, held.knee.angle, r.tolerance) << name;
    const msd::Points shifted = held.tissue.x.colwise() + V * held.tissue.t;
    EXPECT_LT((moving.tissue.x - shifted).cwiseAbs().maxCoeff(), r.tolerance) << name;
    EXPECT_LT((moving.tissue.v.colwise() - V - held.tissue.v).cwiseAbs().maxCoeff(), 1e-6) << name;  // m/s
    EXPECT_NEAR(b.knee_torque, a.knee_torque, 1e-6 * (1.0 + std::abs(a.knee_torque))) << name;
  }
}

TEST(LegModel, AThighSwungForwardFromTheHipLeavesTheLowerLegBehindAndTheKneeFlexes) {
  // Standing, relaxed; the femur turned forward (hip flexion) by keyframes
  // about the thigh's top. The lower leg's inertia keeps it behind: the knee
  // flexes while the thigh accelerates, and the femur's nodes are where the
  // keyframes put them.
  msd::LegModelOptions o = options();
  o.gravity = msd::Vec3(0, 0, -9.81);
  o.min_flexion = -0.2;
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  msd::PoseKeyframes hip(msd::Vec3(0, 0, 0.93));
  hip.add(0.0, msd::Vec3(0, 0, 0.93), Eigen::Quaterniond::Identity());
  hip.add(0.4, msd::Vec3(0, 0, 0.93), Eigen::Quaterniond(Eigen::AngleAxisd(-30.0 * kDeg, msd::Vec3::UnitY())));
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  msd::LegControls c;
  const double dt = 1e-4;
  double most = 0.0;
  for (int k = 1; k <= 1500; ++k) {
    c.femur = hip.at(k * dt);
    msd::step_leg(leg, s, c, dt, scratch);
    most = std::max(most, s.knee.angle);
  }
  EXPECT_GT(most, 3.0 * kDeg);
  const msd::RigidMotion f = hip.at(s.tissue.t);
  for (int i : leg.femur_nodes) EXPECT_LT((msd::Vec3(s.tissue.x.col(i)) - f.place(leg.tissue.rest_positions.col(i))).norm(), 1e-12);
  // The lower leg rides on the turned femur: its nodes at R_f (c + R(theta) (X - c)) + d_f.
  const msd::Mat3 R = f.rotation * msd::hinge_rotation(leg.knee, s.knee.angle);
  const msd::Vec3 c_w = f.place(leg.knee.centre);
  for (int i : leg.lower_nodes)
    EXPECT_LT((msd::Vec3(s.tissue.x.col(i)) - (c_w + R * (leg.tissue.rest_positions.col(i) - leg.knee.centre))).norm(), 1e-12);
}

TEST(LegModel, TheSkinIsAClosedMembraneOnTheOuterSurfaceAndHoldsTheStandingThighsFleshUp) {
  // The skin (issue 18, item 4) at benchmarks/materials.yaml's in-vivo
  // constants (E = 129 kPa, Diridollou et al. 2000; h = 1.55 mm, Laurent et
  // al. 2007) over flesh and muscle at the same file's.
  msd::LegModelOptions with = options();
  with.skin = msd::LegModelOptions::Skin{129e3, 1.55e-3};
  const msd::LegModel leg = msd::build_leg_model(shipped().mesh, shipped().tendons, with);
  const msd::SkinMembrane& skin = leg.tissue.skin;
  ASSERT_GT(skin.triangles.size(), 500u);
  EXPECT_DOUBLE_EQ(skin.shear_modulus, 129e3 / 3.0);
  // A sleeve: every edge of the membrane is shared by an even number of its
  // triangles (two, or four where the surface pinches) except on the rims at
  // the limb's two end cuts (hip and bottom), which it leaves open; no triangle
  // lies in a cut.
  const msd::Points& rest = leg.tissue.rest_positions;
  const double top = rest.row(2).maxCoeff(), bottom = rest.row(2).minCoeff();
  std::map<std::pair<int, int>, int> uses;
  for (const msd::MembraneTriangle& t : skin.triangles) {
    int at_top = 0, at_bottom = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = t.nodes[static_cast<size_t>(k)], b = t.nodes[static_cast<size_t>((k + 1) % 3)];
      ++uses[{std::min(a, b), std::max(a, b)}];
      at_top += rest(2, a) > top - 1e-9;
      at_bottom += rest(2, a) < bottom + 1e-9;
    }
    EXPECT_LT(at_top, 3);
    EXPECT_LT(at_bottom, 3);
  }
  long rim = 0;
  for (const auto& [edge, n] : uses) {
    const bool in_a_cut = (rest(2, edge.first) > top - 1e-9 && rest(2, edge.second) > top - 1e-9) ||
                          (rest(2, edge.first) < bottom + 1e-9 && rest(2, edge.second) < bottom + 1e-9);
    if (n % 2) {
      EXPECT_TRUE(in_a_cut) << "a free edge " << edge.first << "-" << edge.second << " away from the cuts";
      ++rim;
    }
  }
  EXPECT_GT(rim, 10);  // the two rims are open
  // Standing, thigh fixed, gravity on: after 0.2 s the free thigh nodes have
  // sagged less with the skin than without it (it carries part of the weight).
  const msd::LegModel bare = msd::build_leg_model(shipped().mesh, shipped().tendons, options());
  EXPECT_TRUE(bare.tissue.skin.empty());
  auto sag = [](const msd::LegModel& model) {
    msd::LegState s = msd::leg_rest_state(model, 0.0);
    msd::LegScratch scratch;
    for (int k = 0; k < 1000; ++k) msd::step_leg(model, s, {}, 2e-4, scratch);
    double sum = 0.0;
    long count = 0;
    for (int i = 0; i < model.tissue.num_nodes(); ++i)
      if (!model.attached[static_cast<size_t>(i)] && model.tissue.rest_positions(2, i) > 0.6) {
        sum += model.tissue.rest_positions(2, i) - s.tissue.x(2, i);
        ++count;
      }
    return sum / static_cast<double>(count);
  };
  const double sag_bare = sag(bare), sag_skin = sag(leg);
  EXPECT_GT(sag_bare, 1e-3);  // the flesh sags by millimetres
  EXPECT_LT(sag_skin, 0.9 * sag_bare) << "with skin " << sag_skin << " m, without " << sag_bare << " m";
  // And the implicit step takes the membrane's stiffness: BDF2 at 2 ms stays finite.
  msd::LegState s = msd::leg_rest_state(leg, 0.0);
  msd::LegScratch scratch;
  for (int k = 0; k < 10; ++k) msd::step_leg(leg, s, {}, 2e-3, scratch, msd::Integrator::Bdf2);
  EXPECT_TRUE(s.tissue.x.allFinite());
}

TEST(LegModel, TheContinuumLegTakesOneVolumeRatioPerCubeOfTheGrid) {
  // Five tets per cube each holding its own volume would lock nearly
  // incompressible tissue; the continuum element's groups are the grid's cubes.
  const msd::LimbMesh& m = shipped().mesh;
  ASSERT_EQ(m.tet_cube.size(), m.mesh.tets.size());
  std::map<long, int> tets_of_cube;
  for (long c : m.tet_cube) ++tets_of_cube[c];
  EXPECT_EQ(static_cast<long>(tets_of_cube.size()), m.cubes);
  for (const auto& [c, n] : tets_of_cube) EXPECT_EQ(n, 5) << "cube " << c;

  msd::LegModelOptions o = options();
  o.joint_space_radius = 0.09;
  o.terms = msd::kNeoHookean | msd::kDampers | msd::kGravity;
  o.passive.poisson_ratio = 0.495;
  o.muscle.poisson_ratio = 0.495;
  const msd::LegModel leg = msd::build_leg_model(m, shipped().tendons, o);
  const msd::VolumeGroups& g = leg.tissue.volume_groups;
  ASSERT_FALSE(g.empty());
  ASSERT_EQ(g.of_tet.size(), leg.tets.size());
  // As many groups as cubes with a tet left after the joint space; a group's
  // tets are one cube's: at most five, one region, their centroids within the
  // cube's diagonal of each other.
  std::map<int, std::vector<size_t>> tets_of_group;
  for (size_t t = 0; t < leg.tets.size(); ++t) tets_of_group[g.of_tet[t]].push_back(t);
  EXPECT_EQ(static_cast<int>(tets_of_group.size()), g.size());
  EXPECT_GT(g.size(), m.cubes - 100);
  const double diagonal = std::sqrt(3.0) * 0.0245;
  for (const auto& [group, tets] : tets_of_group) {
    EXPECT_LE(tets.size(), 5u);
    const msd::Vec3 first = [&] {
      msd::Vec3 c = msd::Vec3::Zero();
      for (int v : leg.tets[tets.front()]) c += 0.25 * leg.tissue.rest_positions.col(v);
      return c;
    }();
    for (size_t t : tets) {
      EXPECT_EQ(leg.tissue.elements[t].region, leg.tissue.elements[tets.front()].region);
      msd::Vec3 c = msd::Vec3::Zero();
      for (int v : leg.tets[t]) c += 0.25 * leg.tissue.rest_positions.col(v);
      EXPECT_LT((c - first).norm(), diagonal) << "group " << group;
    }
  }
  // The thesis' terms take no groups.
  const msd::LegModel thesis = msd::build_leg_model(m, shipped().tendons, options());
  EXPECT_TRUE(thesis.tissue.volume_groups.empty());
  // A mesh without its tets' cubes is refused for the continuum element, not run one ratio per tet.
  msd::LimbMesh without = m;
  without.tet_cube.clear();
  const std::string no_cubes = refusal_of(without, o);
  EXPECT_NE(no_cubes.find("cube"), std::string::npos) << no_cubes;
  EXPECT_NO_THROW(msd::build_leg_model(without, shipped().tendons, options()));  // the thesis' terms need none
}

TEST(LegModel, DirectTendonsRunStraightFromTheirMuscleNodeAndDragNoFleshNode) {
  // tendons_direct: each strand is its muscle node and its bone end, nothing
  // between - so a taut strand pulls only the muscle node and the bone, and
  // its natural length is the straight distance.
  msd::LegModelOptions o = knee_cap_inserted();
  const msd::Vec3& insertion = kKneeCapInsertion;
  const msd::LegModel routed = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  o.tendons_direct = true;
  const msd::LegModel direct = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  ASSERT_EQ(direct.strands.size(), routed.strands.size());
  int had_interior = 0;
  for (size_t i = 0; i < direct.strands.size(); ++i) {
    const msd::LegStrand& d = direct.strands[i];
    const msd::LegStrand& r = routed.strands[i];
    had_interior += r.nodes.size() > (r.anchored ? 1u : 2u);
    EXPECT_EQ(d.nodes.front(), r.nodes.front());
    EXPECT_EQ(d.anchored, r.anchored);
    const msd::Vec3 from = direct.tissue.rest_positions.col(d.nodes.front());
    if (d.anchored) {
      ASSERT_EQ(d.nodes.size(), 1u);
      EXPECT_NEAR(d.natural_length, (insertion - from).norm(), 1e-15);
    } else {
      ASSERT_EQ(d.nodes.size(), 2u);
      EXPECT_EQ(d.nodes.back(), r.nodes.back());
      EXPECT_NEAR(d.natural_length, (direct.tissue.rest_positions.col(d.nodes.back()) - from).norm(), 1e-15);
    }
  }
  EXPECT_GT(had_interior, 0);  // the routed leg has strands through tissue nodes: the option changes something
  // Shortened by 10 %: the knee cap's straight strands pull with E A 0.1
  // each, in front of the knee's centre: they extend it.
  msd::LegScratch scratch;
  step_with_the_knee_cap_tendon_shortened(direct, scratch);
  EXPECT_NEAR(scratch.tendon_tension[3], 6 * o.tendon_modulus * o.strand_area * 0.1, 1e-9);
  EXPECT_LT(scratch.knee_torque, 0.0);
}

TEST(LegModel, AnAponeurosisTakesAStrandFromEveryFibreEndAndKeepsEachTendonsSection) {
  // tendons_at_fibre_ends: each tendon's strands leave every free end of its
  // muscle's fibres on its side (fibre_end_nodes), straight to its bone end,
  // and share the patch's section (strands x strand_area): the tendon pulls
  // as hard at the same strain, from more of the muscle.
  msd::LegModelOptions o = knee_cap_inserted();
  o.tendons_direct = true;
  const msd::LegModel patch = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  o.tendons_at_fibre_ends = true;
  const msd::LegModel apo = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  const msd::Points& x = apo.tissue.rest_positions;
  ASSERT_EQ(apo.tendon_names, patch.tendon_names);
  for (size_t t = 0; t < apo.tendon_names.size(); ++t) {
    const msd::TendonStrands& route = shipped().tendons[t];
    const bool front = route.muscle == msd::kFrontMuscle;
    const auto& units = front ? apo.front_units : apo.back_units;
    // The tendon's side: its patch's end of the muscle along the line (+z up the thigh).
    const auto first = std::find_if(patch.strands.begin(), patch.strands.end(),
                                    [&](const msd::LegStrand& s) { return s.tendon == static_cast<int>(t); });
    ASSERT_NE(first, patch.strands.end()) << route.name;
    const double patch_z = x(2, first->nodes.front());
    double middle = 0.0;
    for (const auto& u : units) middle += 0.5 * (x(2, u.a) + x(2, u.b));
    middle /= static_cast<double>(units.size());
    std::vector<int> expected;
    for (int v : msd::fibre_end_nodes(x, units, msd::Vec3::UnitZ(), patch_z > middle ? 1 : -1))
      if (!apo.attached[static_cast<size_t>(v)]) expected.push_back(v);
    std::vector<int> got;
    double section = 0.0, patch_section = 0.0;
    for (const msd::LegStrand& s : apo.strands)
      if (s.tendon == static_cast<int>(t)) {
        got.push_back(s.nodes.front());
        section += s.k_t * s.natural_length / o.tendon_modulus;  // k = E A / L
        EXPECT_EQ(s.nodes.size(), s.anchored ? 1u : 2u);
      }
    for (const msd::LegStrand& s : patch.strands)
      if (s.tendon == static_cast<int>(t)) patch_section += s.k_t * s.natural_length / o.tendon_modulus;
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << route.name;
    EXPECT_FALSE(got.empty()) << route.name;  // (the thesis leg's 30-tet front muscle has 4 fibres; the back, more than its patch)
    EXPECT_NEAR(section, route.strands.size() * o.strand_area, 1e-12 * section) << route.name;
    EXPECT_NEAR(section, patch_section, 1e-12 * section) << route.name;
  }
  // The sides, checked apart from the code's own rule: each muscle's lower
  // tendon (back_lower, front_lower) leaves fibre ends lower down the thigh
  // (z) than its upper tendon.
  const auto ends_of = [&](int t) {
    std::vector<int> v;
    for (const msd::LegStrand& s : apo.strands)
      if (s.tendon == t) v.push_back(s.nodes.front());
    return v;
  };
  const auto mean_z = [&](const std::vector<int>& v) {
    double z = 0.0;
    for (int i : v) z += x(2, i);
    return z / static_cast<double>(v.size());
  };
  for (const auto& [upper, lower] : {std::pair{0, 1}, std::pair{2, 3}}) {
    ASSERT_EQ(shipped().tendons[static_cast<size_t>(upper)].name.find("upper") != std::string::npos, true);
    ASSERT_EQ(shipped().tendons[static_cast<size_t>(lower)].name.find("lower") != std::string::npos, true);
    for (int i : ends_of(lower))
      for (int j : ends_of(upper)) EXPECT_LT(x(2, i), x(2, j)) << shipped().tendons[static_cast<size_t>(lower)].name;
    EXPECT_LT(mean_z(ends_of(lower)), mean_z(ends_of(upper)));
  }
  // Shortened by 10 %, the knee cap's tendon pulls with E x its section x 0.1,
  // as the patch's: the same tendon, spread over the muscle's end.
  msd::LegScratch scratch;
  step_with_the_knee_cap_tendon_shortened(apo, scratch);
  EXPECT_NEAR(scratch.tendon_tension[3], 6 * o.tendon_modulus * o.strand_area * 0.1, 1e-6);
  EXPECT_LT(scratch.knee_torque, 0.0);
  // Without the direct route the fibre ends cannot be routed: refused, naming it.
  o.tendons_direct = false;
  const std::string routed = refusal_of(shipped().mesh, o);
  EXPECT_NE(routed.find("direct route"), std::string::npos) << routed;
}

TEST(LegModel, OnTheAnatomicalLegEveryTendonsAponeurosisSpansMoreFibresThanItsPatch) {
  // The anatomical leg's muscles (msd/data/leg_anatomical, sized to
  // Handsfield et al. 2014) are many cubes across, so each tendon's fibre
  // ends (17-22) outnumber its patch's 6-8 strands: the force of every
  // fibre reaches the tendon directly, not through the soft tissue around a
  // patch (docs/leg-motion.md, "The physiological leg").
  msd::LimbMeshOptions mo;
  mo.spacing = 0.0245;
  const msd::MeshedLeg anatomical = msd::mesh_leg(std::string(TISSUEBENCH_DATA_DIR) + "/leg_anatomical", mo);
  msd::LegModelOptions o = options();
  o.tendons_direct = true;
  o.tendons_at_fibre_ends = true;
  const msd::LegModel leg = msd::build_leg_model(anatomical.mesh, anatomical.tendons, o);
  for (size_t t = 0; t < leg.tendon_names.size(); ++t) {
    const long n = std::count_if(leg.strands.begin(), leg.strands.end(),
                                 [&](const msd::LegStrand& s) { return s.tendon == static_cast<int>(t); });
    std::printf("%s: %ld fibre-end strands (patch: %zu)\n", leg.tendon_names[t].c_str(), n,
                anatomical.tendons[t].strands.size());
    EXPECT_GT(n, static_cast<long>(anatomical.tendons[t].strands.size())) << leg.tendon_names[t];
  }
}

TEST(LegModel, AMusclesTendonsAreJustTautWithTheKneeAtItsOptimalAngle) {
  // front_optimal_angle: the front muscle's tendons take their natural
  // lengths with the tissue at rest and the knee there, so the knee cap's
  // tendon (inserted on the lower bone, in front of the axis) is slack when
  // the knee is straighter and pulls when it is more flexed. The other
  // tendons keep the straight knee's lengths. Every tendon here runs
  // straight to an insertion (the angle needs it): the knee cap's at
  // kKneeCapInsertion, the others at their bone node's rest position.
  msd::LegModelOptions o = knee_cap_inserted();
  o.tendons_direct = true;
  {
    const msd::LegModel routed = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
    for (const msd::LegStrand& s : routed.strands)
      if (!s.anchored) o.tendon_insertions[static_cast<size_t>(s.tendon)] = routed.tissue.rest_positions.col(s.nodes.back());
  }
  const msd::LegModel straight = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  const double optimum = 50.0 * kDeg;
  o.front_optimal_angle = optimum;
  const msd::LegModel flexed = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  ASSERT_EQ(flexed.strands.size(), straight.strands.size());
  const msd::Mat3 r = msd::hinge_rotation(flexed.knee, optimum);
  int knee_cap_strands = 0;
  for (size_t i = 0; i < flexed.strands.size(); ++i) {
    const msd::LegStrand& s = flexed.strands[i];
    ASSERT_TRUE(s.anchored);
    if (s.tendon != 3) {
      EXPECT_EQ(s.natural_length, straight.strands[i].natural_length) << flexed.tendon_names[s.tendon];
      continue;
    }
    // Closed form: from the muscle node at rest to the insertion turned about the knee.
    ASSERT_EQ(s.nodes.size(), 1u);
    const msd::Vec3 p = flexed.tissue.rest_positions.col(s.nodes.front());
    const msd::Vec3 q = flexed.knee.centre + r * (kKneeCapInsertion - flexed.knee.centre);
    EXPECT_NEAR(s.natural_length, (p - q).norm(), 1e-12);
    EXPECT_GT(s.natural_length, straight.strands[i].natural_length);  // flexion lengthens a tendon in front of the axis
    ++knee_cap_strands;
  }
  EXPECT_GT(knee_cap_strands, 0);
  // Held at 40 degrees the knee cap's tendon is slack; at 60, taut.
  for (const double deg : {0.0, 40.0, 60.0}) {
    msd::LegState st = msd::leg_rest_state(flexed, deg * kDeg);
    msd::LegControls c;
    c.scripted_knee = msd::HingeState{deg * kDeg, 0.0};
    msd::LegScratch scratch;
    msd::step_leg(flexed, st, c, 1e-4, scratch);
    if (deg < 50.0)
      EXPECT_EQ(scratch.tendon_tension[3], 0.0) << deg;
    else
      EXPECT_GT(scratch.tendon_tension[3], 0.0) << deg;
  }
  // The back muscle's angle moves only its lower tendon (on the lower bone,
  // behind the axis: flexion shortens it); the front's stay as they were.
  o.back_optimal_angle = 30.0 * kDeg;
  const msd::LegModel both = msd::build_leg_model(shipped().mesh, shipped().tendons, o);
  int back_lower_strands = 0;
  for (size_t i = 0; i < both.strands.size(); ++i) {
    if (both.strands[i].tendon == 1) {
      EXPECT_LT(both.strands[i].natural_length, flexed.strands[i].natural_length) << i;
      ++back_lower_strands;
    } else {
      EXPECT_EQ(both.strands[i].natural_length, flexed.strands[i].natural_length) << i;
    }
  }
  EXPECT_GT(back_lower_strands, 0);
  // An angle outside the knee's range is refused, naming it.
  o.back_optimal_angle = 0.0;
  o.front_optimal_angle = o.max_flexion + 0.1;
  const std::string outside = refusal_of(shipped().mesh, o);
  EXPECT_NE(outside.find("optimal-length knee angle"), std::string::npos) << outside;
  // So is an angle for a strand that does not run straight to an insertion:
  // through flesh nodes, or to a bone node, its length would not turn with
  // the knee.
  o.front_optimal_angle = optimum;
  o.tendons_direct = false;
  const std::string routed = refusal_of(shipped().mesh, o);
  EXPECT_NE(routed.find("direct route"), std::string::npos) << routed;
  o.tendons_direct = true;
  o.tendon_insertions[3] = std::nullopt;
  const std::string to_a_node = refusal_of(shipped().mesh, o);
  EXPECT_NE(to_a_node.find("insertion at the path's end"), std::string::npos) << to_a_node;
}
