// `tissuebench leg SCENE.yaml --out DIR`: the leg in motion (thesis 6). A
// scene names the limb (a mesh scene, default the shipped leg), its materials,
// how the knee is driven, the tendons' pre-tension, the muscles' activation
// script, the collision regions and rigid objects, and what to measure. Only
// what it names is built: no obstacle, no contact region, no script - no cost.
//
//   name: hamstrings
//   description: ...
//   geometry: ../leg/leg.yaml        # a `tissuebench mesh` scene; default: the shipped leg
//   mesh_pull: false                 # ignore the geometry's pull areas (thesis 4.6); default true
//   duration: 11.0                   # s
//   dt: 2.0e-4                       # s
//   output_interval: 0.04            # s (the thesis' 1/25 s); a whole number of steps
//   gravity: [0, 0, -9.81]           # m/s^2 in the leg's frame (z up the leg, x forward)
//   terms: [springs, dampers, repulsion, volume, gravity]   # optional
//   nonlinear_threshold: 0.7         # thesis 5.8
//   materials:                       # physical constants (tissue_material.hpp)
//     passive: {density: 920, youngs_modulus: 15000, damping_time: 4.2e-3,
//               repulsion_factor: 0.5, volume_factor: 1.6}
//     muscle:  {density: 1040, youngs_modulus: 75000, ...}
//   knee:
//     centre: [0, 0, 0.50046]        # m, required
//     axis: [0, 1, 0]                # positive rotation = flexion
//     range_deg: [0, 137.5]          # hard stops
//     initial_angle_deg: 0
//     initial_velocity_deg: 0        # deg/s
//     angle_deg: [[0, 0], [2, 90]]   # kinematic override: [t, deg] keyframes, linear
//     release: 2.5                   # s: the override ends here and the knee moves dynamically
//     torque: [[0, 0], [1, 5]]       # added joint torque: [t, N m] keyframes
//     damping: 1.0                   # the knee's passive structures, N m s/rad
//     limit_stiffness: 0             # N m/rad beyond passive_range_deg
//     passive_range_deg: [0, 120]
//     joint_space_radius: 0.04       # m: also leave out tets squeezed between the bones (leg_model.hpp)
//   tendons:
//     modulus: 36.4e6                # Pa (thesis: 0.8e6 softened; real 1.2e9)
//     strand_area: 2.0e-5            # m^2 per strand
//     insertions: path               # bone ends at the paths' last points (default), or "nodes":
//                                    # at the bone node the route reached (the thesis)
//     moduli: {front_lower: 0.8e6}   # per-tendon overrides (Pa)
//     engage_at: 2.0                 # s: slack until then; then natural length = the path's length
//     pretension: {fraction: 0.3, start: 0, duration: 0.5}   # L0 -> (1 - fraction) L0, linearly
//   muscles:
//     max_stress: 1.0e6              # Pa
//     force_length_zero: 0.2         # lambda_0 of the force-length relation; "none": the thesis' constant force
//     unit_angle_deg: 30
//     front_line: [0, 0, 1]
//     back_line: [0, 0, 1]
//     script: ../scripts/hamstrings.txt   # thesis 5.7 format; muscles FRONT_MUSCLE, BACK_MUSCLE
//     activation: {front: 0.3, back: 0.3} # or constant activations
//   contact:
//     knee: {lo: [x, y, z], hi: [x, y, z]}   # skin against skin behind the knee
//     obstacles:
//       - {name: rod, shape: cylinder, point: [x, y, z], axis: [0, 1, 0], radius: 0.04,
//          response: stick, box: {lo: [...], hi: [...]}, motion: [[t, dx, dy, dz], ...]}
//       - {name: table, shape: plane, point: [...], normal: [...]}
//   analysis:
//     from: 2.0                       # s: the summary's extremes from here on (after a lead-in)
//     bulge: [{name: knee_sides, lo: [...], hi: [...]}]   # skin areas whose bulge is reported
//     drop: {release: 0}              # pendulum metrics of the knee angle after `release`
//     wobble: {probe: {lo: [...], hi: [...]}, after: 0.3}   # the flesh in the box, after t
//   variants:                         # runs of the same scene differing in activation
//     - {name: relaxed, activation: {front: 0, back: 0}}
//   outputs: {obj_every: 1}           # an OBJ of the skin every n-th frame (0: none)
//
// What a run writes into DIR (or DIR/VARIANT): leg.h5 (benchmarks/RESULTS.md
// layout: /series every output interval - time, knee angle and velocity,
// torques, joint reaction, activations, tendon tensions, volume ratios,
// contact area and obstacle forces, energies, bulges, muscle shape, tendon
// straightness; /fields nodes and skin frames), leg.csv, leg.xdmf (ParaView:
// the tissue's tets and the embedded skin over time), skin/frame_NNNN.obj and,
// last, summary.json.
#pragma once

