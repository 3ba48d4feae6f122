// Time stepping (thesis 5.8: explicit Euler) with the kinematic constraints of
// the platens. step() is the whole update: accumulate the enabled force terms,
// integrate, apply prescribed motion, stop on a non-finite value.
//
//  - Explicit Euler (the thesis' method):
//      x+ = x + dt v,  v+ = v + dt a(x, v)
//  - Semi-implicit (symplectic) Euler:
//      v+ = v + dt a(x, v),  x+ = x + dt v+
//  - Velocity Verlet (kick-drift-kick; dampers see the half-step velocity):
//      v' = v + dt/2 a,  x+ = x + dt v',  a+ = a(x+, v'),  v+ = v' + dt/2 a+
//    One force evaluation per step: a+ is kept in the State for the next step.
//  - IMEX Euler (msd/integrate/imex_strands.hpp): symplectic Euler with the
//    tendon strands' stiffness taken linearly implicitly,
//      (M - dt^2 K_s) v+ = M v + dt f(x, v),  x+ = x + dt v+,
//    stable for real (1.2 GPa) tendons at the tissue's own explicit step.
//  - Backward Euler (implicit, msd/integrate/implicit.hpp):
//      v+ = v + dt a(x+, v+),  x+ = x + dt v+,  solved by Newton's method.
//  - BDF2 (implicit, second order; the same Newton solve):
//      y+ = 4/3 y - 1/3 y- + 2/3 dt F(y+) for y = (x, v), y- the state one
//      step back (State::x_prev, v_prev); variable-step form when the last
//      step had another length; a backward-Euler step where no history is.
//  - Quasi-static (no inertia, no dampers; the same Newton solve):
//      f(x+, 0) + load(t + dt) = 0 - the FEM reference's static problem.
// Constrained components of kinematic-group nodes are set to the prescribed
// position and velocity after each update; then surface nodes that entered a
// rigid obstacle are moved out of it (msd/contact/rigid_obstacle.hpp).
#pragma once

#include "msd/model/model.hpp"

#include <string>

namespace msd {

enum class Integrator { ExplicitEuler, SymplecticEuler, VelocityVerlet, BackwardEuler, Bdf2, QuasiStatic, ImexEuler };

/// Backward Euler, BDF2 and quasi-static: Newton solves, msd::NewtonOptions apply.
inline bool is_implicit(Integrator i) {
  return i == Integrator::BackwardEuler || i == Integrator::Bdf2 || i == Integrator::QuasiStatic;
}

/// Parses "explicit_euler", "symplectic_euler" (or "semi_implicit_euler"),
/// "velocity_verlet", "imex_euler", "backward_euler", "bdf2", "quasi_static".
Integrator parse_integrator(const std::string& name);
std::string to_string(Integrator integrator);

/// A run that produced a non-finite value or blew up. Carries when and where.
class SimulationFailure : public Error {
 public:
  SimulationFailure(const std::string& reason, double time, long step, int element, int node);
  double time;
  long step;
  int element;  ///< -1 when not tied to one element
  int node;     ///< -1 when not tied to one node
  std::string reason;
};

/// Sets the constrained components of group nodes in x and v from `controls`
/// (position = rest + offset, velocity = the group's), or - for a group a
/// joint drives - turns them rigidly to the joint's state in `joints`.
void apply_group_constraints(const Model& model, const Controls& controls, const std::vector<HingeState>& joints,
                             Points& x, Points& v);

/// Sets the constrained components of group nodes from `controls` and the
/// joints, resolves skin-against-skin contact (Model::self_contact), then the
/// contacts with the model's rigid obstacles at their placement in `controls`.
/// With `report`: its self_contact and obstacles record what was done, the
/// obstacles' reactions from the forces in report->f.
void apply_constraints(const Model& model, const Controls& controls, State& state);
void apply_constraints(const Model& model, const Controls& controls, State& state, Scratch* report);

/// The passive torque of a joint at state s (N m): -damping omega, and the
/// end-range torque outside [passive_lo, passive_hi].
double joint_passive_torque(const Joint& joint, const HingeState& s);

/// Steps the model's joints by dt (semi-implicit Euler, or their scripted
/// state) under the torque of the forces in scratch.f at `state`, recording
/// scratch.joints and the states before in scratch.joints_before.
void step_joints(const Model& model, State& state, const Controls& controls, double dt, Scratch& scratch);

/// Acceleration (f + s f_ext) / m (+ s g when gravity is enabled) from the
/// internal forces in scratch.f, with s = load_scale.
void accelerations(const Model& model, const Scratch& scratch, double load_scale, Points& a);

/// `controls` at the start of a step of dt that they prescribe at its end:
/// each rigid motion (Controls::group_motion) taken back by dt
/// (rigid_motion_before, second order), into scratch.start_controls.
const Controls& controls_before(const Controls& controls, double dt, Scratch& scratch);

/// Advances `state` by dt. `controls` prescribe the kinematic groups at t + dt;
/// the forces at the step's start see the groups' rigid motions there
/// (controls_before).
/// Throws SimulationFailure (naming the element, node, time and step) if a force,
/// position or velocity becomes non-finite.
void step(const Model& model, State& state, const Controls& controls, double dt,
          Integrator integrator, Scratch& scratch);

/// Evaluates internal forces at the current state into scratch.f (and the
/// nonlinear activity count), throwing SimulationFailure on a non-finite value.
/// With `controls`: the strands and muscles under them (msd/forces/parts.hpp);
/// without: relaxed muscles, the model's natural lengths.
void evaluate_forces(const Model& model, const State& state, Scratch& scratch);
void evaluate_forces(const Model& model, const State& state, const Controls& controls, Scratch& scratch);

}  // namespace msd
