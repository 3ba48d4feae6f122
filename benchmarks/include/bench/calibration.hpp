// Calibration of a tissue's MSD constants against the FEM reference of the same
// material (the thesis tuned its constants by hand, 5.2): the stiffness scale,
// repulsion factor and volume factor of the physical constants are fitted to
// the FEM over the uni-axial and shear calibration specs together (stage 1),
// then the MSD dampers' time constant to a ring-down (stage 2, below).
//
// Objective of stage 1: the sum over the calibration specs of
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
// With the edge classes (calibrate(..., edge_classes = true); the CLI's
// --edge-classes; issue 17), stage 1 fits two more lattice parameters with
// the three factors: the cube edges' stiffness relative to the face
// diagonals' (msd.edge_classes.axis.stiffness; face_diagonal keeps 1 and
// stiffness_scale the level) and one compression exponent n of the spring law
// on both classes (tension exponent 1; msd/forces/spring_law.hpp). The fit
// starts there from the Cauchy-Born isotropic lattice, axis 0.5, and n = 1.
// Damping (stage 2): the quasi-static references above cannot identify it (the
// FEM has no rate there; the MSD dampers add 2-3 % of the elastic stress at the
// turning points), so a dynamic calibration specimen does - a spec with loading
// type vibration (calibrate_ringdown.yaml: the calibration cylinder stretched
// by a dead load on its top, released, ringing down). With the elastic factors
// of stage 1 fixed, the MSD dampers' time constant (msd.damping_time: k_d =
// damping_time k_s) is fitted by the same Levenberg-Marquardt method to the
// residual (zeta_msd - zeta_fem) / zeta_fem of the ring-down's damping ratio
// (bench::analyse_ring_down of the free end's axial motion after the release),
// bounded by the same logistic map to [damping_lo, damping_hi]. Stage 2 after
// stage 1 because zeta = omega tau / 2 for stiffness-proportional damping: the
// damping ratio depends on the fitted stiffness, while the quasi-static fit
// barely depends on tau. Without a vibration spec among the calibration specs,
// damping is not fitted and the material's damping_time is kept.
#pragma once

#include "bench/spec.hpp"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace bench {

struct CalibrationParameters {
  double stiffness_scale = 1.0;
  double repulsion_factor = 0.1;
  double volume_factor = 1.0;
  /// s, the MSD dampers' time constant (msd.damping_time); empty: the material's.
  std::optional<double> damping_time;
  /// The lattice's edge classes (empty: not fitted, the thesis' springs):
  /// msd.edge_classes.axis.stiffness, and the compression exponent of both
  /// classes' spring law (tension exponent 1).
  std::optional<double> axis_stiffness, compression_exponent;
};

struct CalibrationBounds {
  double scale_lo = 0.2, scale_hi = 5.0;
  double repulsion_lo = 0.0, repulsion_hi = 2.0;
  double volume_lo = 0.0, volume_hi = 20.0;
  double damping_lo = 0.0, damping_hi = 0.03;  ///< s (the materials' damping_time is 4.2 ms)
  double axis_lo = 0.2, axis_hi = 2.0;         ///< the cube edges' stiffness over the face diagonals'
  double exponent_lo = 0.0, exponent_hi = 4.0; ///< the spring law's compression exponent
};

/// Where a fit starts instead of the spec's constants (calibrate --start): a
/// calibration file's parameters. The elastic ones start stage 1 (which keeps
/// the material's damping_time, as a fit from the spec's constants does); its
/// damping_time, when it has one, starts stage 2.
struct CalibrationStart {
  CalibrationParameters parameters;
  std::string file;      ///< named in messages and in the written file
  std::string material;  ///< the file's; must be the fit's
};

struct SpecError {
  std::string spec, sha256;
  std::string load_series;  ///< the fitted series; "damping_ratio" for a ring-down spec
  /// Relative RMS of the load curve; for a ring-down spec |zeta_msd - zeta_fem| / zeta_fem.
  double rel_rms_before = 0.0, rel_rms_after = 0.0;
  double volume_max_error_before = 0.0, volume_max_error_after = 0.0;
  /// Ring-down specs: damping ratio and first frequency (Hz), FEM and MSD.
  double damping_ratio_fem = 0.0, damping_ratio_before = 0.0, damping_ratio_after = 0.0;
  double frequency_fem = 0.0, frequency_before = 0.0, frequency_after = 0.0;
  bool ring_down() const { return load_series == "damping_ratio"; }
};

