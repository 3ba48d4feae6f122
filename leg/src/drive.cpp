#include "leg/drive.hpp"

#include <algorithm>
#include <limits>

namespace leg {

msd::LegControls initial_controls(const msd::LegModel& model, const LegScene& scene) {
  msd::LegControls c;
  c.tendon_length_scale.assign(model.tendon_names.size(), 1.0);
  c.obstacle_offset.assign(model.obstacles.size(), msd::Vec3::Zero());
  c.obstacle_velocity.assign(model.obstacles.size(), msd::Vec3::Zero());
  if (scene.tendons_engage_at)
    c.strand_natural_length.assign(model.strands.size(), std::numeric_limits<double>::infinity());
  return c;
}

void drive(const LegScene& scene, const LegVariant& variant, double t, double dt, msd::LegControls& controls) {
  controls.front_activation = scene.script ? scene.script->activation("FRONT_MUSCLE", t) : variant.front;
  controls.back_activation = scene.script ? scene.script->activation("BACK_MUSCLE", t) : variant.back;
  double scale = 1.0;
  if (scene.pretension_fraction > 0.0) {
    // L0 -> (1 - fraction) L0, linearly over the pre-tension's duration.
    const double ramp = scene.pretension_duration > 0.0
                            ? std::clamp((t - scene.pretension_start) / scene.pretension_duration, 0.0, 1.0)
                            : (t >= scene.pretension_start ? 1.0 : 0.0);
    scale = 1.0 - scene.pretension_fraction * ramp;
  }
  std::fill(controls.tendon_length_scale.begin(), controls.tendon_length_scale.end(), scale);
  controls.joint_torque = scene.joint_torque.empty() ? 0.0 : scene.joint_torque.at(t);
  // Rates at the step's midpoint: the slope of the segment the step lies in.
  if (!scene.knee_angle.empty() && (!scene.knee_release || t <= *scene.knee_release))
    controls.scripted_knee = msd::HingeState{scene.knee_angle.at(t), scene.knee_angle.rate(t - 0.5 * dt)};
  else
    controls.scripted_knee.reset();
  if (scene.hip)
    controls.femur = scene.hip->at(t);
  else
    controls.femur.reset();
  for (size_t k = 0; k < scene.obstacle_motion.size(); ++k)
    if (!scene.obstacle_motion[k].empty()) {
      controls.obstacle_offset[k] = scene.obstacle_motion[k].at(t);
      controls.obstacle_velocity[k] = scene.obstacle_motion[k].rate(t - 0.5 * dt);
    }
}

void engage_tendons(const msd::LegModel& model, const msd::LegState& state, msd::LegControls& controls) {
  for (size_t k = 0; k < model.strands.size(); ++k)
    controls.strand_natural_length[k] = msd::leg_strand_length(model, model.strands[k], state.tissue.x, state.knee.angle, state.femur);
}

}  // namespace leg
