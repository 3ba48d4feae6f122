#include "msd/integrate/step.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/forces/force_engine.hpp"
#include "msd/forces/parts.hpp"
#include "msd/integrate/imex_strands.hpp"
#include "msd/integrate/implicit.hpp"

#include <cmath>

namespace msd {

Integrator parse_integrator(const std::string& name) {
  if (name == "explicit_euler") return Integrator::ExplicitEuler;
  if (name == "symplectic_euler" || name == "semi_implicit_euler") return Integrator::SymplecticEuler;
  if (name == "velocity_verlet") return Integrator::VelocityVerlet;
  if (name == "backward_euler") return Integrator::BackwardEuler;
  if (name == "bdf2") return Integrator::Bdf2;
  if (name == "quasi_static") return Integrator::QuasiStatic;
  if (name == "imex_euler") return Integrator::ImexEuler;
  throw Error("unknown integrator '" + name +
              "' (expected explicit_euler, symplectic_euler, velocity_verlet, imex_euler, backward_euler, bdf2 or quasi_static)");
}

std::string to_string(Integrator integrator) {
  switch (integrator) {
    case Integrator::ExplicitEuler: return "explicit_euler";
    case Integrator::SymplecticEuler: return "symplectic_euler";
    case Integrator::VelocityVerlet: return "velocity_verlet";
    case Integrator::BackwardEuler: return "backward_euler";
    case Integrator::Bdf2: return "bdf2";
    case Integrator::QuasiStatic: return "quasi_static";
    case Integrator::ImexEuler: return "imex_euler";
  }
  return "?";
}

namespace {

std::string describe(const std::string& reason, double time, long step, int element, int node) {
  std::string s = reason + " at t = " + std::to_string(time) + " s (step " + std::to_string(step) + ")";
  if (element >= 0) s += ", element " + std::to_string(element);
  if (node >= 0) s += ", node " + std::to_string(node);
  return s;
}

[[noreturn]] void fail_non_finite_force(const Model& model, const State& state) {
  // Find the first element whose own forces are not finite.
  for (int e = 0; e < model.num_elements(); ++e) {
    Vec3 fe[4];
    element_forces(model, e, state.x, state.v, fe);
    for (int i = 0; i < 4; ++i)
      if (!fe[i].allFinite())
        throw SimulationFailure("non-finite element force", state.t, state.step, e,
                                model.elements[static_cast<size_t>(e)].nodes[i]);
  }
  throw SimulationFailure("non-finite force", state.t, state.step, -1, -1);
}

void check_state(const Model& model, const State& state) {
  for (size_t j = 0; j < state.joints.size(); ++j)
    if (!std::isfinite(state.joints[j].angle) || !std::isfinite(state.joints[j].velocity))
      throw SimulationFailure("non-finite angle of joint '" + model.joints[j].name + "'", state.t, state.step, -1, -1);
  if (state.x.allFinite() && state.v.allFinite()) return;
  for (int n = 0; n < state.x.cols(); ++n)
    if (!state.x.col(n).allFinite() || !state.v.col(n).allFinite()) {
      int element = -1;
      for (int e = 0; e < model.num_elements() && element < 0; ++e)
        for (int i = 0; i < 4; ++i)
          if (model.elements[static_cast<size_t>(e)].nodes[i] == n) element = e;
      throw SimulationFailure("non-finite position or velocity", state.t, state.step, element, n);
    }
}

}  // namespace

SimulationFailure::SimulationFailure(const std::string& why, double t, long s, int e, int n)
    : Error(describe(why, t, s, e, n)), time(t), step(s), element(e), node(n), reason(why) {}

void apply_group_constraints(const Model& model, const Controls& controls, const std::vector<HingeState>& joints,
                             Points& x, Points& v) {
  for (size_t g = 0; g < model.groups.size(); ++g) {
    const KinematicGroup& grp = model.groups[g];
    const RigidMotion* own = group_motion(controls, static_cast<int>(g));
    if (own && (grp.joint >= 0 || !(grp.axes[0] && grp.axes[1] && grp.axes[2])))
      throw Error("controls: group '" + grp.name + "' is given a rigid motion but " +
                  (grp.joint >= 0 ? "its joint turns it" : "it leaves an axis free"));
    if (grp.joint >= 0) {
      place_attached(model.joints[static_cast<size_t>(grp.joint)].hinge, joints[static_cast<size_t>(grp.joint)],
                     model.rest_positions, grp.nodes, x, v);
      // On a moving parent: relative placement, then carried by its frame.
      if (const RigidMotion* frame = joint_frame(model, controls, grp.joint))
        for (int n : grp.nodes) {
          const Vec3 p = frame->place(x.col(n));
          v.col(n) = frame->rotation * Vec3(v.col(n)) + frame->velocity_at(p);
          x.col(n) = p;
        }
      continue;
    }
    if (const RigidMotion* m = own) {
      for (int n : grp.nodes) {
        x.col(n) = m->place(model.rest_positions.col(n));
        v.col(n) = m->velocity_at(x.col(n));
      }
      continue;
    }
    const Vec3& off = controls.group_offset.at(g);
    const Vec3& vel = controls.group_velocity.at(g);
    for (int n : grp.nodes)
      for (int a = 0; a < 3; ++a)
        if (grp.axes[a]) {
          x(a, n) = model.rest_positions(a, n) + off[a];
          v(a, n) = vel[a];
        }
  }
}

void apply_constraints(const Model& model, const Controls& controls, State& state) {
  apply_constraints(model, controls, state, nullptr);
}

void apply_constraints(const Model& model, const Controls& controls, State& state, Scratch* report) {
  apply_group_constraints(model, controls, state.joints, state.x, state.v);
  if (model.self_contact) {
    if (report) {
      report->self_contact = resolve_self_contact(*model.self_contact, model.contact_tets, state.x, state.v,
                                                  model.kinematic, report->contact_buffers);
    } else {
      resolve_self_contact(*model.self_contact, model.contact_tets, state.x, state.v, model.kinematic);
    }
  }
  if (report && report->obstacles.size() != model.obstacles.size()) report->obstacles.resize(model.obstacles.size());
  const bool gravity = model.terms & kGravity;
  for (size_t k = 0; k < model.obstacles.size(); ++k) {
    const RigidObstacle& ob = model.obstacles[k];
    const Vec3 off = k < controls.obstacle_offset.size() ? controls.obstacle_offset[k] : Vec3::Zero();
    const Vec3 vel = k < controls.obstacle_velocity.size() ? controls.obstacle_velocity[k] : Vec3::Zero();
    ObstacleContact* out = report ? &report->obstacles[k] : nullptr;
    if (out) *out = ObstacleContact{};
    for (int n : ob.nodes) {
      Vec3 x = state.x.col(n), v = state.v.col(n);
      const ContactGap gap = out ? obstacle_gap(ob, off, x) : ContactGap{};
      if (!resolve_obstacle_contact(ob, off, vel, x, v)) continue;
      state.x.col(n) = x;
      state.v.col(n) = v;
      if (!out) continue;
      // The reaction that holds the node on the surface against the last
      // evaluated forces (rigid_obstacle.hpp).
      ++out->contacts;
      out->max_depth = std::max(out->max_depth, gap.depth);
      const Vec3 g = gravity ? Vec3(controls.load_scale * model.gravity) : Vec3::Zero();
      const double lambda = std::max(0.0, -(Vec3(report->f.col(n)) + model.mass[n] * g).dot(gap.normal));
      out->force += lambda * gap.normal;
    }
  }
}

void accelerations(const Model& model, const Scratch& scratch, double load_scale, Points& a) {
  if (model.external_force.cols() == scratch.f.cols())
    a = (scratch.f + load_scale * model.external_force) * model.inv_mass.asDiagonal();
  else
    a = scratch.f * model.inv_mass.asDiagonal();
  if (model.terms & kGravity) a.colwise() += load_scale * model.gravity;
}

void evaluate_forces(const Model& model, const State& state, Scratch& scratch) {
  static const Controls none;
  evaluate_forces(model, state, none, scratch);
}

void evaluate_forces(const Model& model, const State& state, const Controls& controls, Scratch& scratch) {
  scratch.nonlinear_active = model.reference_forces
                                 ? compute_internal_forces_reference(model, state.x, state.v, scratch.f)
                                 : compute_forces_fast(model, state.x, state.v, scratch.f, scratch);
  if (!model.strands.empty() || !model.muscles.empty() || !model.skin.empty())
    add_part_forces(model, state.x, state.v, state.joints, controls, scratch);
  if (!scratch.f.allFinite()) fail_non_finite_force(model, state);
}

namespace {

// The hinge's centre and axis now, and the inertia tensor (about the centre)
// and first moment of its body: its own mass and its group's nodes.
struct JointBody {
  Vec3 centre, axis, moment{Vec3::Zero()};
  Mat3 inertia{Mat3::Zero()};
  double mass = 0.0;
};

void add_point_mass(JointBody& b, double m, const Vec3& r) {
  b.mass += m;
  b.moment += m * r;
  b.inertia += m * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
}

// The fictitious torque about the axis of a hinge on a moving parent (Joint):
// -n . (I_c alpha) - n . (omega x I_c omega) - n . (S_c x a_c).
double frame_torque(const JointBody& b, const RigidMotion& p) {
  const Vec3 a_c = p.acceleration_at(b.centre);
  const Vec3 w = p.angular_velocity;
  return -b.axis.dot(b.inertia * p.angular_acceleration + w.cross(b.inertia * w) + b.moment.cross(a_c));
}

}  // namespace

void step_joints(const Model& model, State& state, const Controls& c, double dt, Scratch& scratch) {
  const size_t nj = model.joints.size();
  if (scratch.joints.size() != nj) scratch.joints.resize(nj);
  scratch.joints_before = state.joints;
  const Points& f = scratch.f;
  const Vec3 g = (model.terms & kGravity) ? Vec3(c.load_scale * model.gravity) : Vec3::Zero();
  for (size_t j = 0; j < nj; ++j) {
    const Joint& jt = model.joints[j];
    const Hinge& h = jt.hinge;
    HingeState& hs = state.joints[j];
    const RigidMotion* frame = joint_frame(model, c, static_cast<int>(j));
    JointBody b;
    b.centre = frame ? frame->place(h.centre) : h.centre;
    b.axis = frame ? Vec3(frame->rotation * h.axis) : h.axis;
    // Torque about the centre, resultant and first moment of the turning body:
    // its anchored strands, its nodes, its own mass.
    Vec3 torque = Vec3::Zero(), applied = Vec3::Zero();
    for (size_t si = 0; si < model.strands.size() && si < scratch.anchor_force.size(); ++si) {
      const Strand& s = model.strands[si];
      if (s.anchor_group != jt.group) continue;
      const Vec3 fa = scratch.anchor_force[si];
      torque += (group_point(model, s.anchor_group, s.anchor_rest, state.x, state.joints, c) - b.centre).cross(fa);
      applied += fa;
    }
    for (int i : model.groups[static_cast<size_t>(jt.group)].nodes) {
      const Vec3 r = Vec3(state.x.col(i)) - b.centre;
      torque += r.cross(Vec3(f.col(i)) + model.mass[i] * g);
      applied += Vec3(f.col(i)) + model.mass[i] * g;
      if (frame)
        add_point_mass(b, model.mass[i], r);
      else
        b.moment += model.mass[i] * r;
    }
    if (jt.body.mass > 0.0) {
      const Mat3 rot = frame ? Mat3(frame->rotation * hinge_rotation(h, hs.angle)) : hinge_rotation(h, hs.angle);
      const Vec3 r = Vec3(b.centre + rot * (jt.body.centre - h.centre)) - b.centre;  // (the bits of c + R (X - c) - c)
      torque += r.cross(jt.body.mass * g);
      applied += jt.body.mass * g;
      if (frame) {
        add_point_mass(b, jt.body.mass, r);
        b.inertia += rot * jt.body.inertia * rot.transpose();
      } else {
        b.moment += jt.body.mass * r;
      }
    }
    const double omega_before = hs.velocity;
    JointReport& rep = scratch.joints[j];
    rep.passive_torque = joint_passive_torque(jt, hs);
    rep.torque = (frame ? b.axis.dot(torque) : axial_torque(h, torque)) + (j < c.joint_torque.size() ? c.joint_torque[j] : 0.0) + rep.passive_torque;
    if (frame) rep.torque += frame_torque(b, *frame);
    if (j < c.scripted_joint.size() && c.scripted_joint[j])
      hs = *c.scripted_joint[j];
    else
      step_hinge(h, rep.torque, dt, hs);
    // The body's momentum changes by M a_cm = R + applied: R the reaction.
    const Vec3 n = b.axis;
    const double alpha = dt > 0.0 ? (hs.velocity - omega_before) / dt : 0.0, w = hs.velocity;
    if (frame) {
      // M a_cm = M a_c + Omega' x S_c + Omega x (Omega x S_c), Omega = omega_p + theta' n.
      const Vec3 big_w = frame->angular_velocity + w * n;
      const Vec3 big_w_dot = frame->angular_acceleration + alpha * n + w * frame->angular_velocity.cross(n);
      rep.reaction = b.mass * frame->acceleration_at(b.centre) + big_w_dot.cross(b.moment) +
                     big_w.cross(big_w.cross(b.moment)) - applied;
    } else {
      // a_c = alpha n x r_c - omega^2 r_c,perp (r_c its centre of mass from the joint's centre).
      const Vec3 rc_perp = b.moment - b.moment.dot(n) * n;
      rep.reaction = alpha * n.cross(b.moment) - w * w * rc_perp - applied;
    }
  }
}

double joint_passive_torque(const Joint& j, const HingeState& s) {
  double tau = -j.damping * s.velocity;
  if (s.angle > j.passive_hi) tau -= j.limit_stiffness * (s.angle - j.passive_hi);
  if (s.angle < j.passive_lo) tau -= j.limit_stiffness * (s.angle - j.passive_lo);
  return tau;
}

const Controls& controls_before(const Controls& controls, double dt, Scratch& scratch) {
  Controls& b = scratch.start_controls;
  b = controls;  // (into the buffers of the last step: no allocation once sized)
  for (auto& m : b.group_motion)
    if (m) m = rigid_motion_before(*m, dt);
  return b;
}

void step(const Model& model, State& state, const Controls& controls, double dt,
          Integrator integrator, Scratch& scratch) {
  if (state.x.cols() != model.num_nodes() || state.v.cols() != model.num_nodes())
    throw Error("step: state has " + std::to_string(state.x.cols()) + " nodes, model " +
                std::to_string(model.num_nodes()));
  if (state.joints.size() != model.joints.size())
    throw Error("step: state has " + std::to_string(state.joints.size()) + " joints, model " +
                std::to_string(model.joints.size()));
  const bool joints = !model.joints.empty();
  // The forces at the step's start, and the joints stepped from them, see the
  // kinematic groups where the state's nodes are: a rigid motion (given at
  // the step's end) taken back by dt. Without one, the controls as they are.
  const Controls& start = controls.group_motion.empty() ? controls : controls_before(controls, dt, scratch);
  switch (integrator) {
    case Integrator::ExplicitEuler: {
      evaluate_forces(model, state, start, scratch);
      accelerations(model, scratch, controls.load_scale, state.a);
      if (joints) step_joints(model, state, start, dt, scratch);
      state.x += dt * state.v;
      state.v += dt * state.a;
      break;
    }
    case Integrator::SymplecticEuler: {
      evaluate_forces(model, state, start, scratch);
      accelerations(model, scratch, controls.load_scale, state.a);
      if (joints) step_joints(model, state, start, dt, scratch);
      state.v += dt * state.a;
      state.x += dt * state.v;
      break;
    }
    case Integrator::ImexEuler: {
      evaluate_forces(model, state, start, scratch);
      accelerations(model, scratch, controls.load_scale, state.a);
      StrandSolveWorkspace* ws = nullptr;
      if (!model.strands.empty()) {
        if (!scratch.strand_solve) scratch.strand_solve = std::make_shared<StrandSolveWorkspace>();
        ws = scratch.strand_solve.get();
        // The strands' stiffness where their forces were evaluated: before the joints move.
        assemble_strand_systems(model, state, start, dt, *ws);
      }
      if (joints) step_joints(model, state, start, dt, scratch);
      state.v += dt * state.a;
      if (ws) solve_strand_velocities(model, controls, dt, *ws, state);
      state.x += dt * state.v;
      break;
    }
    case Integrator::VelocityVerlet: {
      if (!state.a_valid || joints) {
        evaluate_forces(model, state, start, scratch);
        accelerations(model, scratch, controls.load_scale, state.a);
      }
      if (joints) step_joints(model, state, start, dt, scratch);
      state.v += 0.5 * dt * state.a;
      state.x += dt * state.v;
      apply_constraints(model, controls, state, &scratch);
      evaluate_forces(model, state, controls, scratch);
      accelerations(model, scratch, controls.load_scale, state.a);
      state.v += 0.5 * dt * state.a;
      state.a_valid = true;
      break;
    }
    case Integrator::QuasiStatic:
      step_quasi_static(model, state, controls, dt, scratch);
      break;
    case Integrator::BackwardEuler:
    case Integrator::Bdf2:
      if (joints) {
        evaluate_forces(model, state, start, scratch);
        step_joints(model, state, start, dt, scratch);
      }
      try {
        if (integrator == Integrator::Bdf2)
          step_bdf2(model, state, controls, dt, scratch);
        else
          step_backward_euler(model, state, controls, dt, scratch);
      } catch (const SimulationFailure&) {
        if (joints) state.joints = scratch.joints_before;  // the joints stay with the nodes, at the step's start
        throw;
      }
      break;
  }
  if (integrator != Integrator::VelocityVerlet) state.a_valid = false;
  if (integrator != Integrator::Bdf2) state.dt_prev = 0.0;  // another integrator's step: no BDF2 history
  state.t += dt;
  ++state.step;
  apply_constraints(model, controls, state, &scratch);
  check_state(model, state);
}

}  // namespace msd
