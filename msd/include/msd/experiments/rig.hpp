// Building blocks of the virtual material tests: the faces of a sample, loads
// spread over a face, probes, and one time loop that drives any test through
// its controls (prescribed motion, load factor) and samples it at output times.
#pragma once

#include "msd/integrate/step.hpp"
#include "msd/mesh/tet_mesh.hpp"
#include "msd/model/model.hpp"

#include <functional>
#include <string>
#include <vector>

namespace msd {

/// The six faces of a sample's bounding box: left/right (x min/max),
/// front/back (y), bottom/top (z).
enum class Face { Left = 0, Right = 1, Front = 2, Back = 3, Bottom = 4, Top = 5 };
Face parse_face(const std::string& name);
std::string to_string(Face face);

/// Nodes lying on the plane of `face` (within 1e-9 of the sample's size).
std::vector<int> face_nodes(const TetMesh& mesh, Face face);

/// Rest area of the boundary triangles whose three nodes are all in `nodes`.
double face_area(const TetMesh& mesh, const std::vector<int>& nodes);

/// A total force spread over the boundary triangles of `nodes` in proportion to
/// area (each triangle gives a third of its share to each vertex), as the
/// consistent nodal loads of a uniform dead traction on linear elements.
Points face_load(const TetMesh& mesh, const std::vector<int>& nodes, const Vec3& total_force);

/// Index of the node nearest p.
int nearest_node(const Points& x, const Vec3& p);

/// Total signed volume of the model's elements at positions x (3 x N, m^3)
/// and how many of them are inverted or flat (signed volume <= 0).
struct ElementVolumes {
  double volume = 0.0;
  int inverted = 0;
};
ElementVolumes element_volumes(const Model& model, const Points& x);

/// What every test samples of the whole body: volume ratio V/V0 (against
/// `rest_volume`), inverted elements, kinetic energy (J).
struct BulkSample {
  double volume_ratio = 1.0;
  int inverted_elements = 0;
  double kinetic_energy = 0.0;
};
BulkSample measure_bulk(const Model& model, const State& state, double rest_volume);

/// Force on a node from everything but its constraints: the internal forces in
/// scratch.f plus the dead loads (external forces and gravity) at `load_scale`.
/// Its negative is what a support or a contact must supply to hold the node.
Vec3 applied_force(const Model& model, const Scratch& scratch, double load_scale, int node);

struct TimeSteppingOptions {
  double dt = 1e-4;
  Integrator integrator = Integrator::SymplecticEuler;
  double output_interval = 0.01;
  /// A node moving farther than this many sample sizes from rest is a blow-up
  /// (and the other limits of msd/experiments/blowup.hpp).
  double blowup_factor = 10.0;
};

struct RunStats {
  long steps = 0;
  double simulated_seconds = 0.0;
  long newton_iterations = 0;  ///< backward Euler: Newton iterations over the run
  long step_cuts = 0;          ///< backward Euler: steps halved because Newton failed
  long factorizations = 0;     ///< backward Euler: LU factorisations (fewer than iterations with reuse)
};

struct ExperimentHooks {
  /// Controls at time t (prescribed group motion, load factor).
  std::function<Controls(double t)> controls;
  /// Called at t = 0, every output interval and at the end, with the state and
  /// scratch (evaluate forces into it as needed); false stops the run.
  std::function<bool(const State&, Scratch&)> sample;
  /// Optional: called after each sample with the loop's position (the step
  /// index k of `state` and the outputs taken so far) - where a checkpoint is written.
  std::function<void(const State&, long step, long outputs)> after_sample;
};

/// Where run_experiment continues from a checkpoint: `state` is the state at
/// step `step`, already sampled, with `outputs` outputs taken.
struct LoopPosition {
  long step = 0;
  long outputs = 0;
};

/// Integrates from `initial` to end_time. Throws SimulationFailure on a
/// non-finite value or a blow-up (BlowUpLimits, checked at every output: a
/// node farther than blowup_factor * size, too fast, or too much kinetic
/// energy), msd::Interrupted at the next step after SIGINT/SIGTERM
/// (msd/io/interrupt.hpp). With `resume`, `initial` is a checkpoint's state at
/// resume->step (not constrained again, not sampled again) and the run
/// continues bit-identically.
RunStats run_experiment(const Model& model, State initial, double end_time, double size,
                        const TimeSteppingOptions& options, const ExperimentHooks& hooks,
                        const LoopPosition* resume = nullptr);

}  // namespace msd
