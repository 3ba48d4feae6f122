// Stability at the extremes: the largest stable time step of each integrator
// and force-term configuration, found by bisection with a blow-up detector, and
// the MSD model under extreme loads (huge compression and extension, a very
// large volume factor, tendon-like stiffness, a platen impact).
//
// Blow-up detector (a trial is unstable when any holds):
//   - a non-finite force, position or velocity, or a node farther than ten
//     sample sizes from rest (msd::SimulationFailure);
//   - energy growth: the largest kinetic energy of the run exceeds
//     `energy_growth` (10) times that of the reference run at the spec's dt
//     (plus 1e-9 J, so a quasi-static reference near rest is not a hair trigger);
//   - unrecoverable inversion: more elements inverted at the end of the run
//     than at the end of the reference run.
#pragma once

#include "bench/spec.hpp"

#include <yaml-cpp/yaml.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace bench {

/// What one MSD run did (in memory, no results file).
struct TrialOutcome {
  bool finite = true;             ///< completed without msd::SimulationFailure
  std::string failure;            ///< its message
  double failure_time = std::numeric_limits<double>::quiet_NaN();
  long steps = 0;
  double wall_seconds = 0.0;
  int max_inverted = 0, final_inverted = 0;
  double max_kinetic_energy = 0.0;  ///< J
  double min_volume_ratio = 1.0, max_volume_ratio = 1.0;
  double min_load = 0.0, max_load = 0.0;  ///< the test's load series (nominal stress, ...)
  double volume_error() const;      ///< max |V/V0 - 1|
};

TrialOutcome run_trial(const Spec& spec);

struct StabilityCriteria {
  double energy_growth = 10.0;
  double energy_floor = 1e-9;  ///< J
};

/// Whether `trial` passes the blow-up detector against `reference`; else the reason.
bool is_stable(const TrialOutcome& trial, const TrialOutcome& reference, const StabilityCriteria& c,
               std::string* reason = nullptr);

/// The spec re-read with edits applied to its YAML (name kept; validation as
/// for a file). `edit` receives the root node.
Spec spec_variant(const Spec& spec, const std::function<void(YAML::Node&)>& edit);

struct DtSearch {
  std::string integrator, terms;
  double reference_dt = 0.0;
  double largest_stable_dt = 0.0;
  double smallest_unstable_dt = std::numeric_limits<double>::quiet_NaN();  ///< NaN: none up to the cap
  std::string unstable_reason;
  int trials = 0;
  double wall_seconds = 0.0;
};

/// Largest stable dt of the spec with the integrator and term set: doubling
/// from the spec's dt until the detector fires (or dt reaches the output
/// interval, the cap), then bisection (geometric) to a bracket ratio of 1.1.
DtSearch search_dt(const Spec& spec, const std::string& integrator, const std::string& terms,
                   const StabilityCriteria& c = {}, const std::function<void(const std::string&)>& log = {});

struct ExtremeRow {
  std::string name, description, terms;
  std::string integrator;  ///< the spec's explicit one, or backward_euler
  double dt = 0.0;
  TrialOutcome outcome;
};

/// The extreme-load variants of a uni-axial spec with physical constants, each
/// run with every term set in `term_sets`: at the case's natural time step (the
/// spec's dt scaled by sqrt(E_spec / E_case) or sqrt(k_spec / k_case) for the
/// stiffness and volume-factor cases, as the explicit limit scales), and if that
/// run fails, again at 1/4 and then 1/16 of it until one stays finite. With
/// an explicit spec integrator, also backward Euler with every term; and
/// whatever the spec's integrator, when the material has a Poisson's ratio,
/// BDF2 with the continuum rung; both at the case's duration / 200. (The
/// continuum element has no volume factor: its volume_factor_1000 row is the
/// case's strain path alone.)
std::vector<ExtremeRow> run_extremes(const Spec& spec, const std::vector<std::string>& term_sets,
                                     const std::function<void(const std::string&)>& log = {});

std::string format_dt_searches(const std::vector<DtSearch>& rows);
std::string format_extremes(const std::vector<ExtremeRow>& rows);
void write_stability_json(const std::string& spec, const std::vector<DtSearch>& dt,
                          const std::vector<ExtremeRow>& extremes, const std::string& path);

}  // namespace bench