#include "msd/control/activation_script.hpp"
#include "msd/scene/leg_model.hpp"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bench {

/// Piecewise-linear keyframes, held constant before the first and after the last.
template <class T>
struct Keyframes {
  std::vector<double> time;
  std::vector<T> value;
  bool empty() const { return time.empty(); }
  T at(double t) const;
  T rate(double t) const;  ///< slope of the segment holding t (zero outside)
};

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
  std::string geometry;  ///< mesh scene (YAML)
  bool mesh_pull = true; ///< false: the geometry's pull areas are ignored
  double duration = 0.0, dt = 0.0, output_interval = 0.04;
  msd::LegModelOptions model;
  double initial_angle = 0.0, initial_velocity = 0.0;  ///< rad, rad/s
  Keyframes<double> knee_angle;                        ///< rad; empty: dynamic knee
  std::optional<double> knee_release;                  ///< s: after it the knee is dynamic
  Keyframes<double> joint_torque;                      ///< N m
  bool insert_at_path_end = true;
  std::optional<double> tendons_engage_at;
  double pretension_fraction = 0.0, pretension_start = 0.0, pretension_duration = 0.0;
  std::optional<msd::ActivationScript> script;
  std::string script_path;
  double front_activation = 0.0, back_activation = 0.0;  ///< when there is no script
  std::vector<Keyframes<msd::Vec3>> obstacle_motion;     ///< per obstacle, offsets (m)
  double analysis_from = 0.0;
  std::vector<LegBox> bulge_areas;
  std::optional<double> drop_release;
  std::optional<LegBox> wobble_probe;
  double wobble_after = 0.0;
  std::vector<LegVariant> variants;
  int obj_every = 1;
};

/// Reads a scene. Throws msd::Error "FILE:LINE:COL: field: what" for a missing
/// or unknown field, a value out of range, a script with errors (its own
/// file and line), or an output interval that is not a whole number of steps.
LegScene read_leg_scene(const std::string& path);

/// The summary of one run (one variant): what summary.json holds.
struct LegRunSummary {
  std::string name, variant, dir, status = "complete", failure;
  double simulated = 0.0, wall_seconds = 0.0;
  long steps = 0, frames = 0, nodes = 0, tets = 0;
  /// Scalar results by name (knee angles in degrees, areas in m^2, ...).
  std::map<std::string, double> values;
  /// Knee angle (deg) every 0.2 s: (time, angle).
  std::vector<std::pair<double, double>> trajectory;
  double wall_per_simulated() const { return simulated > 0.0 ? wall_seconds / simulated : 0.0; }
};

/// Runs every variant of the scene (or the scene once) into out_dir. A blow-up
/// is not thrown: its run's summary says failed, when, where and why, and its
/// files keep every frame written before it. `progress(t, end)` is called
/// now and then.
std::vector<LegRunSummary> run_leg_scene(const LegScene& scene, const std::string& out_dir,
                                         const std::function<void(double, double)>& progress = {});

/// The lines the command prints for a run.
std::string format_leg_summary(const LegRunSummary& s);

}  // namespace bench
