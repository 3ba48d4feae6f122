// Mesh-refinement studies of the FEM reference: run one spec at several
// refinement levels, compare the main load curve between consecutive levels,
// and estimate the observed order of convergence and the error of the finest
// level by Richardson extrapolation. This estimate is what "ground truth" means
// in every report.
#pragma once

#include "bench/msd_runner.hpp"
#include "bench/spec.hpp"

#include <string>
#include <vector>

namespace bench {

struct ConvergenceLevel {
  int level = 0;
  unsigned degree = 1;
  unsigned refinement = 0;
  std::array<unsigned, 3> cells{{0, 0, 0}};
  RunSummary run;
  std::vector<double> values;   ///< the study quantity at each report time (or one value)
};

struct ConvergenceStudy {
  std::string spec_name;
  std::string quantity;          ///< e.g. nominal_stress, tip_displacement, first_frequency
  std::string units;
  std::vector<ConvergenceLevel> levels;
  /// differences[k]: RMS over report times of (level k+1 - level k).
  std::vector<double> differences;
  double scale = 0.0;            ///< max |value| on the finest level
  double observed_order = 0.0;   ///< log2(d[n-2] / d[n-1]) (0 with fewer than 3 levels)
  double finest_error = 0.0;     ///< d[n-1] / (2^p - 1): estimated RMS error of the finest level
  double finest_relative_error = 0.0;  ///< finest_error / scale
};

/// The spec at a refinement level: boxes and cylinders get `level` global
/// refinements of their coarse mesh, Cook's membrane 2^level times the spec's
/// coarse cells per side.
Spec refined_spec(const Spec& spec, int level, unsigned degree);

/// Runs the levels (each writes OUT_DIR/NAME_pP_lL.h5). Throws if a level fails.
ConvergenceStudy run_convergence(const Spec& spec, const std::vector<int>& levels, unsigned degree,
                                 const std::string& out_dir, const Progress& progress = {});

/// The value of largest magnitude (0 for an empty series).
double peak(const std::vector<double>& values);

/// Writes the study as JSON (stable keys, documented in benchmarks/RESULTS.md).
void write_convergence_json(const ConvergenceStudy& study, const std::string& path);

}  // namespace bench
