#include "msd/scene/leg_model.hpp"

#include "msd/forces/muscle_units.hpp"
#include "msd/forces/tendon.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace msd {

namespace {

// Which bone holds each node (1 femur, 2 lower bone, 0 free): its tets' nodes
// and its bone points; the femur's and the lower bone's node lists.
void attach_bone_nodes(const LimbMesh& m, LegModel& leg) {
  const int n = m.mesh.num_nodes();
  leg.attached.assign(static_cast<size_t>(n), 0);
  for (size_t e = 0; e < m.mesh.tets.size(); ++e)
    for (int v : m.mesh.tets[e]) {
      if (m.mesh.region[e] == kUpperBone) leg.attached[static_cast<size_t>(v)] = 1;
      if (m.mesh.region[e] == kLowerBone) leg.attached[static_cast<size_t>(v)] = 2;
    }
  for (const auto& [node, region] : m.bone_points) leg.attached[static_cast<size_t>(node)] = region == kUpperBone ? 1 : 2;
  for (int i = 0; i < n; ++i) {
    if (leg.attached[static_cast<size_t>(i)] == 1) leg.femur_nodes.push_back(i);
    if (leg.attached[static_cast<size_t>(i)] == 2) leg.lower_nodes.push_back(i);
  }
}

// The tissue's tets without the joint space: a tet with nodes on both bones
// would be crushed by any rotation of one about the other (the cubic mesh
// leaves a single cube of passive tissue between condyles and plateau), so it
// is left out - no tissue joins the two bones directly. Counts the tets left
// out in leg.joint_space_tets. `cubes` gets each kept tet's grid cube (empty
// when the mesh carries none).
TetMesh tissue_without_joint_space(const LimbMesh& m, const LegModelOptions& o, LegModel& leg,
                                   std::vector<long>& cubes) {
  const bool has_cubes = m.tet_cube.size() == m.mesh.tets.size();
  cubes.clear();
  const int n = m.mesh.num_nodes();
  TetMesh tissue_mesh = m.mesh;
  tissue_mesh.tets.clear();
  tissue_mesh.region.clear();
  auto keep = [&](size_t e) {  // tet e of m stays, with its region and cube
    tissue_mesh.tets.push_back(m.mesh.tets[e]);
    tissue_mesh.region.push_back(m.mesh.region[e]);
    if (has_cubes) cubes.push_back(m.tet_cube[e]);
  };
  std::vector<unsigned> near_bone(static_cast<size_t>(n), 0);  // bones a node shares a tet with
  for (const Tet& t : m.mesh.tets) {
    unsigned b = 0;
    for (int v : t) b |= leg.attached[static_cast<size_t>(v)];
    for (int v : t) near_bone[static_cast<size_t>(v)] |= b;
  }
  const Vec3 axis = o.knee_axis.normalized();
  std::vector<size_t> squeezed_tets;
  for (size_t e = 0; e < m.mesh.tets.size(); ++e) {
    unsigned bones = 0, near = 0;
    Vec3 c = Vec3::Zero();
    for (int v : m.mesh.tets[e]) {
      bones |= leg.attached[static_cast<size_t>(v)];
      near |= near_bone[static_cast<size_t>(v)];
      c += 0.25 * m.mesh.nodes.col(v);
    }
    const Vec3 r = c - o.knee_centre;
    const bool bone_tet = m.mesh.region[e] == kUpperBone || m.mesh.region[e] == kLowerBone;
    const bool squeezed = o.joint_space_radius > 0.0 && !bone_tet && bones != 0u && near == 3u &&
                          (r - r.dot(axis) * axis).norm() < o.joint_space_radius;
    if (bones == 3u) {
      ++leg.joint_space_tets;
      continue;
    }
    if (squeezed) {
      squeezed_tets.push_back(e);
      continue;
    }
    keep(e);
  }
  // A squeezed tet stays if leaving it out would leave a node in no tet.
  std::vector<int> uses(static_cast<size_t>(n), 0);
  for (const Tet& t : tissue_mesh.tets)
    for (int v : t) ++uses[static_cast<size_t>(v)];
  for (size_t e : squeezed_tets) {
    const Tet& t = m.mesh.tets[e];
    if (std::any_of(t.begin(), t.end(), [&](int v) { return uses[static_cast<size_t>(v)] == 0; })) {
      keep(e);
      for (int v : t) ++uses[static_cast<size_t>(v)];
    } else {
      ++leg.joint_space_tets;
    }
  }
  return tissue_mesh;
}

// The tissue model of the leg's tets: the scene's force terms, one material
// per region label. With the continuum element (kNeoHookean), one volume
// ratio per cube of the mesh's grid (mean dilatation,
// msd/forces/stable_neo_hookean.hpp): five tets per cube each holding its own
// volume would lock a nearly incompressible tissue (five constraints per
// cube against three freedoms per node).
Model tissue_model(const TetMesh& tissue_mesh, const std::vector<long>& cubes, const LegModelOptions& o) {
  ModelOptions mo;
  mo.terms = o.terms;
  mo.nonlinear_threshold = o.nonlinear_threshold;
  mo.threads = o.threads;
  mo.reference_forces = o.reference_forces;
  mo.newton = o.newton;
  mo.gravity = o.gravity;
  // Region labels 0..4: passive, front and back muscle, the bones (their tets
  // move rigidly; any material will do, passive tissue's is used).
  mo.region_materials = {o.passive, o.muscle, o.muscle, o.passive, o.passive};
  if (o.terms & kNeoHookean) {
    if (cubes.size() != tissue_mesh.tets.size())
      throw Error("leg: the continuum element needs the mesh's grid cube of every tet (LimbMesh::tet_cube), one "
                  "volume ratio per cube; this mesh has none (one per tet would lock the nearly incompressible tissue)");
    mo.volume_group = cubes;
  }
  return build_model(tissue_mesh, mo);
}

// The knee hinge and the lower bone (thesis 5.4): the bone's mass properties
// and the hinge's moment of inertia, I = the bone's moment about the axis +
// sum of the lower-bone nodes' m r^2.
void build_knee(const LimbMesh& m, const LegModelOptions& o, LegModel& leg) {
  if (leg.femur_nodes.empty()) throw Error("leg: the upper bone has no tets or bone points in the mesh");
  if (leg.lower_nodes.empty()) throw Error("leg: the lower bone has no tets or bone points in the mesh");

  leg.knee.centre = o.knee_centre;
  leg.knee.axis = o.knee_axis.normalized();
  leg.knee.min_angle = o.min_flexion;
  leg.knee.max_angle = o.max_flexion;
  const bool has_lower_tets = std::count(m.mesh.region.begin(), m.mesh.region.end(), kLowerBone) > 0;
  double inertia = 0.0;
  if (has_lower_tets) {
    leg.lower_bone = region_mass_properties(m.mesh, kLowerBone, o.bone_density);
    inertia = moment_about_axis(leg.lower_bone, leg.knee.centre, leg.knee.axis);
  }
  for (int i : leg.lower_nodes) {
    const Vec3 r = leg.tissue.rest_positions.col(i) - leg.knee.centre;
    inertia += leg.tissue.mass[i] * (r - r.dot(leg.knee.axis) * leg.knee.axis).squaredNorm();
  }
  leg.knee.inertia = inertia;
  check_hinge(leg.knee);
}

// An aponeurosis (LegModelOptions::tendons_at_fibre_ends): tendon t's strands
// from every fibre end of its muscle on its side - the side its patch (the
// first strand's muscle node) lies on, from the muscle's middle along its line
// of action - to its bone end (the one bone node route_tendon gives all of a
// tendon's strands). Fibre ends on a bone are left out. Needs the muscles'
// units (build_muscles).
std::vector<std::vector<int>> fibre_end_strands(const TendonStrands& t, const std::vector<TendonStrands>& tendons,
                                                const LegModelOptions& o, const LegModel& leg) {
  const bool front = t.muscle == kFrontMuscle;
  if (!front && t.muscle != kBackMuscle) throw Error("leg: tendon '" + t.name + "' does not leave a muscle");
  const std::vector<ContractileUnit>& units = front ? leg.front_units : leg.back_units;
  const Vec3 d = (front ? o.front_line : o.back_line).normalized();
  const Points& x = leg.tissue.rest_positions;
  if (units.empty() || t.strands.empty()) throw Error("leg: tendon '" + t.name + "': its muscle has no units to attach to");
  double middle = 0.0;
  for (const ContractileUnit& u : units) middle += 0.5 * (x.col(u.a) + x.col(u.b)).dot(d);
  middle /= static_cast<double>(units.size());
  auto side_of = [&](const TendonStrands& other) { return x.col(other.strands.front().front()).dot(d) > middle ? 1 : -1; };
  const int side = side_of(t);
  for (const TendonStrands& other : tendons)
    if (&other != &t && other.muscle == t.muscle && !other.strands.empty() && side_of(other) == side)
      throw Error("leg: tendons '" + t.name + "' and '" + other.name +
                  "' leave the same end of their muscle, so the fibre ends cannot be shared between them");
  std::vector<std::vector<int>> strands;
  const int bone_end = t.strands.front().back();
  for (int v : fibre_end_nodes(x, units, d, side))
    if (!leg.attached[static_cast<size_t>(v)]) strands.push_back({v, bone_end});
  if (strands.empty()) throw Error("leg: tendon '" + t.name + "': its muscle has no free fibre end on its side");
  return strands;
}

// The tendons' strands (thesis 5.3): through the route's tissue nodes or
// direct, bone ends anchored at the insertions where given, natural lengths
// at rest with the knee at each muscle's optimal-length angle, stiffness from
// each tendon's modulus.
void build_strands(const std::vector<TendonStrands>& tendons, const LegModelOptions& o, LegModel& leg) {
  if (!o.tendon_insertions.empty() && o.tendon_insertions.size() != tendons.size())
    throw Error("leg: " + std::to_string(o.tendon_insertions.size()) + " tendon insertions for " +
                std::to_string(tendons.size()) + " tendons");
  for (const auto& modulus : o.tendon_moduli) {
    const std::string& name = modulus.first;  // (C++17 lambdas cannot capture a structured binding: clang refuses)
    if (std::none_of(tendons.begin(), tendons.end(), [&](const TendonStrands& t) { return t.name == name; }))
      throw Error("leg: a modulus is given for tendon '" + name + "', which the leg does not have");
  }
  for (const double a : {o.front_optimal_angle, o.back_optimal_angle})
    if (!(a >= o.min_flexion && a <= o.max_flexion))
      throw Error("leg: a muscle's optimal-length knee angle (" + std::to_string(a * 180.0 / M_PI) +
                  " deg) lies outside the knee's flexion range");
  if (o.tendons_at_fibre_ends && !o.tendons_direct)
    throw Error("leg: tendons attached at the fibre ends need the direct route (a strand from every fibre end cannot "
                "run through the path's tissue nodes)");
  for (const TendonStrands& t : tendons) {
    leg.tendon_names.push_back(t.name);
    const size_t ti = leg.tendon_names.size() - 1;
    const std::vector<std::vector<int>> strands = o.tendons_at_fibre_ends ? fibre_end_strands(t, tendons, o, leg) : t.strands;
    // Natural lengths with the knee where the tendon's muscle is at its mesh length.
    const double taut_angle =
        t.muscle == kFrontMuscle ? o.front_optimal_angle : t.muscle == kBackMuscle ? o.back_optimal_angle : 0.0;
    // The route's strands share its section (patch strands x strand_area): for the patch itself the ratio is 1.
    const double area =
        o.strand_area * (static_cast<double>(t.strands.size()) / static_cast<double>(strands.size()));
    const bool inserted = ti < o.tendon_insertions.size() && o.tendon_insertions[ti];
    // Only an anchored strand's insertion turns with the angle (leg_strand_length): a
    // strand through flesh nodes or to a bone node would keep the straight knee's length.
    if (taut_angle != 0.0 && !(o.tendons_direct && inserted))
      throw Error("leg: tendon '" + t.name + "': a muscle's optimal-length knee angle needs the direct route and "
                  "the insertion at the path's end");
    for (const auto& s : strands) {
      LegStrand ls;
      ls.nodes = s;
      if (o.tendons_direct && s.size() > 2) ls.nodes = {s.front(), s.back()};
      ls.tendon = static_cast<int>(ti);
      if (inserted) {
        const int bone = leg.attached[static_cast<size_t>(s.back())];
        if (!bone) throw Error("leg: tendon '" + t.name + "' does not end on a bone node, so it cannot take an insertion");
        if (ls.nodes.size() < 2) throw Error("leg: tendon '" + t.name + "' has a strand of one node");
        ls.nodes.pop_back();
        ls.anchored = true;
        ls.anchor_bone = bone;
        ls.anchor_rest = *o.tendon_insertions[ti];
      }
      ls.natural_length = leg_strand_length(leg, ls, leg.tissue.rest_positions, taut_angle);
      if (!(ls.natural_length > 0.0)) throw Error("leg: tendon '" + t.name + "' has a strand of zero length");
      const auto mod = o.tendon_moduli.find(t.name);
      ls.k_t = tendon_stiffness(mod != o.tendon_moduli.end() ? mod->second : o.tendon_modulus, area,
                                ls.natural_length);
      leg.strands.push_back(ls);
    }
  }
}

// The skin: the limb's outer boundary faces (the joint space's hole has
// boundary faces too, inside the knee, that no skin touches). Empty when no
// contact and no skin membrane needs it.
std::vector<Tri> skin_faces(const LimbMesh& m, const TetMesh& tissue_mesh, const LegModelOptions& o) {
  std::vector<Tri> faces;
  if (o.knee_contact_box || !o.obstacles.empty() || o.skin) {
    auto key = [](Tri f) {
      std::sort(f.begin(), f.end());
      return f;
    };
    std::set<Tri> outer;
    for (const Tri& f : boundary_faces(m.mesh.tets)) outer.insert(key(f));
    for (const Tri& f : boundary_faces(tissue_mesh.tets))
      if (outer.count(key(f))) faces.push_back(f);
  }
  return faces;
}

// The skin membrane's faces: the outer faces but those lying in the limb's two
// end planes across its axis - the cut at the hip and the one at the bottom,
// where real skin does not close the limb but continues into the body and foot.
std::vector<Tri> membrane_faces(const std::vector<Tri>& skin, const Points& rest, const Vec3& axis) {
  const Vec3 a = axis.normalized();
  const Eigen::VectorXd h = rest.transpose() * a;
  const double lo = h.minCoeff(), hi = h.maxCoeff(), tol = 1e-6 * (hi - lo);
  std::vector<Tri> faces;
  for (const Tri& f : skin) {
    bool top = true, bottom = true;
    for (int v : f) {
      top = top && h[v] > hi - tol;
      bottom = bottom && h[v] < lo + tol;
    }
    if (!top && !bottom) faces.push_back(f);
  }
  return faces;
}

// Skin against skin behind the knee (thesis 5.6): the region in the scene's
// box and its largest correction.
void build_knee_contact(const LimbMesh& m, const TetMesh& tissue_mesh, const std::vector<Tri>& skin,
                        const LegModelOptions& o, LegModel& leg) {
  if (o.knee_contact_box)
    leg.knee_contact = make_self_contact_region(tissue_mesh, "behind the knee", o.knee_contact_box->first,
                                                o.knee_contact_box->second, o.knee_centre, o.leg_axis, skin);
  if (leg.knee_contact) {
    // Half the mean edge of the region's tets: skin passes skin by less than
    // that in one step; anything deeper is a node caught across the split.
    double sum = 0.0;
    long count = 0;
    for (int side = 0; side < 2; ++side)
      for (int e : leg.knee_contact->tets[side])
        for (const auto& edge : kTetEdges) {
          const Tet& t = tissue_mesh.tets[static_cast<size_t>(e)];
          sum += (m.mesh.nodes.col(t[static_cast<size_t>(edge[0])]) - m.mesh.nodes.col(t[static_cast<size_t>(edge[1])])).norm();
          ++count;
        }
    if (count) leg.knee_contact->max_correction = 0.5 * sum / static_cast<double>(count);
  }
}

// Rigid external objects (thesis 5.6, 6.3, 6.7): each with the free surface
// nodes in its box.
void build_obstacles(const LimbMesh& m, const std::vector<Tri>& skin, const LegModelOptions& o, LegModel& leg) {
  if (o.obstacles.empty()) return;
  const int n = m.mesh.num_nodes();
  std::vector<char> on_surface(static_cast<size_t>(n), 0);
  for (const Tri& t : skin)
    for (int v : t) on_surface[static_cast<size_t>(v)] = 1;
  for (size_t k = 0; k < o.obstacles.size(); ++k) {
    RigidObstacle ob = o.obstacles[k].object;
    const std::string where = "leg: obstacle '" + ob.name + "'";
    check_obstacle(ob, where);
    ob.nodes.clear();
    for (int i = 0; i < n; ++i) {
      if (!on_surface[static_cast<size_t>(i)] || leg.attached[static_cast<size_t>(i)]) continue;
      const Vec3 x = m.mesh.nodes.col(i);
      if (o.obstacles[k].box) {
        const auto& [lo, hi] = *o.obstacles[k].box;
        if ((x.array() < lo.array()).any() || (x.array() > hi.array()).any()) continue;
      }
      ob.nodes.push_back(i);
    }
    if (ob.nodes.empty()) throw Error(where + ": no free surface node of the leg lies in its box");
    leg.obstacles.push_back(ob);
  }
}

// The muscles' contractile units and their force per unit at activation 1
// (thesis 5.2.7).
void build_muscles(const LimbMesh& m, const LegModelOptions& o, LegModel& leg) {
  leg.front_units = contractile_units(m.mesh, kFrontMuscle, o.front_line, o.unit_angle_deg);
  leg.back_units = contractile_units(m.mesh, kBackMuscle, o.back_line, o.unit_angle_deg);
  auto force = [&](int region, const std::vector<ContractileUnit>& units, const Vec3& line,
                   const std::optional<double>& pcsa) {
    return pcsa ? unit_force_for_area(m.mesh, region, units, line, 1.0, o.max_muscle_stress, *pcsa)
                : unit_force(m.mesh, region, units, line, 1.0, o.max_muscle_stress);
  };
  leg.front_unit_force = force(kFrontMuscle, leg.front_units, o.front_line, o.front_pcsa);
  leg.back_unit_force = force(kBackMuscle, leg.back_units, o.back_line, o.back_pcsa);
  leg.force_length = o.force_length;
  if (o.hill.enabled) check_hill_muscle(o.hill, "leg: muscles.hill");
  leg.hill = o.hill;
  if (!(o.activation_time >= 0.0) || !(o.deactivation_time >= 0.0))
    throw Error("leg: the muscles' activation and deactivation times must be >= 0");
  leg.activation_time = o.activation_time;
  leg.deactivation_time = o.deactivation_time;
}

// The knee's passive structures: joint damping and the end-range stiffness.
void set_passive_joint(const LegModelOptions& o, LegModel& leg) {
  if (!(o.joint_damping >= 0.0) || !(o.limit_stiffness >= 0.0))
    throw Error("leg: the knee's joint damping and limit stiffness must be >= 0");
  if (!(o.passive_lo <= o.passive_hi)) throw Error("leg: the knee's passive range must have passive_lo <= passive_hi");
  leg.joint_damping = o.joint_damping;
  leg.limit_stiffness = o.limit_stiffness;
  leg.passive_lo = o.passive_lo;
  leg.passive_hi = o.passive_hi;
}

// The leg's moving parts as parts of the tissue model, so msd::step advances
// them: the femur (fixed) and the lower bone (turned by the knee) as kinematic
// groups, the knee as a joint, the strands, the muscles, the contact behind
// the knee and the obstacles.
void compile_parts(LegModel& leg) {
  Model& tm = leg.tissue;
  KinematicGroup femur, lower;
  femur.name = "femur";
  femur.nodes = leg.femur_nodes;
  lower.name = "lower bone";
  lower.nodes = leg.lower_nodes;
  tm.groups = {femur, lower};
  Joint knee;
  knee.name = "knee";
  knee.group = kLowerBoneGroup;
  knee.hinge = leg.knee;
  knee.body = leg.lower_bone;
  knee.damping = leg.joint_damping;
  knee.limit_stiffness = leg.limit_stiffness;
  knee.passive_lo = leg.passive_lo;
  knee.passive_hi = leg.passive_hi;
  knee.parent = kFemurGroup;  // a scripted hip moves the femur, and the knee with it (LegControls::femur)
  tm.joints = {knee};
  tm.strands.clear();
  for (const LegStrand& ls : leg.strands) {
    Strand s;
    s.nodes = ls.nodes;
    s.natural_length = ls.natural_length;
    s.k_t = ls.k_t;
    s.toe_strain = leg.tendon_toe_strain;
    if (ls.anchored) {
      s.anchor_group = ls.anchor_bone == 2 ? kLowerBoneGroup : kFemurGroup;
      s.anchor_rest = ls.anchor_rest;
    }
    tm.strands.push_back(s);
  }
  tm.muscles = {Muscle{"front muscle", leg.front_units, leg.front_unit_force, leg.force_length, leg.hill},
                Muscle{"back muscle", leg.back_units, leg.back_unit_force, leg.force_length, leg.hill}};
  tm.self_contact = leg.knee_contact;
  tm.contact_tets = leg.tets;
  tm.obstacles = leg.obstacles;
  check_model_parts(tm);
}

}  // namespace

