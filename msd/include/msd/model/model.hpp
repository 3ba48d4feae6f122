// The model / state / scratch split (design notes): a Model is everything fixed
// once a scene is compiled - rest positions, lumped masses, per-element rest data
// and constants, which force terms are on, kinematic node groups. A State is what
// changes every step. Scratch holds buffers reused between steps.
#pragma once

#include "msd/contact/rigid_obstacle.hpp"
#include "msd/contact/self_contact.hpp"
#include "msd/core/types.hpp"
#include "msd/forces/bulk_volume.hpp"
#include "msd/forces/muscle_units.hpp"
#include "msd/forces/skin_membrane.hpp"
#include "msd/forces/stable_neo_hookean.hpp"
#include "msd/material/tissue_material.hpp"
#include "msd/mesh/tet_mesh.hpp"
#include "msd/skeleton/hinge.hpp"
#include "msd/skeleton/rigid_motion.hpp"
#include "msd/skeleton/rigid_body.hpp"

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace msd {

/// Newton's method inside the implicit integrator (msd/integrate/implicit.hpp):
/// a step has converged when the largest residual component is at most
/// `tolerance` times the largest term in the balance (momentum, internal and
/// external impulse); a step that has not after `max_iterations` is retried
/// as two half steps, at most `max_step_cuts` times over, then fails.
///
/// With `reuse_factorization` (modified Newton) an iteration first tries the
/// factorisation of an earlier Jacobian - from an earlier iterate or step of
/// the same dt - and keeps that chord step when it at least halves |G|;
/// otherwise it factorises the Jacobian at the iterate (full Newton with a
/// line search). The converged steps meet the same tolerance either way.
///
/// `linear_solver` picks the factorisation of Newton's matrix
/// A = M - h D - h^2 K: `sparse_lu` factorises A itself (Eigen's SparseLU,
/// COLAMD ordering), exact Newton; `symmetric_ldlt` factorises its symmetric
/// part (A + A^T)/2 (Eigen's SimplicialLDLT, AMD ordering), an approximate
/// Newton whose convergence rate is set by A's asymmetry (the dampers'
/// position derivatives and the non-conservative volume term), at a fraction
/// of the cost (docs/msd-model.md section 5).
///
/// With `anderson_depth` m > 0 the chord steps are Anderson-accelerated
/// (Anderson 1965; Walker & Ni 2011): each mixes in the last m chord steps of
/// the same solve, the mix that minimises |G| were G linear, and is kept on
/// the same test as a plain one. It only changes the path to the tolerance;
/// the converged steps meet the same tolerance (msd/src/integrate/implicit.cpp,
/// anderson_step; measured in benchmarks/README.md).
///
/// With `keep_orientation` every iterate Newton accepts keeps every tet's
/// orientation (signed volume > 0): a first guess that inverts one is replaced
/// by the step's start positions, a chord step that does is dropped, and the
/// line search halves an update until none does. With a barrier among the
/// forces (the face repulsion with a small `repulsion_floor`) the step's
/// solution then lies inside, and no element inverts however hard it is
/// loaded; without one Newton may stall where the balance needs an inverted
/// tet. Off by default (the check costs a pass over the tets per iterate).
enum class LinearSolver { sparse_lu, symmetric_ldlt };

struct NewtonOptions {
  double tolerance = 1e-8;
  int max_iterations = 20;
  int max_step_cuts = 6;
  bool reuse_factorization = true;
  LinearSolver linear_solver = LinearSolver::sparse_lu;
  bool keep_orientation = false;
  /// Anderson acceleration of the chord steps: how many earlier chord
  /// steps of the same Newton solve are mixed into the next (0: plain chord
  /// steps; at most 8). See the comment above NewtonOptions.
  int anderson_depth = 0;
};

/// "sparse_lu" / "symmetric_ldlt"; parse_linear_solver throws msd::Error naming the choices.
const char* to_string(LinearSolver s);
LinearSolver parse_linear_solver(const std::string& name);

/// Force terms; a model evaluates only those it was built with.
enum ForceTerm : unsigned {
  kSprings = 1u << 0,    ///< edge springs, k_s (5.1.2)
  kDampers = 1u << 1,    ///< edge dampers, k_d (5.1.2)
  kRepulsion = 1u << 2,  ///< face repulsion + equalisation, k_r (eq. 5.1-5.4)
  kVolume = 1u << 3,     ///< volume preservation + equalisation, k_v (eq. 5.5)
  kGravity = 1u << 4,    ///< uniform gravity on every node
  /// The stable neo-Hookean continuum element on every tet
  /// (msd/forces/stable_neo_hookean.hpp): not a thesis term - the model
  /// ladder's continuum rung, from the material's E and Poisson's ratio.
  kNeoHookean = 1u << 5,
  /// The lattice's bulk term, one volume ratio per volume group (a cube)
  /// (msd/forces/bulk_volume.hpp): not a thesis term - the non-locking volume
  /// term of the calibrated lattice, K from E and Poisson's ratio.
  kBulk = 1u << 6,
};

/// Parses "springs", "dampers", "repulsion", "volume", "gravity", "neo_hookean", "bulk".
ForceTerm parse_force_term(const std::string& name);
std::string force_terms_to_string(unsigned terms);

/// Rest data and constants of one tetrahedral element.
struct Element {
  Tet nodes;
  int region = 0;
  double rest_volume = 0.0;
  double rest_length[6];   ///< kTetEdges order
  /// kTetEdges order: each edge's class (msd/forces/spring_law.hpp), from its rest vector.
  EdgeClass edge_class[6] = {EdgeClass::axis, EdgeClass::axis, EdgeClass::axis,
                             EdgeClass::axis, EdgeClass::axis, EdgeClass::axis};
  double rest_height[4];   ///< vertex i over the plane of its opposite face
  double floor = 0.01;     ///< repulsion tangent continuation (fraction of x0)
  ElementConstants k;
};

/// The continuum element's rest data per tet (msd/forces/stable_neo_hookean.hpp;
/// kNeoHookean only, else empty: the thesis' element data stays as compact as
/// before): D_m^-1 and the energy's constants, T entries each.
struct ContinuumElements {
  std::vector<Mat3> dm_inv;
  std::vector<SnhConstants> constants;
};

/// The element terms laid out for the fast force evaluation
/// (msd/forces/force_engine.hpp), built once by build_model.
///  - Unique edges as structure-of-arrays, E entries each: end nodes a, b;
///    rest length; k_s and k_d summed over the tets that share the edge (an
///    edge of the five-tet lattice is in up to six tets, so each edge's
///    spring and damper is evaluated once instead of once per tet side).
///  - The spring law's exponents per edge (msd/forces/spring_law.hpp), E
///    each - empty when every edge has the thesis' linear law, which then
///    runs its own code path.
///  - The gather tables (CSR, N + 1 offsets): for node n, the edges touching it
///    as 2 e + (n == b[e]) and the tet corners it is, as 4 t + c, both in
///    increasing order, so every node's force is summed in a fixed order
///    whatever the thread count.
struct ForcePlan {
  std::vector<int> edge_a, edge_b;           ///< E
  std::vector<double> edge_rest, edge_k_s, edge_k_d;  ///< E
  std::vector<double> edge_law_m, edge_law_n;         ///< E, or empty: linear
  std::vector<int> node_edge_offset, node_edge;        ///< N + 1, 2 E
  std::vector<int> node_corner_offset, node_corner;    ///< N + 1, 4 T
  int num_edges() const { return static_cast<int>(edge_a.size()); }
};

/// The volume groups (mean dilatation) of the continuum element
/// (msd/forces/stable_neo_hookean.hpp) or of the lattice's bulk term
/// (msd/forces/bulk_volume.hpp, which needs them): group g's tets are
/// tets[tet_offset[g] .. tet_offset[g+1]), its distinct nodes
/// nodes[node_offset[g] .. node_offset[g+1]) and corner_slot[4 t + i] is the
/// place of tet t's corner i in its group's node list. Empty: every tet is
/// its own group (the per-tet element).
struct VolumeGroups {
  std::vector<int> tet_offset, tets;    ///< G + 1, T
  std::vector<int> node_offset, nodes;  ///< G + 1, sum of group sizes
  std::vector<int> of_tet;              ///< T: the group of each tet
  std::vector<int> corner_slot;         ///< 4 T
  std::vector<double> rest_volume;      ///< G, m^3
  std::vector<BulkLaw> bulk_law;        ///< G: the bulk term's volume law (kBulk), else empty
  int size() const { return static_cast<int>(rest_volume.size()); }
  bool empty() const { return rest_volume.empty(); }
};

/// Nodes whose motion is prescribed: for each prescribed axis, position =
/// rest position + offset(t) and velocity = velocity(t), both from Controls.
/// (A bonded platen prescribes all three axes; a frictionless one only its
/// normal axis.) Or, with a rigid motion in Controls::group_motion (all
/// three axes prescribed), x = R X + d, v = omega x (R X) + d' (a bone that
/// turns, msd/skeleton/rigid_motion.hpp).
/// A group driven by a joint (Model::joints) turns rigidly with it instead:
/// x = c + R(theta) (X - c), v = omega n x (x - c) (msd/skeleton/hinge.hpp).
struct KinematicGroup {
  std::string name;
  std::vector<int> nodes;
  bool axes[3] = {true, true, true};
  int joint = -1;  ///< the joint driving it (set by check_model_parts), or -1
};

/// A tendon strand (msd/forces/tendon.hpp, thesis 5.3): a tension-only cable
/// through `nodes`, then - when `anchor_group` >= 0 - through a point fixed on
/// that kinematic group (its insertion on a bone), at `anchor_rest` when the
/// group is at rest. The anchor moves with its group (turned by its joint, or
/// translated with its first node).
struct Strand {
  std::vector<int> nodes;
  double natural_length = 0.0;  ///< m (Controls::strand_natural_length overrides)
  double k_t = 0.0;             ///< E A / L0, N/m (the linear modulus's)
  int anchor_group = -1;
  Vec3 anchor_rest{Vec3::Zero()};
  double toe_strain = 0.0;      ///< the toe region's end (tendon.hpp); 0: linear from slack
};

/// A muscle's contractile units (msd/forces/muscle_units.hpp, thesis 5.2.7):
/// each pulls with activation * unit_force (times f_L of its stretch when
/// `force_length` is enabled), or - with `hill` enabled - with the Hill-type
/// law's tension (active, force-velocity and passive); the activation comes
/// from Controls.
struct Muscle {
  std::string name;
  std::vector<ContractileUnit> units;
  double unit_force = 0.0;  ///< N per unit at activation 1 (F_max's share)
  ForceLength force_length;
  HillMuscle hill;
};

/// A hinge joint (thesis 5.4) turning one kinematic group - a rigid bone and
/// the nodes attached to it - about a fixed axis. Its torque is everything
/// acting on the group's nodes (their internal forces, weight), the strands
/// anchored on it, the body's own weight, an added torque from Controls and
/// the joint's passive structures: -damping omega, and -limit_stiffness
/// (theta - passive_hi) above passive_hi (likewise below passive_lo). The
/// joint is stepped by semi-implicit Euler with the torque at the start of
/// the step, whatever the nodes' integrator (a partitioned scheme: the
/// implicit integrator solves the tissue with the group at its new angle).
///
/// The hinge may sit on a moving bone: with `parent` >= 0 and a rigid motion
/// of that group in Controls::group_motion, the centre and axis are fixed in
/// the parent (x = R_p (c + R(theta)(X - c)) + d_p) and theta is the angle
/// relative to it. Its equation is then taken in the parent's accelerating,
/// turning frame (about the moving centre c_w, axis n_w = R_p n):
///
///   I_n theta'' = tau_n - n_w . (I_c alpha_p) - n_w . (omega_p x I_c omega_p)
///                 - n_w . (S_c x a_c),
///
/// I_c the body's inertia tensor about c_w (its own and its nodes' masses),
/// S_c = sum m (x - c_w) its first moment, a_c the centre's acceleration
/// (RigidMotion::acceleration_at); the Coriolis terms cancel about the axis.
/// (From dH_c/dt = tau_c - S_c x a_c with H_c = I_c Omega, Omega = omega_p +
/// theta' n_w.) Without a motion of the parent the hinge stays where it is.
struct Joint {
  std::string name;
  int group = -1;
  int parent = -1;      ///< the group carrying the hinge (-1: fixed in space)
  Hinge hinge;          ///< centre, unit axis, range, inertia (of body and group nodes)
  MassProperties body;  ///< the rigid body's own mass beside its nodes' (0: none)
  double damping = 0.0, limit_stiffness = 0.0, passive_lo = 0.0, passive_hi = 0.0;
};

struct Model {
  Points rest_positions;          ///< 3 x N
  Eigen::VectorXd mass;           ///< N, kg
  Eigen::VectorXd inv_mass;       ///< N, 1/kg
  std::vector<Element> elements;
  unsigned terms = 0;
  /// Repulsion and volume terms act only in elements where some vertex height
  /// has dropped below this fraction of its rest value (thesis 5.8 used 0.7);
  /// 0 means always on (the thesis' own material tests).
  double nonlinear_threshold = 0.0;
  Vec3 gravity{Vec3::Zero()};
  /// Dead external loads per node (3 x N, N), e.g. a traction spread over a
  /// face; scaled by Controls::load_scale. Empty: none.
  Points external_force;
  std::vector<KinematicGroup> groups;
  /// Rigid objects the surface nodes cannot enter (thesis 5.6), each with the
  /// nodes it is tested against (none in a kinematic group). Empty: no
  /// collision work at all.
  std::vector<RigidObstacle> obstacles;
  std::vector<TissueMaterial> region_materials;  ///< by region label
  /// The moving parts besides the tissue (the leg's, thesis 5.3-5.6): tendon
  /// strands, muscles, joints and skin-against-skin contact (its tets are
  /// the model's elements; kinematic nodes are never moved by it). Set after
  /// build_model, then checked by check_model_parts.
  std::vector<Strand> strands;
  std::vector<Muscle> muscles;
  std::vector<Joint> joints;
  /// The skin, a membrane on the limb's outer surface triangles
  /// (msd/forces/skin_membrane.hpp); empty: none.
  SkinMembrane skin;
  std::optional<SelfContactRegion> self_contact;
  std::vector<Tet> contact_tets;      ///< the elements' nodes (for self_contact)
  std::vector<char> kinematic;        ///< per node: in a kinematic group (for self_contact)
  ForcePlan plan;   ///< the fast evaluation's layout (build_model)
  ContinuumElements continuum;  ///< the continuum element's rest data (kNeoHookean)
  VolumeGroups volume_groups;  ///< the continuum element's or the bulk term's (ModelOptions::volume_group)
  int threads = 1;  ///< threads of the force evaluation (results do not depend on it)
  /// Evaluate with the per-tet reference loop instead of the engine (the path
  /// the engine replaced: for verification and side-by-side timing).
  bool reference_forces = false;
  NewtonOptions newton;  ///< the implicit integrator's Newton iterations

  int num_nodes() const { return static_cast<int>(rest_positions.cols()); }
  int num_elements() const { return static_cast<int>(elements.size()); }
};

struct ModelOptions {
  unsigned terms = kSprings | kDampers | kRepulsion | kVolume;
  double nonlinear_threshold = 0.0;
  Vec3 gravity{Vec3::Zero()};
  /// Material of each region label (index = label); every label used by the
  /// mesh needs one.
  std::vector<TissueMaterial> region_materials;
  std::vector<KinematicGroup> groups;
  /// Rigid obstacles; an obstacle given without nodes is tested against every
  /// surface node of the mesh that is in no kinematic group.
  std::vector<RigidObstacle> obstacles;
  Points external_force;  ///< optional, 3 x N
  /// Threads of the force evaluation, >= 1; the forces are bit-identical for
  /// every count (msd/forces/force_engine.hpp).
  int threads = 1;
  bool reference_forces = false;  ///< see Model::reference_forces
  NewtonOptions newton;           ///< see Model::newton
  /// With kNeoHookean or kBulk: a group label per tet (e.g. its cube of the
  /// lattice, GridMeshInfo::tet_cube_id); tets with one label share one
  /// volume ratio (mean dilatation) and must share a region. Empty: per tet
  /// (the continuum element; the bulk term needs groups).
  std::vector<long> volume_group;
};

/// Compiles a model: checks the mesh and materials, computes rest data and
/// per-element constants, lumps masses. Throws msd::Error with context.
Model build_model(const TetMesh& mesh, const ModelOptions& options);

/// Checks the model's strands, muscles, joints and self-contact (nodes and
/// groups in range, positive lengths and stiffnesses, a joint per group at
/// most, joints only on groups prescribing all three axes) and links each
/// driven group to its joint. Call after setting them. Throws msd::Error
/// naming the part.
void check_model_parts(Model& model);

/// Mutable simulation state.
struct State {
  Points x;            ///< positions, 3 x N
  Points v;            ///< velocities, 3 x N
  double t = 0.0;      ///< time, s
  long step = 0;       ///< steps taken
  Points a;            ///< last acceleration (velocity Verlet's memory)
  bool a_valid = false;
  /// BDF2's memory: positions and velocities one step back and that step's
  /// length (s); dt_prev = 0: none (the next BDF2 step is backward Euler).
  Points x_prev, v_prev;
  double dt_prev = 0.0;
  std::vector<HingeState> joints;  ///< per Model::joints
};

/// The rest state: x = rest positions, v = 0, t = 0.
State rest_state(const Model& model);

/// Prescribed motion of each kinematic group at the time being integrated to,
/// and the factor on the dead loads (external forces and gravity).
struct Controls {
  std::vector<Vec3> group_offset;
  std::vector<Vec3> group_velocity;
  /// Per group (empty or unset: none): a rigid motion placing the group
  /// instead of its offset and velocity, and carrying the joints whose parent
  /// it is (Joint::parent). Only for a group that prescribes all three axes
  /// and has no joint (step refuses others).
  std::vector<std::optional<RigidMotion>> group_motion{};
  /// Rigid motion (translation) of each obstacle from its rest placement, and
  /// its velocity; empty: obstacles at rest.
  std::vector<Vec3> obstacle_offset{};
  std::vector<Vec3> obstacle_velocity{};
  double load_scale = 1.0;
  /// Per muscle, 0 ... 1; empty: all relaxed.
  std::vector<double> activation{};
  /// Per strand, natural lengths replacing the model's (infinity: slack);
  /// empty: the model's.
  std::vector<double> strand_natural_length{};
  /// Per joint: a torque added about its axis (N m; empty: none) and a
  /// kinematic override of its angle and velocity (empty or unset: dynamic).
  std::vector<double> joint_torque{};
  std::vector<std::optional<HingeState>> scripted_joint{};
};

/// What a joint did in the last step.
struct JointReport {
  double torque = 0.0;          ///< about the axis, N m (all of it; on a moving parent with its frame's terms)
  double passive_torque = 0.0;  ///< of it, the joint's passive structures
  Vec3 reaction{Vec3::Zero()};  ///< force the fixed side exerts on the turning body at the joint, N
};

struct ImplicitWorkspace;  // msd/integrate/implicit.hpp
struct StrandSolveWorkspace;  // msd/integrate/imex_strands.hpp

/// Reused buffers and per-evaluation diagnostics.
struct Scratch {
  Points f;                        ///< internal force per node (no gravity)
  long nonlinear_active = 0;       ///< elements whose non-linear terms ran
  Points edge_force;               ///< 3 x E: force on each edge's node a (b gets minus)
  Points corner_force;             ///< 3 x 4T: non-linear force on each tet corner
  Points skin_corner_force;        ///< 3 x 3T: the skin membrane's force on each triangle corner
  std::vector<double> group_pressure;  ///< per volume group: lambda (Jbar - alpha), Pa
  /// The implicit integrator's matrix, factorisation and vectors (made on its
  /// first step, then reused).
  std::shared_ptr<ImplicitWorkspace> implicit;
  /// The IMEX step's strand systems (made on its first step, then reused).
  std::shared_ptr<StrandSolveWorkspace> strand_solve;
  long newton_iterations = 0;      ///< Newton iterations of the implicit steps so far
  int last_newton_iterations = 0;  ///< of the last implicit step
  int last_step_cuts = 0;          ///< times the last implicit step was halved
  long step_cuts = 0;              ///< halvings of the implicit steps so far
  long factorizations = 0;         ///< LU factorisations of the implicit steps so far
  // The moving parts (Model::strands ... self_contact), per evaluation / step:
  std::vector<double> strand_tension;  ///< per strand, N (>= 0)
  std::vector<double> strand_strain;   ///< per strand, (L - L0) / L0 when taut, else 0
  std::vector<Vec3> anchor_force;      ///< per strand: the force on its anchor, N (zero without one)
  std::vector<JointReport> joints;     ///< per joint
  SelfContactReport self_contact;      ///< skin against skin
  SelfContactWorkspace contact_buffers;  ///< its buffers
  std::vector<ObstacleContact> obstacles;  ///< per obstacle
  std::vector<HingeState> joints_before;   ///< the joints at the step's start (buffer)
  Points strand_points, strand_forces;     ///< an anchored strand's points and forces (buffers)
  std::vector<int> strand_index;           ///< 0 ... m-1 (buffer)
  Controls start_controls;                 ///< the controls at a step's start (controls_before; buffer)
};

}  // namespace msd
