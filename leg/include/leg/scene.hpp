// A leg scene (`tissuebench leg SCENE.yaml`, thesis 6): the limb, its
// materials, how the knee is driven, the tendons, the muscles' activation, the
// collision regions and objects, what to measure. Field reference:
// docs/leg-scenes.md. Only what a scene names is built.
#pragma once

#include "msd/control/activation_script.hpp"
#include "msd/control/keyframes.hpp"
#include "msd/control/pose_keyframes.hpp"
#include "msd/scene/leg_model.hpp"

#include "tbio/parameter.hpp"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace leg {

struct LegBox {
  std::string name;
  msd::Vec3 lo{msd::Vec3::Zero()}, hi{msd::Vec3::Zero()};
  bool contains(const msd::Vec3& x) const {
    return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  }
};

struct LegVariant {
  std::string name;
  double front = 0.0, back = 0.0;  ///< constant activations
};

struct LegScene {
  std::string name, description, file, text;
  std::vector<std::string> overrides;  ///< --set KEY=VALUE applied to the file (read_leg_scene)
  std::string geometry;  ///< mesh scene (YAML)
  bool mesh_pull = true; ///< false: the geometry's pull areas are ignored
  double duration = 0.0, dt = 0.0, output_interval = 0.04;
  msd::Integrator integrator = msd::Integrator::SymplecticEuler;
  msd::LegModelOptions model;
  double initial_angle = 0.0, initial_velocity = 0.0;  ///< rad, rad/s
  msd::Keyframes<double> knee_angle;                        ///< rad; empty: dynamic knee
  std::optional<double> knee_release;                  ///< s: after it the knee is dynamic
  msd::Keyframes<double> joint_torque;                      ///< N m
  /// A scripted hip: the femur's pose through time (the pivot's position and
  /// the orientation); none: the femur held at rest.
  std::optional<msd::PoseKeyframes> hip;
  bool insert_at_path_end = true;
  std::optional<double> tendons_engage_at;
  double tendon_failure_strain = 0.1;  ///< the summary warns past it
  double pretension_fraction = 0.0, pretension_start = 0.0, pretension_duration = 0.0;
  std::optional<msd::ActivationScript> script;
  std::string script_path;
  double front_activation = 0.0, back_activation = 0.0;  ///< when there is no script
  std::vector<msd::Keyframes<msd::Vec3>> obstacle_motion;     ///< per obstacle, offsets (m)
  double analysis_from = 0.0;
  std::vector<LegBox> bulge_areas;
  std::optional<double> drop_release;
  std::optional<LegBox> wobble_probe;
  double wobble_after = 0.0;
  std::vector<LegVariant> variants;
  int obj_every = 1;
};

/// Every field of a scene, declared once (path, unit, default, range, doc);
/// docs/leg-scenes.md's table is generated from it.
const std::vector<tbio::Parameter>& leg_scene_parameters();
/// The declaration at `path` (throws std::logic_error if none: a reader's typo).
const tbio::Parameter& leg_scene_parameter(const std::string& path);

/// Reads a scene. Throws msd::Error "FILE:LINE:COL: field: what" for a missing
/// or unknown field, a value out of range, a script with errors (its own
/// file and line), or an output interval that is not a whole number of steps.
/// `overrides` ("KEY=VALUE", KEY a dotted field such as knee.damping or
/// materials.passive.youngs_modulus, VALUE YAML) replace or add fields before
/// the scene is checked, as if the file said so (a missing section is made);
/// a malformed one throws msd::Error "--set KEY=VALUE: what". They are kept in
/// LegScene::overrides, and LegScene::text is then the changed scene (YAML,
/// without the file's comments) followed by a "# --set KEY=VALUE" line each.
LegScene read_leg_scene(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace leg