LegModel build_leg_model(const LimbMesh& m, const std::vector<TendonStrands>& tendons, const LegModelOptions& o) {
  check_material(o.passive, "leg: passive tissue");
  check_material(o.muscle, "leg: muscle");
  LegModel leg;
  attach_bone_nodes(m, leg);
  std::vector<long> cubes;
  const TetMesh tissue_mesh = tissue_without_joint_space(m, o, leg, cubes);
  leg.tissue = tissue_model(tissue_mesh, cubes, o);
  build_knee(m, o, leg);
  build_muscles(m, o, leg);  // before the strands: an aponeurosis attaches at the muscles' fibre ends
  build_strands(tendons, o, leg);
  leg.tendon_toe_strain = o.tendon_toe_strain;
  leg.tets = tissue_mesh.tets;
  const std::vector<Tri> skin = skin_faces(m, tissue_mesh, o);
  build_knee_contact(m, tissue_mesh, skin, o, leg);
  build_obstacles(m, skin, o, leg);
  if (o.skin) {
    try {
      leg.tissue.skin = make_skin_membrane(leg.tissue.rest_positions, membrane_faces(skin, leg.tissue.rest_positions, o.leg_axis),
                                           o.skin->youngs_modulus, o.skin->thickness);
    } catch (const Error& e) {
      throw Error(std::string("leg: ") + e.what());
    }
  }
  leg.leg_axis = o.leg_axis.normalized();
  set_passive_joint(o, leg);
  compile_parts(leg);
  return leg;
}

