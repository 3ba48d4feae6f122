// The comparison of an MSD results file with an FEM results file of the same
// spec: the load curve over the whole path and over the tissue working range,
// the volume ratio, the displacement field at the MSD nodes, and the ring-down
// frequency and damping. Keys of the JSON form are stable (benchmarks/RESULTS.md);
// reports and the CI guard read them.
#pragma once

#include "bench/loading.hpp"

#include <limits>
#include <string>

namespace bench {

struct Comparison {
  std::string spec;
  Loading loading = Loading::Uniaxial;
  std::string load_series;      ///< the compared load curve, e.g. nominal_stress
  std::string units;
  long points = 0;              ///< FEM report times inside the MSD run
  double load_rms_fem = 0.0;    ///< RMS of the FEM curve (the relative errors' scale)
  double load_rel_rms = std::numeric_limits<double>::quiet_NaN();
  /// Over the working range |strain| <= 0.4 (thesis 5.2.6; uniaxial and shear).
  double load_rel_rms_working = std::numeric_limits<double>::quiet_NaN();
  double load_max_abs_error = std::numeric_limits<double>::quiet_NaN();
  double volume_ratio_max_error = std::numeric_limits<double>::quiet_NaN();
  /// Displacement at the MSD nodes against the FEM solution at their rest
  /// positions, relative to the largest FEM displacement over the frames.
  double displacement_rel_rms = std::numeric_limits<double>::quiet_NaN();
  double displacement_rel_max = std::numeric_limits<double>::quiet_NaN();
  long nodes_compared = 0, nodes_outside = 0, frames_compared = 0;
  double frequency_msd = std::numeric_limits<double>::quiet_NaN();
  double frequency_fem = std::numeric_limits<double>::quiet_NaN();
  double frequency_rel_error = std::numeric_limits<double>::quiet_NaN();
  double damping_ratio_msd = std::numeric_limits<double>::quiet_NaN();
  double damping_ratio_fem = std::numeric_limits<double>::quiet_NaN();
  double damping_ratio_abs_error = std::numeric_limits<double>::quiet_NaN();
  /// Cost of each run (wall s per simulated s, from the files' /timing).
  double msd_cost = std::numeric_limits<double>::quiet_NaN();
  double fem_cost = std::numeric_limits<double>::quiet_NaN();
  /// The same in CPU seconds of the solving process (/timing/cpu_seconds).
  double msd_cpu_cost = std::numeric_limits<double>::quiet_NaN();
  double fem_cpu_cost = std::numeric_limits<double>::quiet_NaN();
  /// msd / fem: a speed figure both solvers measured on the same machine, in
  /// CPU time when both files record it (another job sharing the cores
  /// stretches wall time, not CPU time), else in wall time.
  double cost_ratio = std::numeric_limits<double>::quiet_NaN();
};

/// The load curve a loading is judged by (loading_info's load_series):
/// nominal_stress (uniaxial), shear_stress (simple_shear), tip_displacement
/// (vibration), indentation_force (indentation), tip_displacement_z (static:
/// the default; a comparison picks the component the FEM moves most along);
/// "" otherwise.
std::string load_series_name(Loading loading);

/// Compares two complete results files (msd first). Throws msd::Error when a
/// file is missing, incomplete, of the wrong solver or of a different loading.
/// `displacement_field` false skips the field comparison (an MSD run on another
/// mesh than the one the FEM probed).
Comparison compare_results(const std::string& msd_file, const std::string& fem_file,
                           bool displacement_field = true);

void write_comparison_json(const Comparison& c, const std::string& path);

/// A short human-readable table.
std::string format_comparison(const Comparison& c);

}  // namespace bench
