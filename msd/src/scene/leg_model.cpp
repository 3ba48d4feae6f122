#include "msd/scene/leg_model.hpp"

#include "msd/forces/muscle_units.hpp"
#include "msd/forces/tendon.hpp"

#include <algorithm>
#include <cmath>

namespace msd {

LegModel build_leg_model(const LimbMesh& m, const std::vector<TendonStrands>& tendons, const LegModelOptions& o) {
  check_material(o.passive, "leg: passive tissue");
  check_material(o.muscle, "leg: muscle");
  LegModel leg;
  // Which bone holds each node: its tets' nodes and its bone points.
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
  // The joint space: a tet with nodes on both bones would be crushed by any
  // rotation of one about the other (the cubic mesh leaves a single cube of
  // passive tissue between condyles and plateau), so it is left out - no
  // tissue joins the two bones directly.
  TetMesh tissue_mesh = m.mesh;
  tissue_mesh.tets.clear();
  tissue_mesh.region.clear();
  for (size_t e = 0; e < m.mesh.tets.size(); ++e) {
    unsigned bones = 0;
    for (int v : m.mesh.tets[e]) bones |= leg.attached[static_cast<size_t>(v)];
    if (bones == 3u) {
      ++leg.joint_space_tets;
      continue;
    }
    tissue_mesh.tets.push_back(m.mesh.tets[e]);
    tissue_mesh.region.push_back(m.mesh.region[e]);
  }
  ModelOptions mo;
  mo.terms = o.terms;
  mo.nonlinear_threshold = o.nonlinear_threshold;
  mo.gravity = o.gravity;
  // Region labels 0..4: passive, front and back muscle, the bones (their tets
  // move rigidly; any material will do, passive tissue's is used).
  mo.region_materials = {o.passive, o.muscle, o.muscle, o.passive, o.passive};
  leg.tissue = build_model(tissue_mesh, mo);

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

  for (const TendonStrands& t : tendons) {
    leg.tendon_names.push_back(t.name);
    for (const auto& s : t.strands) {
      LegStrand ls;
      ls.nodes = s;
      ls.tendon = static_cast<int>(leg.tendon_names.size()) - 1;
      ls.natural_length = strand_length(leg.tissue.rest_positions, s);
      if (!(ls.natural_length > 0.0)) throw Error("leg: tendon '" + t.name + "' has a strand of zero length");
      ls.k_t = tendon_stiffness(o.tendon_modulus, o.strand_area, ls.natural_length);
      leg.strands.push_back(ls);
    }
  }
  leg.tets = tissue_mesh.tets;
  if (o.knee_contact_box)
    leg.knee_contact = make_self_contact_region(tissue_mesh, "behind the knee", o.knee_contact_box->first,
                                                o.knee_contact_box->second, o.knee_centre, o.leg_axis);
  leg.front_units = contractile_units(m.mesh, kFrontMuscle, o.front_line, o.unit_angle_deg);
  leg.back_units = contractile_units(m.mesh, kBackMuscle, o.back_line, o.unit_angle_deg);
  leg.front_unit_force = unit_force(m.mesh, kFrontMuscle, leg.front_units, o.front_line, 1.0, o.max_muscle_stress);
  leg.back_unit_force = unit_force(m.mesh, kBackMuscle, leg.back_units, o.back_line, 1.0, o.max_muscle_stress);
  return leg;
}

LegState leg_rest_state(const LegModel& model, double angle) {
  LegState s;
  s.tissue = rest_state(model.tissue);
  s.knee.angle = angle;
  place_attached(model.knee, s.knee, model.tissue.rest_positions, model.lower_nodes, s.tissue.x, s.tissue.v);
  return s;
}

void step_leg(const LegModel& model, LegState& state, const LegControls& c, double dt, LegScratch& scratch) {
  const Model& tm = model.tissue;
  State& ts = state.tissue;
  evaluate_forces(tm, ts, scratch.tissue);
  Points& f = scratch.tissue.f;

  // Tendons (tension only) and muscles add to the one force buffer.
  scratch.tendon_tension.assign(model.tendon_names.size(), 0.0);
  for (const LegStrand& s : model.strands) {
    const double scale = static_cast<size_t>(s.tendon) < c.tendon_length_scale.size()
                             ? c.tendon_length_scale[static_cast<size_t>(s.tendon)]
                             : 1.0;
    scratch.tendon_tension[static_cast<size_t>(s.tendon)] +=
        add_tendon_forces(ts.x, s.nodes, scale * s.natural_length, s.k_t, f);
  }
  if (c.front_activation > 0.0) add_muscle_forces(ts.x, model.front_units, c.front_activation * model.front_unit_force, f);
  if (c.back_activation > 0.0) add_muscle_forces(ts.x, model.back_units, c.back_activation * model.back_unit_force, f);

  // The torque on the lower leg about the hinge.
  const bool gravity = tm.terms & kGravity;
  const Vec3 g = gravity ? tm.gravity : Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  for (int i : model.lower_nodes)
    torque += (Vec3(ts.x.col(i)) - model.knee.centre).cross(Vec3(f.col(i)) + tm.mass[i] * g);
  if (model.lower_bone.mass > 0.0) {
    const Vec3 centre = model.knee.centre + hinge_rotation(model.knee, state.knee.angle) *
                                                (model.lower_bone.centre - model.knee.centre);
    torque += (centre - model.knee.centre).cross(model.lower_bone.mass * g);
  }
  scratch.knee_torque = axial_torque(model.knee, torque) + c.joint_torque;

  // Free nodes: semi-implicit Euler.
  for (int i = 0; i < tm.num_nodes(); ++i) {
    if (model.attached[static_cast<size_t>(i)]) continue;
    ts.v.col(i) += dt * (f.col(i) * tm.inv_mass[i] + g);
    ts.x.col(i) += dt * ts.v.col(i);
  }
  // The knee, then the bones' nodes.
  if (c.scripted_knee)
    state.knee = *c.scripted_knee;
  else
    step_hinge(model.knee, scratch.knee_torque, dt, state.knee);
  place_attached(model.knee, state.knee, tm.rest_positions, model.lower_nodes, ts.x, ts.v);
  for (int i : model.femur_nodes) {
    ts.x.col(i) = tm.rest_positions.col(i);
    ts.v.col(i).setZero();
  }
  scratch.knee_contact = model.knee_contact
                             ? resolve_self_contact(*model.knee_contact, model.tets, ts.x, ts.v, model.attached)
                             : SelfContactReport{};
  ts.t += dt;
  ++ts.step;
  if (!ts.x.allFinite() || !ts.v.allFinite() || !std::isfinite(state.knee.angle)) {
    for (int i = 0; i < tm.num_nodes(); ++i)
      if (!ts.x.col(i).allFinite() || !ts.v.col(i).allFinite())
        throw SimulationFailure("leg: non-finite position or velocity", ts.t, ts.step, -1, i);
    throw SimulationFailure("leg: non-finite knee angle", ts.t, ts.step, -1, -1);
  }
}

double leg_kinetic_energy(const LegModel& model, const LegState& state) {
  double e = 0.0;
  for (int i = 0; i < model.tissue.num_nodes(); ++i)
    e += 0.5 * model.tissue.mass[i] * state.tissue.v.col(i).squaredNorm();
  const double w = state.knee.velocity;
  if (model.lower_bone.mass > 0.0)
    e += 0.5 * moment_about_axis(model.lower_bone, model.knee.centre, model.knee.axis) * w * w;
  return e;
}

}  // namespace msd
