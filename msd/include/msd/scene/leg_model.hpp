// The leg in motion (thesis 5.2.7, 5.3, 5.4): the meshed limb compiled into a
// tissue model, a fixed femur, a lower bone on the knee hinge, tendon strands
// and contractile units; one step advances all of them together.
//
// What moves how:
//  - femur nodes (the upper bone's tet nodes and bone points) are held at rest
//    (the thigh fixed, thesis 3.7.2 "kinematic");
//  - lower-bone nodes (its tet nodes and bone points) follow the hinge exactly,
//    x = c + R(theta)(X - c) (msd/skeleton/hinge.hpp);
//  - every other node is integrated by semi-implicit Euler under the tissue's
//    internal forces, the tendons, the muscles and gravity; then, where the
//    scene names a region behind the knee, skin nodes that entered the other
//    side's tissue are put back on its surface (msd/contact/self_contact.hpp).
// The hinge is driven by the torque about its axis of everything acting on
// the lower-bone nodes - tissue forces from the free nodes around them, tendon
// pulls, the nodes' own weight - plus the bone's weight and an added joint
// torque, with I = the bone's moment about the axis (its tets at the thesis'
// bone density, exact) + sum of the attached nodes' m r^2. Or the angle is
// scripted (kinematic override). Bone tets stay in the tissue model: their
// internal forces are equal and opposite between nodes of one rigid body and
// add no torque. Tets with nodes on both bones - the joint space, one cube
// of passive tissue between condyles and plateau in the cubic mesh - are left
// out: any rotation about the hinge would crush them.
#pragma once

#include "msd/contact/self_contact.hpp"
#include "msd/forces/muscle_units.hpp"
#include "msd/integrate/step.hpp"
#include "msd/mesh/limb_mesher.hpp"
#include "msd/mesh/tendon_paths.hpp"
#include "msd/skeleton/hinge.hpp"
#include "msd/skeleton/rigid_body.hpp"

#include <optional>
#include <string>
#include <vector>

namespace msd {

struct LegModelOptions {
  TissueMaterial passive, muscle;    ///< passive tissue; both muscles (passive properties)
  unsigned terms = kSprings | kDampers | kRepulsion | kVolume | kGravity;
  double nonlinear_threshold = 0.7;  ///< thesis 5.8
  Vec3 gravity{0.0, 0.0, -9.81};     ///< m/s^2 in the leg's frame
  Vec3 knee_centre{Vec3::Zero()};
  Vec3 knee_axis{Vec3::UnitY()};     ///< positive rotation = flexion
  double min_flexion = 0.0, max_flexion = 2.4;  ///< rad
  double bone_density = kBoneDensity;
  /// Tendons (thesis 5.3): modulus (the thesis' softened 0.8 MPa by default)
  /// and the cross-section of one strand.
  double tendon_modulus = 0.8e6, strand_area = 2.0e-5;
  /// Muscles (5.2.7): maximum isometric stress, line of action (unit vectors,
  /// front and back muscle) and the units' angle tolerance.
  double max_muscle_stress = 3.0e5;
  Vec3 front_line{Vec3::UnitZ()}, back_line{Vec3::UnitZ()};
  double unit_angle_deg = 30.0;
  /// Skin against skin behind the knee (thesis 5.6): the box tested, split at
  /// the knee's centre across the leg's axis. None: no collision work.
  std::optional<std::pair<Vec3, Vec3>> knee_contact_box;
  Vec3 leg_axis{Vec3::UnitZ()};  ///< thigh side = (x - knee centre) . axis >= 0
};

struct LegStrand {
  std::vector<int> nodes;    ///< muscle node first, bone node last
  int tendon = 0;            ///< index into LegModel::tendon_names
  double natural_length = 0.0, k_t = 0.0;
};

struct LegModel {
  Model tissue;
  std::vector<int> femur_nodes, lower_nodes;
  std::vector<char> attached;        ///< per node: 1 femur, 2 lower bone, 0 free
  Hinge knee;
  MassProperties lower_bone;         ///< the bone's own tets
  std::vector<std::string> tendon_names;
  std::vector<LegStrand> strands;
  std::vector<ContractileUnit> front_units, back_units;
  double front_unit_force = 0.0, back_unit_force = 0.0;  ///< N per unit at activation 1
  std::vector<Tet> tets;  ///< the tissue's tets (the contact test's solids)
  long joint_space_tets = 0;  ///< tets left out because they had nodes on both bones
  std::optional<SelfContactRegion> knee_contact;
};

struct LegState {
  State tissue;
  HingeState knee;
};

struct LegControls {
  double front_activation = 0.0, back_activation = 0.0;  ///< 0 ... 1
  std::vector<double> tendon_length_scale;  ///< per tendon (pre-tension: < 1); empty: 1
  double joint_torque = 0.0;                ///< added about the hinge axis, N m
  std::optional<HingeState> scripted_knee;  ///< kinematic override of the angle
};

/// Diagnostics of the last step.
struct LegScratch {
  Scratch tissue;
  std::vector<double> tendon_tension;  ///< per tendon: the sum over its strands (N)
  double knee_torque = 0.0;            ///< about the axis, N m
  SelfContactReport knee_contact;      ///< skin against skin behind the knee
};

/// Compiles the leg. Throws msd::Error if a bone has no tets or bone points,
/// a tendon's strand is degenerate, or a material is unphysical.
LegModel build_leg_model(const LimbMesh& mesh, const std::vector<TendonStrands>& tendons,
                         const LegModelOptions& options);

/// The rest state with the knee at `angle` (rad), lower-leg nodes placed rigidly.
LegState leg_rest_state(const LegModel& model, double angle);

/// One step of dt. Throws SimulationFailure (when, where) on a non-finite value.
void step_leg(const LegModel& model, LegState& state, const LegControls& controls, double dt, LegScratch& scratch);

/// Kinetic energy of the free tissue nodes and of the lower leg (J).
double leg_kinetic_energy(const LegModel& model, const LegState& state);

}  // namespace msd
