// Calibration of a tissue's MSD constants against the FEM reference of the same
// material (the thesis tuned its constants by hand, 5.2): the stiffness scale,
// repulsion factor and volume factor of the physical constants are fitted to
// the FEM over the uni-axial and shear calibration specs together.
//
// Objective: the sum over the calibration specs of
//     sum_i ((y_msd(t_i) - y_fem(t_i)) / rms(y_fem))^2 / N
// over the FEM report times t_i (y: nominal stress, shear stress), plus for the
// uni-axial spec sum_i (w (V_msd - V_fem))^2 / N with the volume weight w
// (default 2: a volume-ratio error of 0.05 weighs like a stress error of 10 %
// of the FEM curve's RMS) - so the fit also keeps the volume, which the stress
// alone barely sees. Optimiser: Eigen's
// Levenberg-Marquardt (unsupported/Eigen/NonLinearOptimization, MINPACK lmder)
// with forward-difference Jacobians. Bounds that keep the explicit model stable
// at the calibration specs' time steps are imposed by the change of variables
// p = lo + (hi - lo) / (1 + exp(-q)).
// Damping is not fitted: the FEM references of the calibration tests are
// quasi-static (no viscous stress to fit it to; the MSD dampers add about 2-3 %
// of the elastic stress at the turning points of these paths). The material's
// damping_time is kept and its effect measured on the held-out vibration test.
#pragma once

#include "bench/spec.hpp"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace bench {

struct CalibrationParameters {
  double stiffness_scale = 1.0;
  double repulsion_factor = 0.1;
  double volume_factor = 1.0;
};

struct CalibrationBounds {
  double scale_lo = 0.2, scale_hi = 5.0;
  double repulsion_lo = 0.0, repulsion_hi = 2.0;
  double volume_lo = 0.0, volume_hi = 20.0;
};

struct SpecError {
  std::string spec, sha256, load_series;
  double rel_rms_before = 0.0, rel_rms_after = 0.0;  ///< relative RMS of the load curve
  double volume_max_error_before = 0.0, volume_max_error_after = 0.0;
};

struct CalibrationResult {
  std::string material;
  CalibrationParameters before, after;
  double damping_time = 0.0;
  double objective_before = 0.0, objective_after = 0.0;
  double volume_weight = 2.0;
  int iterations = 0, evaluations = 0;
  std::string optimiser_status;
  std::vector<SpecError> specs;
  std::string fem_version, fem_git_revision, created;
};

/// The spec with its msd constants replaced by `p` (physical constants).
Spec with_parameters(const Spec& spec, const CalibrationParameters& p);

/// Series of an MSD run held in memory (no file).
std::map<std::string, std::vector<double>> simulate_msd(const Spec& spec);

/// Fits the parameters for `material` (a benchmarks/materials.yaml entry) on
/// the calibration specs (their material replaced by the library entry). FEM
/// references are written to out_dir. `log` receives one line per evaluation.
CalibrationResult calibrate(const std::string& material, const std::vector<std::string>& spec_files,
                            const std::string& out_dir, const CalibrationBounds& bounds = {},
                            const std::function<void(const std::string&)>& log = {},
                            int max_evaluations = 40, double volume_weight = 2.0);

/// Writes the calibrated set with its provenance (YAML; the msd solver reads it
/// through `msd.calibration` in a spec).
void write_calibration(const CalibrationResult& result, const std::string& path);

/// Reads the parameters of a calibration file (and the material it was fitted
/// for, into *material). Throws msd::Error naming the file.
CalibrationParameters read_calibration(const std::string& path, std::string* material = nullptr);

/// Puts a calibration file's parameters into the spec's msd section (physical
/// constants). The file's material must be the spec's material. `where` is
/// prefixed to messages (the spec field that named the file).
void apply_calibration(Spec& spec, const std::string& file, const std::string& where = "");

}  // namespace bench