struct CalibrationResult {
  std::string material;
  CalibrationParameters before, after;  ///< before.damping_time: the material's
  double objective_before = 0.0, objective_after = 0.0;  ///< stage 1 (the quasi-static specs)
  double volume_weight = 2.0;
  int iterations = 0, evaluations = 0;
  std::string optimiser_status;
  /// Stage 2: whether damping was fitted (a ring-down spec was given), and how.
  bool damping_fitted = false;
  double damping_objective_before = 0.0, damping_objective_after = 0.0;
  int damping_iterations = 0, damping_evaluations = 0;
  std::string damping_status;
  std::vector<SpecError> specs;
  /// The specs the fitted set was run on after the fit (check_specs): every
  /// one completed without a blow-up or an inverted element.
  std::vector<std::string> checked_on;
  std::string start_file;     ///< the calibration file the fit started from (empty: the spec's constants)
  double damping_start = 0.0; ///< s, stage 2's starting damping_time
  std::string fem_version, fem_git_revision, created;
};

/// The spec with its msd constants replaced by `p` (physical constants).
Spec with_parameters(const Spec& spec, const CalibrationParameters& p);

/// Series of an MSD run held in memory (no file).
std::map<std::string, std::vector<double>> simulate_msd(const Spec& spec);

/// Fits the parameters for `material` (a benchmarks/materials.yaml entry) on
/// the calibration specs (their material replaced by the library entry):
/// uniaxial and simple_shear specs in stage 1 (at most max_evaluations MSD
/// runs of the set), vibration specs in stage 2 (at most
/// max_damping_evaluations). FEM references are written to out_dir. `log`
/// receives one line per evaluation. `start`: begin at a calibration file's
/// parameters (of the same material, each strictly inside `bounds`, else
/// msd::Error naming the file and the field; edge classes in it need edge_classes).
CalibrationResult calibrate(const std::string& material, const std::vector<std::string>& spec_files,
                            const std::string& out_dir, const CalibrationBounds& bounds = {},
                            const std::function<void(const std::string&)>& log = {},
                            int max_evaluations = 40, double volume_weight = 2.0,
                            int max_damping_evaluations = 20, bool edge_classes = false,
                            const std::vector<std::string>& check_specs = {},
                            const std::optional<CalibrationStart>& start = std::nullopt);

/// The shipped comparison specs (uniaxial, shear, bending, bending_gravity,
/// vibration, indentation in benchmarks/specs): a calibration's default
/// check_specs.
std::vector<std::string> shipped_benchmark_specs();

/// Runs the set `p` on each spec (its material replaced by `material`, as the
/// calibration specs; implicit steps with the exact Newton of sparse_lu);
/// throws msd::Error "calibration: the fitted set fails
/// on SPEC: ..." when a run blows up or inverts an element. Returns the specs' names.
std::vector<std::string> check_fitted_set(const std::string& material, const CalibrationParameters& p,
                                          const std::vector<std::string>& spec_files,
                                          const std::function<void(const std::string&)>& log = {});

/// Writes the calibrated set with its provenance (YAML; the msd solver reads it
/// through `msd.calibration` in a spec).
void write_calibration(const CalibrationResult& result, const std::string& path);

/// Reads the parameters of a calibration file (and the material it was fitted
/// for, into *material); damping_time is optional (files from before stage 2
/// have none). Throws msd::Error naming the file.
CalibrationParameters read_calibration(const std::string& path, std::string* material = nullptr);

/// Puts a calibration file's parameters into the spec's msd section (physical
/// constants; msd.damping_time when the file has one). The file's material must be the spec's material. `where` is
/// prefixed to messages (the spec field that named the file).
void apply_calibration(Spec& spec, const std::string& file, const std::string& where = "");

/// The fitted edge classes of `p` into the msd section (nothing when p has
/// none): the axis factor on `axis`, and the law (tension exponent 1,
/// p's compression exponent) on `axis` and `face_diagonal`. Shared by
/// apply_calibration and with_parameters.
void apply_edge_classes(MsdSpec& msd, const CalibrationParameters& p);

}  // namespace bench