LegState leg_rest_state(const LegModel& model, double angle, double blend) {
  LegState s;
  s.tissue = rest_state(model.tissue);
  s.knee.angle = angle;
  if (angle != 0.0) {
    const Hinge& k = model.knee;
    for (int i = 0; i < model.tissue.num_nodes(); ++i) {
      if (model.attached[static_cast<size_t>(i)]) continue;
      const Vec3 r = model.tissue.rest_positions.col(i) - k.centre;
      const double h = r.dot(model.leg_axis);
      const double w = blend > 0.0 ? std::clamp((blend - h) / (2.0 * blend), 0.0, 1.0) : (h < 0.0 ? 1.0 : 0.0);
      if (w > 0.0) s.tissue.x.col(i) = k.centre + hinge_rotation(k, w * angle) * r;
    }
  }
  place_attached(model.knee, s.knee, model.tissue.rest_positions, model.lower_nodes, s.tissue.x, s.tissue.v);
  return s;
}

void place_leg_on_femur(LegState& state, const RigidMotion& femur) {
  Points& x = state.tissue.x;
  Points& v = state.tissue.v;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    const Vec3 p = femur.place(x.col(i));
    v.col(i) = femur.rotation * Vec3(v.col(i)) + femur.velocity_at(p);
    x.col(i) = p;
  }
  state.femur = femur;
}

