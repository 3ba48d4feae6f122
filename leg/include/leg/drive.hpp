// The drive: what a scene and its activation script ask of the leg at time t,
// as the controls of one step (thesis 3.7: kinematic, dynamic and added-torque
// knee control; 5.7: scripted muscle activation; tendon pre-tension; scripted
// obstacle motion).
#pragma once

#include "leg/scene.hpp"

#include "msd/scene/leg_model.hpp"

namespace leg {

/// The controls before the first step: per-tendon and per-obstacle vectors
/// sized for `model`; strands slack when the scene engages its tendons later.
msd::LegControls initial_controls(const msd::LegModel& model, const LegScene& scene);

/// Sets the controls in effect over the step of length dt ending at t:
/// activations (script, else the variant's constants), the tendons' pre-tension
/// scale, the added joint torque, the scripted knee (until its release), the
/// femur's motion (a scripted hip), and the obstacles' offsets and velocities.
void drive(const LegScene& scene, const LegVariant& variant, double t, double dt, msd::LegControls& controls);

/// Whether the scene's slack tendons engage at the step starting at t.
inline bool tendons_due(const LegScene& scene, double t) {
  return scene.tendons_engage_at && t >= *scene.tendons_engage_at - 1e-12;
}

/// Engages tendons that were slack: each strand's natural length becomes its
/// path's length in the current state.
void engage_tendons(const msd::LegModel& model, const msd::LegState& state, msd::LegControls& controls);

}  // namespace leg
