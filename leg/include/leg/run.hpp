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
  int interrupted = 0;  ///< the signal that stopped the run (SIGINT, SIGTERM), 0 when none
  bool kept = true;     ///< false when not even a failed leg.h5 could be written (a full disk)
  double simulated = 0.0, wall_seconds = 0.0;
  long steps = 0, frames = 0, nodes = 0, tets = 0;
  long newton_iterations = 0, step_cuts = 0, factorizations = 0;  ///< backward Euler's, over the run (since a resume)
  /// Scalar results by name (knee angles in degrees, areas in m^2, ...).
  std::map<std::string, double> values;
  /// What the run did that the user must know (e.g. a tendon strained past
  /// failure); in summary.json's "warnings" and printed.
  std::vector<std::string> warnings;
  /// Knee angle (deg) every 0.2 s: (time, angle).
  std::vector<std::pair<double, double>> trajectory;
  double wall_per_simulated() const { return simulated > 0.0 ? wall_seconds / simulated : 0.0; }
};

/// Checkpoints of a leg run (tbio/checkpoint.hpp): DIR/leg.checkpoint every
/// `every` simulated seconds (at a recorded frame), removed when the run
/// completes; `resume` continues from one (bit-identical results). With
/// variants each checkpoints into its own folder, and a resume runs the
/// variants before the checkpoint's again (deterministic) and continues it.
struct LegCheckpointing {
  double every = 0.0;
  std::string resume;
};

/// The checkpoint file of a run into `dir`: DIR/leg.checkpoint.
std::string leg_checkpoint_path(const std::string& dir);

/// Runs every variant of the scene (or the scene once) into out_dir, holding
/// the lock OUT_DIR.lock (a second run into it is refused). A blow-up, a write
/// failure or SIGINT/SIGTERM is not thrown: its run's summary says failed,
/// when, where and why (`interrupted`: the signal; later variants are not
/// run), and its files keep every frame written before it. leg.h5 and its CSV
/// are written under temporary names and renamed into place at the end (an
/// existing run's files are untouched until then). `progress(t, end)` is
/// called now and then.
std::vector<LegRunSummary> run_leg_scene(const LegScene& scene, const std::string& out_dir,
                                         const std::function<void(double, double)>& progress = {},
                                         const LegCheckpointing& cp = {});

/// The lines the command prints for a run.
std::string format_leg_summary(const LegRunSummary& s);

}  // namespace leg
