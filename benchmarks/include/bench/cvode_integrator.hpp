// The MSD model integrated in time by SUNDIALS CVODE (variable-order,
// variable-step BDF with Newton iterations on a matrix-free GMRES solver) at
// tight tolerances: the "exact-in-time" trajectory of the same spatial model,
// against which the fixed-step integrators' time error is measured apart from
// the model error (benchmarks/README.md, "Time error apart from model error").
//
// The ODE is the first-order system y = (x, v), dy/dt = (v, a(x, v, t)) with
// a = (f_int(x, v) + s(t) f_ext) / m (+ s g), for all 3N components. The
// prescribed components of kinematic groups are overwritten from the controls
// at t before every force evaluation (so their integrated values never enter a
// force) and have zero derivative. Tolerances: relative `rtol`, absolute
// `atol_position` (m) on x and `atol_position / time_scale` (m/s) on v.
//
// Lives in benchmarks/, not msd/: the product library stays Eigen-only.
#pragma once

#include "msd/experiments/rig.hpp"

namespace bench {

struct CvodeOptions {
  double rtol = 1e-8;
  double atol_position = 1e-10;   ///< m
  double time_scale = 1e-2;       ///< s; atol on velocities = atol_position / time_scale
  double output_interval = 0.01;  ///< s
  double blowup_factor = 10.0;    ///< sample sizes, as msd::TimeSteppingOptions
  long max_steps = 1'000'000;       ///< internal steps per output interval
  double min_step_fraction = 1e-12; ///< smallest step, as a fraction of the output interval
};

struct CvodeStats {
  long steps = 0;                ///< internal CVODE steps
  long rhs_evaluations = 0;      ///< force evaluations (incl. finite-difference J v products)
  long linear_iterations = 0;
  long error_test_failures = 0;
  double simulated_seconds = 0.0;
};

/// As msd::run_experiment (same hooks, same sampling at every output interval
/// and at the end), integrated by CVODE. Throws msd::SimulationFailure on a
/// non-finite value, a blow-up or a CVODE failure (naming its flag and time).
CvodeStats run_experiment_cvode(const msd::Model& model, msd::State initial, double end_time, double size,
                                const CvodeOptions& options, const msd::ExperimentHooks& hooks);

}  // namespace bench