void step_leg(const LegModel& model, LegState& state, const LegControls& c, double dt, LegScratch& scratch,
              Integrator integrator) {
  const Model& tm = model.tissue;
  // The leg's controls as the tissue model's (buffers reused: no allocation
  // once sized).
  Controls& tc = scratch.controls;
  tc.group_offset.assign(tm.groups.size(), Vec3::Zero());
  tc.group_velocity.assign(tm.groups.size(), Vec3::Zero());
  tc.activation.assign(tm.muscles.size(), 0.0);
  tc.activation[kFrontMuscleIndex] = c.front_activation;
  tc.activation[kBackMuscleIndex] = c.back_activation;
  if (model.activation_time > 0.0 || model.deactivation_time > 0.0) {
    // The controls are excitations; the activations follow them over the step.
    if (state.activation.size() != 2) state.activation = {0.0, 0.0};  // muscles at rest before the first step
    for (int k : {kFrontMuscleIndex, kBackMuscleIndex}) {
      const size_t i = static_cast<size_t>(k);
      state.activation[i] = activation_step(state.activation[i], tc.activation[i], dt, model.activation_time,
                                            model.deactivation_time);
      tc.activation[i] = state.activation[i];
    }
  }
  tc.strand_natural_length.resize(model.strands.size());
  for (size_t si = 0; si < model.strands.size(); ++si) {
    const LegStrand& s = model.strands[si];
    const double scale = (static_cast<size_t>(s.tendon) < c.tendon_length_scale.size()
                              ? c.tendon_length_scale[static_cast<size_t>(s.tendon)]
                              : 1.0) *
                         (si < c.strand_natural_length.size() ? c.strand_natural_length[si] / s.natural_length : 1.0);
    tc.strand_natural_length[si] = scale * s.natural_length;
  }
  if (c.femur) {
    tc.group_motion.assign(tm.groups.size(), std::nullopt);
    tc.group_motion[kFemurGroup] = *c.femur;
  } else {
    tc.group_motion.clear();
  }
  tc.joint_torque.assign(1, c.joint_torque);
  tc.scripted_joint.assign(1, c.scripted_knee);
  tc.obstacle_offset.assign(c.obstacle_offset.begin(), c.obstacle_offset.end());
  tc.obstacle_velocity.assign(c.obstacle_velocity.begin(), c.obstacle_velocity.end());

  state.tissue.joints.resize(1);
  state.tissue.joints[kKneeJoint] = state.knee;
  try {
    step(tm, state.tissue, tc, dt, integrator, scratch.tissue);
  } catch (...) {
    state.knee = state.tissue.joints[kKneeJoint];
    throw;
  }
  state.knee = state.tissue.joints[kKneeJoint];
  state.femur = c.femur ? *c.femur : RigidMotion{};

  const Scratch& ts = scratch.tissue;
  scratch.tendon_tension.assign(model.tendon_names.size(), 0.0);
  scratch.tendon_strain.assign(model.tendon_names.size(), 0.0);
  for (size_t si = 0; si < model.strands.size(); ++si) {
    const size_t t = static_cast<size_t>(model.strands[si].tendon);
    scratch.tendon_tension[t] += ts.strand_tension[si];
    scratch.tendon_strain[t] = std::max(scratch.tendon_strain[t], ts.strand_strain[si]);
  }
  scratch.knee_torque = ts.joints[kKneeJoint].torque;
  scratch.passive_joint_torque = ts.joints[kKneeJoint].passive_torque;
  scratch.joint_reaction = ts.joints[kKneeJoint].reaction;
  scratch.knee_contact = ts.self_contact;
  scratch.obstacles.assign(ts.obstacles.begin(), ts.obstacles.end());
}

