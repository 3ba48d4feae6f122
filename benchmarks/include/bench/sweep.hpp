// The speed-accuracy trade: the MSD model run over a grid of its knobs - mesh
// spacing h, time step, integrator, optional force terms, the 0.7 non-linear
// threshold - each point compared with the FEM reference of the same spec and
// timed. Cost is wall-clock seconds per simulated second and the peak resident
// memory of the point's own process (each point runs as a child
// `tissuebench run`, so the memory is that run's alone). A point is on the
// Pareto front when no other stable point is both cheaper and more accurate.
//
// Time error apart from model error: for every spatial configuration (h, terms,
// threshold) the grid holds a CVODE point (BDF, tight tolerances - the
// exact-in-time trajectory of that spatial model). A fixed-step point's time
// error is its load curve against that CVODE run; the CVODE run's error against
// the FEM is the model error. Both are relative RMS over the FEM load curve's RMS.
//
// Under mpirun -np N the FEM reference is computed by all ranks together, then
// rank r runs the points i with i mod N = r, and rank 0 merges one table.
#pragma once

#include "bench/spec.hpp"

#include <yaml-cpp/yaml.h>

#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace bench {

/// The grid. Empty lists take the defaults noted.
struct SweepGrid {
  std::vector<double> spacing;                ///< m; default: the spec's h and 2h
  std::vector<double> dt;                     ///< s; default: the spec's dt and 2.5 dt
  std::vector<std::string> integrators;       ///< default: symplectic_euler, velocity_verlet, explicit_euler
  std::vector<std::string> term_sets;         ///< all | no_repulsion | no_volume | springs_dampers | continuum | neo_lattice (default: the first four)
  std::vector<double> thresholds;             ///< 0 = off; default: off and 0.7
  bool cvode = true;                          ///< add the CVODE point of each spatial configuration
  /// Add one quasi-static point (msd.integrator: quasi_static, dt = the
  /// spec's output interval, the term set without its dampers - the solve
  /// has no rate) per spatial configuration and term set, when the spec's
  /// loading is static (uni-axial, shear, static): the equilibria the FEM
  /// reference solves. It has no time error (that measures the dynamic run
  /// against CVODE's).
  bool quasi_static = false;
  /// FEM runs besides the reference, as (degree, refinement) on the spec's
  /// coarse cells: their cost and their load-curve error against the
  /// reference go in the same table (the FEM's own speed-accuracy trade).
  std::vector<std::pair<unsigned, unsigned>> fem_levels;
};

/// The msd force terms of a named term set.
std::vector<std::string> term_set(const std::string& name);

/// Sets a spec's msd section (a YAML map) to the term set `name`: its terms,
/// for `continuum` (the neo_hookean term with the dampers) one volume ratio
/// per cube (msd.continuum_volume: per_cube), and for `neo_lattice` (springs,
/// dampers, bulk) zero-length springs (msd.zero_length_springs, no edge
/// classes).
void set_term_set(YAML::Node& msd, const std::string& name);

struct SweepPoint {
  int id = 0;
  double spacing = 0.0, dt = 0.0, threshold = 0.0;
  std::string integrator, terms;
  std::string spec_file, results_file, log_file;  ///< written by the sweep
  // results
  std::string status = "not run";   ///< complete | failed | timeout
  std::string failure;              ///< the failure message of a failed run
  double failure_time = std::numeric_limits<double>::quiet_NaN();
  int tets = 0, nodes = 0;
  long steps = 0;
  double wall_seconds = 0.0, simulated_seconds = 0.0;
  double cost = std::numeric_limits<double>::quiet_NaN();  ///< wall s per simulated s
  double peak_rss_mb = std::numeric_limits<double>::quiet_NaN();   ///< the point's process
  double model_rss_mb = std::numeric_limits<double>::quiet_NaN();  ///< above the process before the model
  double load_rel_rms = std::numeric_limits<double>::quiet_NaN();
  double load_rel_rms_working = std::numeric_limits<double>::quiet_NaN();
  double volume_ratio_max_error = std::numeric_limits<double>::quiet_NaN();
  double displacement_rel_rms = std::numeric_limits<double>::quiet_NaN();
  double frequency_rel_error = std::numeric_limits<double>::quiet_NaN();
  double time_error = std::numeric_limits<double>::quiet_NaN();  ///< against the CVODE point
  int max_inverted = 0;
  bool pareto = false;
  /// The error the Pareto front uses: the working-range load error where the
  /// test has one, else the whole-path load error.
  double error() const;
};

/// The grid's points for `spec` (in a fixed order: h, terms, threshold,
/// integrator, dt; each spatial configuration's CVODE point after its
/// fixed-step points). Throws msd::Error on an empty or invalid grid.
std::vector<SweepPoint> sweep_points(const Spec& spec, const SweepGrid& grid);

/// The spec text of one point (the spec with the point's knobs set; relative
/// file references made absolute).
std::string point_spec_text(const Spec& spec, const SweepPoint& p);

/// Marks the Pareto front (minimum cost and error) among complete points.
void mark_pareto(std::vector<SweepPoint>& points);

/// Fills the time errors (fixed-step points against the CVODE point of their
/// spatial configuration) from the points' results files: RMS difference of
/// `load_series` (the series the FEM comparison used) over `load_rms_fem`.
void fill_time_errors(std::vector<SweepPoint>& points, const std::string& load_series, double load_rms_fem);

struct FemCostRow {
  std::string label;           ///< e.g. "Q2-P1-P1 (condensed)"
  unsigned degree = 0, refinement = 0;
  /// Relative RMS difference of the load curve from the reference's (0 for
  /// the reference itself).
  double load_rel_rms = std::numeric_limits<double>::quiet_NaN();
  unsigned long dofs = 0, cells = 0;
  double wall_seconds = 0.0, simulated_seconds = 0.0, cost = 0.0;
  double peak_rss_mb = std::numeric_limits<double>::quiet_NaN();
  std::string results_file;
};

struct SweepResult {
  std::string spec, spec_path, load_series, reference_file;
  double load_rms_fem = 0.0;
  double baseline_rss_mb = 0.0;   ///< peak memory of a tissuebench process that runs nothing
  std::vector<SweepPoint> points;
  FemCostRow fem;
  std::vector<FemCostRow> fem_levels;   ///< SweepGrid::fem_levels, in order
  int ranks = 1;
};

struct SweepOptions {
  std::string out_dir;
  std::string executable;         ///< the tissuebench binary run for each point
  std::string reference;          ///< an existing FEM results file ("" = compute into out_dir)
  double point_timeout = 0.0;     ///< s of wall time per point before it is stopped (0 = none)
  std::function<void(const std::string&)> log;
};

/// Runs the sweep (collective under MPI). Returns the merged result on rank 0
/// (other ranks: an empty result).
SweepResult run_sweep(const Spec& spec, const SweepGrid& grid, const SweepOptions& options);

void write_sweep_json(const SweepResult& r, const std::string& path);
void write_sweep_csv(const SweepResult& r, const std::string& path);
std::string format_sweep(const SweepResult& r);

}  // namespace bench
