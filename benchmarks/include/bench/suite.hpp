// The standard set ("the main job"): every comparison benchmark of a tier run
// by the FEM reference and by the MSD model in several variants - the thesis'
// raw constants, our physical (uncalibrated) constants, and the shipped
// calibration of the material - each compared with the FEM; a small
// speed-accuracy sweep with the FEM's own levels; the stability extremes; and
// the FEM verification status (closed forms, a published benchmark, a
// refinement study). Tiers are YAML files (benchmarks/suites/TIER.yaml, fields
// in benchmarks/suites/README.md). Everything lands in one folder with a
// manifest, DIR/suite.json, that the report (reports/make_report.py) and the
// regression guard (`tissuebench check`) read.
#pragma once

#include "bench/msd_runner.hpp"
#include "bench/spec.hpp"
#include "tbio/json.hpp"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace bench {

/// MSD variants the suite can run.
///  - thesis: raw constants of the thesis' element (k_s 10.75 N/m, k_d 0.2 N s/m,
///    k_r 3 N/m, k_v 50 N/m), equal mass lumping, explicit Euler, all terms on;
///  - physical: the spec as shipped (constants from E and h);
///  - calibrated: the spec with benchmarks/calibration/MATERIAL.yaml;
///  - lattice: the spec with benchmarks/calibration/MATERIAL_lattice.yaml, the
///    fit with the edge classes (calibrate --edge-classes);
///  - continuum: the stable neo-Hookean tet with cube volumes (the model ladder's top rung).
Spec suite_variant(const Spec& spec, const std::string& variant, const std::string& calibration_dir);

struct SuiteTier {
  std::string name, description, file;
  std::vector<std::string> variants;
  struct Benchmark {
    std::string spec;          ///< file, relative to the specs folder
    std::string edit_yaml;     ///< YAML merged into the spec (quick-tier resolution), "" = none
  };
  std::vector<Benchmark> benchmarks;
  struct Sweep {
    std::string spec;
    std::vector<double> spacing, dt;
    std::vector<std::string> integrators, terms;
    std::vector<double> thresholds;  ///< 0 = off
    std::vector<std::pair<unsigned, unsigned>> fem_levels;
    double point_timeout = 0.0;
    bool quasi_static = false;  ///< SweepGrid::quasi_static
    bool cvode = true;          ///< SweepGrid::cvode (false: no CVODE points, no time errors)
  };
  std::vector<Sweep> sweeps;
  struct Stability {
    std::string spec;
    std::vector<std::string> integrators, terms;
    bool dt_search = false, extremes = true;
  };
  std::vector<Stability> stability;
  std::vector<std::string> verification;  ///< verify_*.yaml specs with closed forms / published values
  struct Convergence {
    std::string spec;
    std::vector<int> levels;
    unsigned degree = 1;
    std::string edit_yaml;
  };
  std::vector<Convergence> convergence;
  /// Leg scenes (files, relative to the scenes folder) run whole into
  /// DIR/leg/SCENE, for the report's leg section.
  std::vector<std::string> leg;
};

/// Reads a tier file; errors name the file and field.
SuiteTier load_tier(const std::string& path);

struct SuiteOptions {
  std::string out_dir;
  std::string specs_dir;         ///< where tier specs are looked up
  std::string calibration_dir;   ///< benchmarks/calibration
  std::string executable;        ///< tissuebench, for the sweep's child runs
  std::function<void(const std::string&)> log;
  std::function<Progress(const std::string& label)> progress;  ///< a progress callback per run
  /// The leg layer, given by the program (the harness does not depend on it):
  /// `check_leg` reads a scene and throws msd::Error for bad input; `run_leg`
  /// runs one into a folder and returns its manifest entry ({scene, scene_file,
  /// dir, status, runs: [{variant, dir, status, failure, wall_per_simulated_second}]},
  /// dir relative to out_dir). Needed when the tier lists leg scenes.
  std::string scenes_dir;  ///< where tier leg scenes are looked up
  std::function<void(const std::string& scene_file)> check_leg;
  std::function<tbio::Json(const std::string& scene_file, const std::string& out_dir, const Progress& progress)> run_leg;
};

/// Runs the tier; writes DIR/suite.json (and everything it lists). Returns the
/// number of MSD runs that failed (blow-ups are results, not errors). Throws
/// msd::Error on bad input before anything runs, or when an FEM reference fails.
int run_suite(const SuiteTier& tier, const SuiteOptions& options);

/// The machine and tool versions recorded as provenance (a JSON object).
tbio::Json provenance_json();

}  // namespace bench