namespace {

// Where an anchored strand's insertion is with the knee at `angle` and the
// femur placed by `femur`.
Vec3 anchor_position(const LegModel& model, const LegStrand& s, double angle, const RigidMotion& femur) {
  const Vec3 p = s.anchor_bone == 2
                     ? Vec3(model.knee.centre + hinge_rotation(model.knee, angle) * (s.anchor_rest - model.knee.centre))
                     : s.anchor_rest;
  return femur.rotation == Mat3::Identity() && femur.offset == Vec3::Zero() ? p : femur.place(p);
}

}  // namespace

void leg_strand_points(const LegModel& model, const LegStrand& s, const Points& x, double angle, Points& p,
                       const RigidMotion& femur) {
  const Eigen::Index m = static_cast<Eigen::Index>(s.nodes.size() + (s.anchored ? 1 : 0));
  if (p.cols() != m) p.resize(3, m);
  for (size_t k = 0; k < s.nodes.size(); ++k) p.col(static_cast<Eigen::Index>(k)) = x.col(s.nodes[k]);
  if (s.anchored) p.col(m - 1) = anchor_position(model, s, angle, femur);
}

Points leg_strand_points(const LegModel& model, const LegStrand& s, const Points& x, double angle,
                         const RigidMotion& femur) {
  Points p;
  leg_strand_points(model, s, x, angle, p, femur);
  return p;
}

