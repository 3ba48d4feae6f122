// Binds a Spec to the msd library: builds the sample geometry and mesh, the
// model with the spec's terms and constants, the rig of the spec's loading
// (platens, clamp, loads, initial state), runs it and writes the results file.
#pragma once

#include "bench/cvode_integrator.hpp"
#include "bench/loading.hpp"
#include "bench/shared_io.hpp"
#include "bench/spec.hpp"
#include "msd/experiments/indentation.hpp"
#include "msd/experiments/shear.hpp"
#include "msd/experiments/static_load.hpp"
#include "msd/experiments/uniaxial.hpp"
#include "msd/geometry/triangle_mesh.hpp"
#include "msd/mesh/cubic_grid.hpp"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace bench {

/// The spec's msd section; throws if the spec lacks what the msd solver needs.
const MsdSpec& msd_section(const Spec& spec);

/// The closed surface a spec's geometry describes.
msd::TriangleMesh make_surface(const GeometrySpec& g);

/// The spec's sample meshed on the cubic grid.
msd::SampleMesh make_sample_mesh(const Spec& spec);

/// The spec's material as msd constants.
msd::TissueMaterial make_material(const Spec& spec);

/// Everything needed to run the spec's test with the MSD model.
struct MsdProblem {
  msd::SampleMesh sample;
  msd::Model model;
  msd::LoadingPath path;              ///< strain, shear strain or load factor
  msd::TimeSteppingOptions stepping;
  Loading loading = Loading::Uniaxial;
  msd::UniaxialSetup platens;         ///< uniaxial, simple_shear
  msd::ClampSetup clamp;              ///< static, vibration
  msd::IndentationSetup indenter;     ///< indentation
  msd::State initial;
  double size = 0.0;                  ///< for the blow-up guard, m
  std::vector<SeriesColumn> columns;  ///< series_columns(loading, Solver::Msd)
  bool cvode = false;                 ///< integrate with CVODE instead of `stepping`
  CvodeOptions cvode_options;
};

MsdProblem compile_msd(const Spec& spec);

/// Runs the problem's time loop with its integrator (fixed step or CVODE).
/// Throws msd::SimulationFailure as msd::run_experiment.
msd::RunStats integrate_msd(const MsdProblem& p, const msd::ExperimentHooks& hooks);

/// The loading's controls and one results row per sample; `frame` (optional)
/// sees the state at every sample first.
msd::ExperimentHooks msd_hooks(const MsdProblem& p, const std::function<bool(const std::vector<double>&)>& row,
                               const std::function<void(const msd::State&)>& frame = {});

/// The material constants actually used, for /meta/material.
std::vector<std::pair<std::string, double>> material_record(const Spec& spec,
                                                            const msd::Model& model);

struct RunSummary {
  std::string name;
  std::string solver = "msd";
  Loading loading = Loading::Uniaxial;
  bool complete = false;
  std::string failure;
  std::string out_path;
  int nodes = 0, tets = 0;            ///< msd
  long cubes = 0;                     ///< msd
  unsigned long dofs = 0, cells = 0;  ///< fem
  /// Named key results for the summary table (e.g. "f1_Hz", "tip_mm").
  std::vector<std::pair<std::string, double>> highlights;
  long steps = 0;
  long newton_iterations = 0, step_cuts = 0;  ///< backward Euler only
  long factorizations = 0;                   ///< backward Euler only: LU factorisations
  double wall_seconds = 0.0;
  double simulated_seconds = 0.0;
  double min_strain = 0.0, max_strain = 0.0;
  double min_stress = 0.0, max_stress = 0.0;       ///< Pa
  double min_volume_ratio = 1.0, max_volume_ratio = 1.0;
  int max_inverted = 0;
  int interrupted = 0;  ///< the signal that stopped the run (SIGINT, SIGTERM), 0 when none
  bool kept = true;     ///< false when not even a failed file could be written (a full disk)
};

/// Positions in a loading's /series of what a RunSummary tracks (-1: absent).
struct SummaryColumns {
  int strain = -1, stress = -1, volume_ratio = -1, inverted_elements = -1;
};

/// The loading's strain and stress columns (loading_info) and the volume ratio
/// and inverted elements, where `columns` hold them.
SummaryColumns summary_columns(Loading loading, const std::vector<SeriesColumn>& columns);

/// Widens the summary's strain, stress and volume-ratio ranges and raises its
/// largest count of inverted elements by one results row.
void track_row(RunSummary& s, const SummaryColumns& c, const std::vector<double>& row);

/// Progress callback: simulated time reached and the run's end time.
using Progress = std::function<void(double t, double end)>;

/// Checkpoints of an MSD run (tbio/checkpoint.hpp).
struct Checkpointing {
  double every = 0.0;  ///< simulated seconds between checkpoints; 0: none
  std::string path;    ///< where they are written; empty: checkpoint_path_for(out)
  std::string resume;  ///< a checkpoint to continue from; empty: start at t = 0
};
/// OUT.checkpoint.
std::string checkpoint_path_for(const std::string& out_path);

/// Runs the spec with the MSD model, writing `out_path` (HDF5) and its CSV twin
/// (under temporary names, renamed into place at the end; tbio::ResultsWriter).
/// Bad input, a bad checkpoint or a busy output throws msd::Error before any
/// file is created. A simulation failure, a write failure, or SIGINT/SIGTERM
/// (inside the time loop) is recorded in the file (status "failed") and
/// returned in the summary (`interrupted`, `kept`). With checkpointing, a
/// checkpoint is written every `cp.every` simulated seconds (at an output
/// time) and removed when the run completes; a run resumed from one writes
/// results bit-identical to an uninterrupted run. The CVODE integrator cannot
/// be checkpointed (refused).
RunSummary run_msd(const Spec& spec, const std::string& out_path, const Progress& progress = {},
                   const Checkpointing& cp = {});

}  // namespace bench
