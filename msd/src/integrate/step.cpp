#include "msd/integrate/step.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/forces/force_engine.hpp"
#include "msd/integrate/implicit.hpp"

#include <cmath>

namespace msd {

Integrator parse_integrator(const std::string& name) {
  if (name == "explicit_euler") return Integrator::ExplicitEuler;
  if (name == "symplectic_euler" || name == "semi_implicit_euler") return Integrator::SymplecticEuler;
  if (name == "velocity_verlet") return Integrator::VelocityVerlet;
  if (name == "backward_euler") return Integrator::BackwardEuler;
  throw Error("unknown integrator '" + name +
              "' (expected explicit_euler, symplectic_euler, velocity_verlet or backward_euler)");
}

std::string to_string(Integrator integrator) {
  switch (integrator) {
    case Integrator::ExplicitEuler: return "explicit_euler";
    case Integrator::SymplecticEuler: return "symplectic_euler";
    case Integrator::VelocityVerlet: return "velocity_verlet";
    case Integrator::BackwardEuler: return "backward_euler";
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

void apply_group_constraints(const Model& model, const Controls& controls, Points& x, Points& v) {
  for (size_t g = 0; g < model.groups.size(); ++g) {
    const KinematicGroup& grp = model.groups[g];
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
  apply_group_constraints(model, controls, state.x, state.v);
  for (size_t k = 0; k < model.obstacles.size(); ++k) {
    const RigidObstacle& ob = model.obstacles[k];
    const Vec3 off = k < controls.obstacle_offset.size() ? controls.obstacle_offset[k] : Vec3::Zero();
    const Vec3 vel = k < controls.obstacle_velocity.size() ? controls.obstacle_velocity[k] : Vec3::Zero();
    for (int n : ob.nodes) {
      Vec3 x = state.x.col(n), v = state.v.col(n);
      if (resolve_obstacle_contact(ob, off, vel, x, v)) {
        state.x.col(n) = x;
        state.v.col(n) = v;
      }
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
  scratch.nonlinear_active = model.reference_forces
                                 ? compute_internal_forces_reference(model, state.x, state.v, scratch.f)
                                 : compute_forces_fast(model, state.x, state.v, scratch.f, scratch);
  if (!scratch.f.allFinite()) fail_non_finite_force(model, state);
}

void step(const Model& model, State& state, const Controls& controls, double dt,
          Integrator integrator, Scratch& scratch) {
  if (state.x.cols() != model.num_nodes() || state.v.cols() != model.num_nodes())
    throw Error("step: state has " + std::to_string(state.x.cols()) + " nodes, model " +
                std::to_string(model.num_nodes()));
  switch (integrator) {
    case Integrator::ExplicitEuler: {
      evaluate_forces(model, state, scratch);
      accelerations(model, scratch, controls.load_scale, state.a);
      state.x += dt * state.v;
      state.v += dt * state.a;
      break;
    }
    case Integrator::SymplecticEuler: {
      evaluate_forces(model, state, scratch);
      accelerations(model, scratch, controls.load_scale, state.a);
      state.v += dt * state.a;
      state.x += dt * state.v;
      break;
    }
    case Integrator::VelocityVerlet: {
      if (!state.a_valid) {
        evaluate_forces(model, state, scratch);
        accelerations(model, scratch, controls.load_scale, state.a);
      }
      state.v += 0.5 * dt * state.a;
      state.x += dt * state.v;
      apply_constraints(model, controls, state);
      evaluate_forces(model, state, scratch);
      accelerations(model, scratch, controls.load_scale, state.a);
      state.v += 0.5 * dt * state.a;
      state.a_valid = true;
      break;
    }
    case Integrator::BackwardEuler:
      step_backward_euler(model, state, controls, dt, scratch);
      break;
  }
  if (integrator != Integrator::VelocityVerlet) state.a_valid = false;
  state.t += dt;
  ++state.step;
  apply_constraints(model, controls, state);
  check_state(model, state);
}

}  // namespace msd