double leg_strand_length(const LegModel& model, const LegStrand& s, const Points& x, double angle,
                         const RigidMotion& femur) {
  double length = strand_length(x, s.nodes);
  if (s.anchored && !s.nodes.empty())
    length += (anchor_position(model, s, angle, femur) - Vec3(x.col(s.nodes.back()))).norm();
  return length;
}

double leg_strand_energy(const LegModel& model, const LegStrand& s, const Points& x, double angle,
                         double natural_length, const RigidMotion& femur) {
  return tendon_energy_at_length(leg_strand_length(model, s, x, angle, femur), natural_length, s.k_t,
                                 model.tendon_toe_strain);
}

double passive_joint_torque(const LegModel& model, const HingeState& knee) {
  return joint_passive_torque(model.tissue.joints[kKneeJoint], knee);
}

double leg_kinetic_energy(const LegModel& model, const LegState& state) {
  double e = 0.0;
  for (int i = 0; i < model.tissue.num_nodes(); ++i)
    e += 0.5 * model.tissue.mass[i] * state.tissue.v.col(i).squaredNorm();
  const double w = state.knee.velocity;
  if (model.lower_bone.mass <= 0.0) return e;
  const RigidMotion& f = state.femur;
  if (f.velocity == Vec3::Zero() && f.angular_velocity == Vec3::Zero())
    return e + 0.5 * moment_about_axis(model.lower_bone, model.knee.centre, model.knee.axis) * w * w;
  // On a moving femur: 1/2 M |v_cm|^2 + 1/2 Omega . I_cm Omega, Omega = omega_f + theta' n.
  const Mat3 rot = f.rotation * hinge_rotation(model.knee, state.knee.angle);
  const Vec3 c = f.place(model.knee.centre), n = f.rotation * model.knee.axis;
  const Vec3 cm = c + rot * (model.lower_bone.centre - model.knee.centre);
  const Vec3 omega = f.angular_velocity + w * n;
  const Vec3 v_cm = f.velocity_at(cm) + w * n.cross(cm - c);
  const Mat3 inertia = rot * model.lower_bone.inertia * rot.transpose();
  return e + 0.5 * model.lower_bone.mass * v_cm.squaredNorm() + 0.5 * omega.dot(inertia * omega);
}

}  // namespace msd
