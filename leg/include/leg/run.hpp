// `tissuebench leg SCENE.yaml --out DIR`: the leg in motion (thesis 6). Runs
// each variant of a scene - the drive sets the controls, msd::step_leg steps,
// the sensors record every output interval - and writes its outputs
// (leg/outputs.hpp) and summary (leg/analysis.hpp).
#pragma once

#include "leg/scene.hpp"

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace leg {

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

}  // namespace leg
