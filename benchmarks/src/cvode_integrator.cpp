#include "bench/cvode_integrator.hpp"

#include "msd/experiments/blowup.hpp"
#include "msd/integrate/step.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_spgmr.h>

#include <cmath>
#include <exception>
#include <memory>
#include <string>

namespace bench {

namespace {

struct Problem {
  const msd::Model& model;
  const msd::ExperimentHooks& hooks;
  msd::State state;
  msd::Scratch scratch;
  msd::Points a;
  std::exception_ptr error;
  long n = 0;  // nodes
};

// y = (x, v) column-major, 6N values.
void unpack(const double* y, long n, msd::State& s) {
  s.x = Eigen::Map<const msd::Points>(y, 3, n);
  s.v = Eigen::Map<const msd::Points>(y + 3 * n, 3, n);
}

int rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user) {
  auto* p = static_cast<Problem*>(user);
  try {
    const long n = p->n;
    unpack(N_VGetArrayPointer(y), n, p->state);
    p->state.t = t;
    const msd::Controls c = p->hooks.controls(t);
    msd::apply_constraints(p->model, c, p->state);
    msd::evaluate_forces(p->model, p->state, p->scratch);
    msd::accelerations(p->model, p->scratch, c.load_scale, p->a);
    for (const auto& g : p->model.groups)
      for (int node : g.nodes)
        for (int k = 0; k < 3; ++k)
          if (g.axes[k]) p->a(k, node) = 0.0;
    double* d = N_VGetArrayPointer(ydot);
    Eigen::Map<msd::Points>(d, 3, n) = p->state.v;
    Eigen::Map<msd::Points>(d + 3 * n, 3, n) = p->a;
    return 0;
  } catch (...) {
    p->error = std::current_exception();
    return -1;  // unrecoverable: CVode returns CV_RHSFUNC_FAIL
  }
}

struct Sundials {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr, atol = nullptr;
  SUNLinearSolver ls = nullptr;
  void* mem = nullptr;
  ~Sundials() {
    if (mem) CVodeFree(&mem);
    if (ls) SUNLinSolFree(ls);
    if (atol) N_VDestroy(atol);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }
};

void check(int flag, const char* what) {
  if (flag < 0) throw msd::Error(std::string("CVODE: ") + what + " failed: " + CVodeGetReturnFlagName(flag));
}

}  // namespace

CvodeStats run_experiment_cvode(const msd::Model& model, msd::State initial, double end_time, double size,
                                const CvodeOptions& o, const msd::ExperimentHooks& hooks) {
  if (!(o.rtol > 0.0) || !(o.atol_position > 0.0) || !(o.time_scale > 0.0))
    throw msd::Error("CVODE tolerances must be positive");
  if (!(o.output_interval > 0.0)) throw msd::Error("output interval must be positive");
  Problem p{model, hooks, std::move(initial), {}, {}, nullptr, model.num_nodes()};
  msd::apply_constraints(model, hooks.controls(0.0), p.state);
  const long n = p.n;
  Sundials s;
  check(SUNContext_Create(nullptr, &s.ctx), "SUNContext_Create");
  s.y = N_VNew_Serial(6 * n, s.ctx);
  s.atol = N_VNew_Serial(6 * n, s.ctx);
  double* y = N_VGetArrayPointer(s.y);
  Eigen::Map<msd::Points>(y, 3, n) = p.state.x;
  Eigen::Map<msd::Points>(y + 3 * n, 3, n) = p.state.v;
  double* at = N_VGetArrayPointer(s.atol);
  for (long i = 0; i < 3 * n; ++i) {
    at[i] = o.atol_position;
    at[3 * n + i] = o.atol_position / o.time_scale;
  }
  s.mem = CVodeCreate(CV_BDF, s.ctx);
  if (!s.mem) throw msd::Error("CVODE: CVodeCreate failed");
  check(CVodeInit(s.mem, rhs, 0.0, s.y), "CVodeInit");
  check(CVodeSetUserData(s.mem, &p), "CVodeSetUserData");
  check(CVodeSVtolerances(s.mem, o.rtol, s.atol), "CVodeSVtolerances");
  check(CVodeSetMaxNumSteps(s.mem, o.max_steps), "CVodeSetMaxNumSteps");
  // A collapsing step (a singular or blowing-up trajectory) ends the run
  // instead of creeping on: steps below 1e-12 of the output interval fail.
  check(CVodeSetMinStep(s.mem, o.min_step_fraction * o.output_interval), "CVodeSetMinStep");
  check(CVodeSetMaxHnilWarns(s.mem, -1), "CVodeSetMaxHnilWarns");
  // Failures are reported through msd::SimulationFailure, not printed by CVODE.
  check(CVodeSetErrHandlerFn(
            s.mem, [](int, const char*, const char*, char*, void*) {}, nullptr),
        "CVodeSetErrHandlerFn");
  check(CVodeSetStopTime(s.mem, end_time), "CVodeSetStopTime");
  s.ls = SUNLinSol_SPGMR(s.y, SUN_PREC_NONE, 30, s.ctx);
  check(CVodeSetLinearSolver(s.mem, s.ls, nullptr), "CVodeSetLinearSolver");

  CvodeStats stats;
  msd::Scratch scratch;
  msd::BlowUpLimits limits(model, size, o.blowup_factor);
  double t = 0.0;
  for (long k = 0;; ++k) {
    double tout = std::min(k * o.output_interval, end_time);
    if (k > 0 && tout > t) {
      const int flag = CVode(s.mem, tout, s.y, &t, CV_NORMAL);
      long steps = 0;
      CVodeGetNumSteps(s.mem, &steps);
      if (p.error) {
        try {
          std::rethrow_exception(p.error);
        } catch (const msd::SimulationFailure&) {
          throw;
        } catch (const std::exception& e) {
          throw msd::SimulationFailure(std::string("CVODE right-hand side: ") + e.what(), p.state.t, steps, -1, -1);
        }
      }
      if (flag < 0)
        throw msd::SimulationFailure(std::string("CVODE: ") + CVodeGetReturnFlagName(flag), t, steps, -1, -1);
    }
    msd::State st;
    unpack(N_VGetArrayPointer(s.y), n, st);
    st.t = tout;
    st.step = k;
    msd::apply_constraints(model, hooks.controls(tout), st);
    limits.see_load_speed(msd::load_speed(hooks.controls(tout)));
    limits.check(model, st);
    if (!hooks.sample(st, scratch)) break;
    if (tout >= end_time) break;
  }
  CVodeGetNumSteps(s.mem, &stats.steps);
  CVodeGetNumRhsEvals(s.mem, &stats.rhs_evaluations);
  long jv = 0;
  CVodeGetNumLinRhsEvals(s.mem, &jv);
  stats.rhs_evaluations += jv;
  CVodeGetNumLinIters(s.mem, &stats.linear_iterations);
  CVodeGetNumErrTestFails(s.mem, &stats.error_test_failures);
  stats.simulated_seconds = t;
  return stats;
}

}  // namespace bench
