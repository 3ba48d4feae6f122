// The leg in motion (thesis 5.2.7, 5.3, 5.4): the meshed limb compiled into a
// tissue model, a fixed femur, a lower bone on the knee hinge, tendon strands
// and contractile units; one step advances all of them together. They are all
// parts of the one msd::Model (LegModel::tissue: two kinematic groups, the
// knee joint driving the second, the strands, the two muscles, the contact
// behind the knee and the obstacles), and step_leg is msd::step on it with the
// leg's controls translated - the benchmarks' step, with any integrator.
//
// What moves how:
//  - femur nodes (the upper bone's tet nodes and bone points) are held at rest
//    (the thigh fixed, thesis 3.7.2 "kinematic"), or moved rigidly by a
//    scripted hip (LegControls::femur), which carries the knee's hinge;
//  - lower-bone nodes (its tet nodes and bone points) follow the hinge exactly,
//    x = c + R(theta)(X - c) (msd/skeleton/hinge.hpp);
//  - every other node is integrated (semi-implicit Euler by default) under the
//    tissue's internal forces, the tendons, the muscles and gravity; then, where the
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

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace msd {

struct LegModelOptions {
  TissueMaterial passive, muscle;    ///< passive tissue; both muscles (passive properties)
  unsigned terms = kSprings | kDampers | kRepulsion | kVolume | kGravity;
  double nonlinear_threshold = 0.7;  ///< thesis 5.8
  int threads = 1;                   ///< force-evaluation threads (results identical for every count)
  bool reference_forces = false;     ///< the per-tet reference loop instead of the engine (Model::reference_forces)
  NewtonOptions newton;              ///< the implicit integrator's Newton iterations (Model::newton)
  Vec3 gravity{0.0, 0.0, -9.81};     ///< m/s^2 in the leg's frame
  Vec3 knee_centre{Vec3::Zero()};
  Vec3 knee_axis{Vec3::UnitY()};     ///< positive rotation = flexion
  double min_flexion = 0.0, max_flexion = 2.4;  ///< rad
  double bone_density = kBoneDensity;
  /// The joint space, widened: besides the tets with nodes on both bones,
  /// leave out those with a node on one bone and a node sharing a tet with
  /// the other whose centroid lies within this distance of the knee's axis
  /// (m; 0: only the first kind). Flexed past about 90 degrees, such a tet is
  /// squeezed between the femur's condyles and the tibia's plateau.
  double joint_space_radius = 0.0;
  /// Tendons (thesis 5.3): modulus (the thesis' softened 0.8 MPa by default)
  /// and the cross-section of one strand.
  double tendon_modulus = 0.8e6, strand_area = 2.0e-5;
  /// Per-tendon moduli overriding tendon_modulus, by tendon name (a relaxed
  /// muscle in series makes its tendon's line compliant; an active one stiff).
  std::map<std::string, double> tendon_moduli;
  /// Per tendon (in order): when set, each strand's bone end is this point,
  /// fixed on the bone its last node belongs to, in place of that node - the
  /// anatomical insertion (a tendon path's last point), not the nearest mesh
  /// node (at 24.5 mm the knee cap has no node of its own).
  std::vector<std::optional<Vec3>> tendon_insertions;
  /// false (the thesis, 4.5): each strand runs through the tissue nodes its
  /// route snapped to, and drags them. true: straight from its muscle node to
  /// its bone end (the insertion, or the bone node), with no node between -
  /// a tendon slides in its sheath and bears on no flesh it passes; bent
  /// through 24.5 mm flesh nodes, a real tendon's pull crushes the flesh at
  /// the bend (docs/leg-motion.md, the physiological leg).
  bool tendons_direct = false;
  /// false (the thesis): each tendon's strands leave the few muscle nodes
  /// nearest its path's start (route_tendon's patch). true (an aponeurosis:
  /// every fibre inserts on tendon): one strand from each end of the
  /// muscle's fibres on the tendon's side (fibre_end_nodes) to the tendon's
  /// bone end (route_tendon gives all of a tendon's strands one bone node;
  /// with an insertion, that point), the tendon's section (its patch strands x
  /// strand_area) shared among them. The total section is kept, not the
  /// stiffness: each strand's E A / L has its own length. Needs
  /// tendons_direct: a strand from every fibre end cannot be routed through
  /// the path's tissue nodes.
  bool tendons_at_fibre_ends = false;
  /// Every strand's toe region (msd/forces/tendon.hpp): 0, the thesis' linear
  /// strand; real tendon about 0.02-0.03 with tendon_modulus about 1.2 GPa.
  double tendon_toe_strain = 0.0;
  /// Muscles (5.2.7): maximum isometric stress, line of action (unit vectors,
  /// front and back muscle) and the units' angle tolerance.
  double max_muscle_stress = 3.0e5;
  /// The muscles' force from these cross-sections (m^2; the published PCSA,
  /// docs/leg-geometry.md) instead of the mesh's: F_max = max_muscle_stress x
  /// area (unit_force_for_area). Unset: the mesh's section (unit_force).
  std::optional<double> front_pcsa, back_pcsa;
  Vec3 front_line{Vec3::UnitZ()}, back_line{Vec3::UnitZ()};
  double unit_angle_deg = 30.0;
  /// The units' force-length relation (msd/forces/muscle_units.hpp); the
  /// thesis' constant force is {false}.
  ForceLength force_length{true, 0.5};
  /// The Hill-type law instead (msd/forces/muscle_units.hpp); max_muscle_stress
  /// is then the specific tension (F_max = it x the cross-section).
  HillMuscle hill;
  /// Per muscle (rad): the knee angle at which the muscle is at its mesh
  /// length with its tendons just taut - its tendons' natural lengths are
  /// their paths' lengths with the tissue at rest and the knee at this angle.
  /// Flexed from it, a muscle whose tendon crosses the knee in front of the
  /// axis is stretched; extended, its tendon goes slack. With the Hill law the
  /// mesh length is the optimal length times rest_fibre_stretch, so this is
  /// the posture of the fibres' optimum (the vastus lateralis: near 50
  /// degrees, Chen et al. 2016). 0 (the thesis): the mesh's straight knee.
  /// Must lie in [min_flexion, max_flexion].
  double front_optimal_angle = 0.0, back_optimal_angle = 0.0;
  /// Activation dynamics (activation_step): the controls' activations become
  /// excitations that the muscles' activations follow with these time
  /// constants (s; Zajac 1989: 0.01 and 0.04). 0: the activation is the
  /// control (the thesis).
  double activation_time = 0.0, deactivation_time = 0.0;
  /// The knee's passive structures (ligaments, capsule, the muscles' passive
  /// resistance, lumped; none in the thesis): a viscous torque -b omega, and
  /// an elastic end-range torque -k (theta - theta_hi) beyond `passive_hi`
  /// (and -k (theta - theta_lo) below `passive_lo`) before the hard stops of
  /// the flexion range. 0: none.
  double joint_damping = 0.0;          ///< b, N m s / rad
  double limit_stiffness = 0.0;        ///< k, N m / rad
  double passive_lo = 0.0, passive_hi = 2.0;  ///< rad
  /// The skin (issue 18, item 4): a membrane on the limb's outer surface
  /// triangles (msd/forces/skin_membrane.hpp) of this Young's modulus (Pa) and
  /// thickness (m), but not on the two end planes across leg_axis (the cuts at
  /// the hip and at the bottom, where skin continues). Unset: none (the thesis).
  struct Skin {
    double youngs_modulus = 0.0, thickness = 0.0;
  };
  std::optional<Skin> skin;
  /// Skin against skin behind the knee (thesis 5.6): the box tested, split at
  /// the knee's centre across the leg's axis. None: no collision work.
  std::optional<std::pair<Vec3, Vec3>> knee_contact_box;
  Vec3 leg_axis{Vec3::UnitZ()};  ///< thigh side = (x - knee centre) . axis >= 0
  /// Rigid external objects (thesis 5.6, 6.3, 6.7): each is tested against the
  /// free surface nodes whose rest position lies in its box (a scene names
  /// where contact can happen), or against every free surface node when the
  /// box is absent.
  struct Obstacle {
    RigidObstacle object;  ///< its nodes are ignored (chosen from the box)
    std::optional<std::pair<Vec3, Vec3>> box;
  };
  std::vector<Obstacle> obstacles;
};

struct LegStrand {
  std::vector<int> nodes;    ///< muscle node first, bone node last (unless anchored)
  int tendon = 0;            ///< index into LegModel::tendon_names
  double natural_length = 0.0, k_t = 0.0;
  /// The bone end as a point fixed on a bone (1 femur, 2 lower bone) after
  /// the last node, instead of a bone node.
  bool anchored = false;
  int anchor_bone = 0;
  Vec3 anchor_rest{Vec3::Zero()};
};

struct LegModel {
  Model tissue;
  std::vector<int> femur_nodes, lower_nodes;
  std::vector<char> attached;        ///< per node: 1 femur, 2 lower bone, 0 free
  Hinge knee;
  MassProperties lower_bone;         ///< the bone's own tets
  std::vector<std::string> tendon_names;
  std::vector<LegStrand> strands;
  double tendon_toe_strain = 0.0;    ///< every strand's (LegModelOptions)
  std::vector<ContractileUnit> front_units, back_units;
  double front_unit_force = 0.0, back_unit_force = 0.0;  ///< N per unit at activation 1
  ForceLength force_length;
  HillMuscle hill;
  double activation_time = 0.0, deactivation_time = 0.0;  ///< s (LegModelOptions)
  Vec3 leg_axis{Vec3::UnitZ()};  ///< up the thigh
  double joint_damping = 0.0, limit_stiffness = 0.0, passive_lo = 0.0, passive_hi = 0.0;
  std::vector<Tet> tets;  ///< the tissue's tets (the contact test's solids)
  long joint_space_tets = 0;  ///< tets left out because they had nodes on both bones
  std::optional<SelfContactRegion> knee_contact;  ///< also tissue.self_contact
  std::vector<RigidObstacle> obstacles;  ///< with the nodes each is tested against (also tissue.obstacles)
};

/// The parts of LegModel::tissue (groups, joints, muscles in this order).
inline constexpr int kFemurGroup = 0, kLowerBoneGroup = 1, kKneeJoint = 0, kFrontMuscleIndex = 0,
                     kBackMuscleIndex = 1;

struct LegState {
  State tissue;
  HingeState knee;
  /// The femur's placement now (the rest pose unless the hip is scripted,
  /// LegControls::femur): the last step's.
  RigidMotion femur;
  /// The muscles' activations (front, back) under activation dynamics; empty
  /// until the first step, which starts them at 0 (muscles at rest).
  std::vector<double> activation;
};

struct LegControls {
  /// 0 ... 1; the excitations when the model has activation dynamics.
  double front_activation = 0.0, back_activation = 0.0;
  std::vector<double> tendon_length_scale;  ///< per tendon (pre-tension: < 1); empty: 1
  /// Per strand (LegModel::strands order): natural lengths replacing the
  /// model's (e.g. measured in a starting posture; infinity: slack); empty:
  /// the model's. The length scale applies on top.
  std::vector<double> strand_natural_length;
  double joint_torque = 0.0;                ///< added about the hinge axis, N m
  std::optional<HingeState> scripted_knee;  ///< kinematic override of the angle
  /// The femur's rigid motion at the step's end - a scripted hip
  /// (msd/control/pose_keyframes.hpp); the knee rides on it (Joint::parent).
  /// Unset: the femur held at rest (the thesis).
  std::optional<RigidMotion> femur;
  /// Each obstacle's translation from its rest placement and its velocity
  /// (scripted motion); empty: at rest.
  std::vector<Vec3> obstacle_offset, obstacle_velocity;
};

/// Diagnostics of the last step.
struct LegScratch {
  Scratch tissue;
  std::vector<double> tendon_tension;  ///< per tendon: the sum over its strands (N)
  std::vector<double> tendon_strain;   ///< per tendon: its strands' largest strain (L - L0) / L0
  double knee_torque = 0.0;            ///< about the axis, N m (all of it: tissue, tendons, gravity, passive joint, added; with a scripted hip also the femur's moving frame's, Joint)
  double passive_joint_torque = 0.0;   ///< of it, the knee's passive structures
  Vec3 joint_reaction{Vec3::Zero()};   ///< force the femur exerts on the lower leg at the hinge, N
  SelfContactReport knee_contact;      ///< skin against skin behind the knee
  std::vector<ObstacleContact> obstacles;
  Controls controls;  ///< the tissue's controls (a buffer reused every step)
};

/// Compiles the leg. Throws msd::Error if a bone has no tets or bone points,
/// a tendon's strand is degenerate, or a material is unphysical.
LegModel build_leg_model(const LimbMesh& mesh, const std::vector<TendonStrands>& tendons,
                         const LegModelOptions& options);

/// The rest state with the knee at `angle` (rad): lower-bone nodes placed
/// rigidly, free tissue turned with them by w(s) angle, s = (X - c) . leg axis
/// its height over the knee's centre, w = 1 below -h, 0 above +h, linear
/// between (h = `blend`, m) - the flesh around the knee shares the bend.
LegState leg_rest_state(const LegModel& model, double angle, double blend = 0.0245);

/// Carries the whole leg rigidly into the femur's placement `femur` (from the
/// rest pose at rest): x -> R x + d, v -> R v + the femur's velocity at the
/// new x; state.femur = femur. A scripted hip's first pose.
void place_leg_on_femur(LegState& state, const RigidMotion& femur);

/// One step of dt: msd::step on the tissue model with `integrator`. Throws
/// SimulationFailure (when, where) on a non-finite value.
void step_leg(const LegModel& model, LegState& state, const LegControls& controls, double dt, LegScratch& scratch,
              Integrator integrator = Integrator::SymplecticEuler);

/// The strand's points (3 x m) at positions x with the knee at `angle` and the
/// femur placed by `femur` (LegState::femur): its nodes, then its anchor
/// where it has one.
Points leg_strand_points(const LegModel& model, const LegStrand& strand, const Points& x, double angle,
                         const RigidMotion& femur = {});

/// The same into p (resized to 3 x m only when its size differs).
void leg_strand_points(const LegModel& model, const LegStrand& strand, const Points& x, double angle, Points& p,
                       const RigidMotion& femur = {});

/// Length of the strand's polyline - its nodes, then its anchor - at x with
/// the knee at `angle` and the femur placed by `femur` (m).
double leg_strand_length(const LegModel& model, const LegStrand& strand, const Points& x, double angle,
                         const RigidMotion& femur = {});

/// The strand's elastic energy at x with the knee at `angle` for a natural
/// length L0 (J; tendon_energy_at_length of leg_strand_length, with the model's toe).
double leg_strand_energy(const LegModel& model, const LegStrand& strand, const Points& x, double angle,
                         double natural_length, const RigidMotion& femur = {});

/// The passive joint torque at a hinge state (N m).
double passive_joint_torque(const LegModel& model, const HingeState& knee);

/// Kinetic energy of the free tissue nodes and of the lower leg (J).
double leg_kinetic_energy(const LegModel& model, const LegState& state);

}  // namespace msd
