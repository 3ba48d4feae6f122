#include "bench/stability.hpp"

#include "bench/compare.hpp"

#include "bench/msd_runner.hpp"
#include "bench/shared_io.hpp"
#include "bench/sweep.hpp"
#include "tbio/json.hpp"
#include "msd/forces/element_forces.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace bench {

namespace fs = std::filesystem;

double TrialOutcome::volume_error() const {
  return std::max(std::abs(min_volume_ratio - 1.0), std::abs(max_volume_ratio - 1.0));
}

TrialOutcome run_trial(const Spec& spec) {
  const MsdProblem p = compile_msd(spec);
  TrialOutcome o;
  const int c_vol = column_index(p.columns, "volume_ratio"), c_inv = column_index(p.columns, "inverted_elements");
  const int c_load = column_index(p.columns, load_series_name(spec.loading.type));
  bool first = true;
  const msd::ExperimentHooks hooks = msd_hooks(
      p,
      [&](const std::vector<double>& r) {
        if (c_vol >= 0) {
          o.min_volume_ratio = std::min(o.min_volume_ratio, r[static_cast<size_t>(c_vol)]);
          o.max_volume_ratio = std::max(o.max_volume_ratio, r[static_cast<size_t>(c_vol)]);
        }
        if (c_inv >= 0) {
          o.final_inverted = static_cast<int>(r[static_cast<size_t>(c_inv)]);
          o.max_inverted = std::max(o.max_inverted, o.final_inverted);
        }
        if (c_load >= 0) {
          const double v = r[static_cast<size_t>(c_load)];
          o.min_load = first ? v : std::min(o.min_load, v);
          o.max_load = first ? v : std::max(o.max_load, v);
          first = false;
        }
        return true;
      },
      [&](const msd::State& st) {
        o.max_kinetic_energy = std::max(o.max_kinetic_energy, msd::kinetic_energy(p.model, st.v));
        o.failure_time = st.t;  // the last sample reached (kept if the run fails)
      });
  const auto start = std::chrono::steady_clock::now();
  try {
    o.steps = integrate_msd(p, hooks).steps;
    o.failure_time = std::numeric_limits<double>::quiet_NaN();
  } catch (const msd::SimulationFailure& f) {
    o.finite = false;
    o.failure = f.what();
    o.failure_time = f.time;
    o.steps = f.step;
  }
  o.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return o;
}

bool is_stable(const TrialOutcome& t, const TrialOutcome& ref, const StabilityCriteria& c, std::string* reason) {
  std::string why;
  if (!t.finite) why = t.failure;
  else if (t.max_kinetic_energy > c.energy_growth * ref.max_kinetic_energy + c.energy_floor)
    why = "energy growth: kinetic energy " + json_number(t.max_kinetic_energy, 3) + " J against " +
          json_number(ref.max_kinetic_energy, 3) + " J at the reference dt";
  else if (t.final_inverted > ref.final_inverted)
    why = "unrecoverable inversion: " + std::to_string(t.final_inverted) + " elements inverted at the end (" +
          std::to_string(ref.final_inverted) + " at the reference dt)";
  if (reason) *reason = why;
  return why.empty();
}

Spec spec_variant(const Spec& spec, const std::function<void(YAML::Node&)>& edit) {
  YAML::Node n = YAML::Load(spec.text);
  edit(n);
  if (spec.msd && !spec.msd->calibration.empty() && n["msd"] && n["msd"]["calibration"])
    n["msd"]["calibration"] = fs::absolute(spec.msd->calibration).string();
  YAML::Emitter e;
  e << n;
  return parse_spec(e.c_str(), spec.path + " (variant)");
}

DtSearch search_dt(const Spec& spec, const std::string& integrator, const std::string& terms,
                   const StabilityCriteria& c, const std::function<void(const std::string&)>& log) {
  if (!spec.msd || spec.msd->integrator == "cvode") throw msd::Error(spec.path + ": a dt search needs a fixed-step msd section");
  DtSearch d;
  d.integrator = integrator;
  d.terms = terms;
  d.reference_dt = spec.msd->dt;
  const auto start = std::chrono::steady_clock::now();
  auto at = [&](double dt) {
    ++d.trials;
    return run_trial(spec_variant(spec, [&](YAML::Node& n) {
      n["msd"]["integrator"] = integrator;
      n["msd"]["dt"] = dt;
      YAML::Node m = n["msd"];
      set_term_set(m, terms);
    }));
  };
  const TrialOutcome ref = at(d.reference_dt);
  if (!ref.finite) {
    d.largest_stable_dt = 0.0;
    d.smallest_unstable_dt = d.reference_dt;
    d.unstable_reason = "unstable at the spec's dt: " + ref.failure;
    d.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return d;
  }
  double lo = d.reference_dt, hi = std::numeric_limits<double>::quiet_NaN();
  const double cap = spec.output.interval;
  std::string reason;
  while (std::isnan(hi)) {
    const double next = std::min(2 * lo, cap);
    if (next <= lo) break;  // stable up to the cap
    std::string why;
    const bool ok = is_stable(at(next), ref, c, &why);
    if (log) log("  " + integrator + "/" + terms + " dt " + json_number(next, 4) + (ok ? " stable" : " unstable: " + why));
    if (ok) lo = next;
    else {
      hi = next;
      reason = why;
    }
  }
  while (!std::isnan(hi) && hi / lo > 1.1) {
    const double mid = std::sqrt(lo * hi);
    std::string why;
    const bool ok = is_stable(at(mid), ref, c, &why);
    if (log) log("  " + integrator + "/" + terms + " dt " + json_number(mid, 4) + (ok ? " stable" : " unstable: " + why));
    if (ok) lo = mid;
    else {
      hi = mid;
      reason = why;
    }
  }
  d.largest_stable_dt = lo;
  d.smallest_unstable_dt = hi;
  d.unstable_reason = reason;
  d.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return d;
}

std::vector<ExtremeRow> run_extremes(const Spec& spec, const std::vector<std::string>& term_sets,
                                     const std::function<void(const std::string&)>& log) {
  if (spec.loading.type != Loading::Uniaxial || !spec.msd || spec.msd->constants != "physical" || spec.msd->integrator == "cvode")
    throw msd::Error(spec.path + ": the extreme loads need a uniaxial spec with physical msd constants and a "
                                 "fixed-step integrator");
  const double E = spec.material.youngs_modulus.value_or(0.0);
  const double L = spec.geometry.shape == "cylinder" ? spec.geometry.height : spec.geometry.size[2];
  struct Case {
    std::string name, description;
    std::vector<std::pair<double, double>> path;
    double youngs_modulus = 0.0, density = 0.0, damping_time = -1.0, volume_factor = -1.0;
  };
  const double impact_end = 0.5 * L / 10.0;  // eps -0.5 at 10 m/s
  // Tendon constants as benchmarks/materials.yaml's tendon entries (density 1100,
  // damping time 1.6e-5 s: the tissue's 4.2e-3 s on a 1 GPa spring would be a
  // damper no explicit step resolves).
  const std::vector<Case> cases = {
      {"compression_0.9", "eps 0 -> -0.9 -> 0 over 4 s", {{0, 0}, {2, -0.9}, {4, 0}}},
      {"extension_2.0", "eps 0 -> +2.0 -> 0 over 4 s", {{0, 0}, {2, 2.0}, {4, 0}}},
      {"volume_factor_1000", "volume factor 1000, eps 0 -> -0.5 -> 0 over 2 s", {{0, 0}, {1, -0.5}, {2, 0}}, 0, 0,
       -1.0, 1000.0},
      {"tendon_35MPa", "E = 35 MPa, 1100 kg/m^3, damping time 1.6e-5 s, eps 0 -> 0.05 -> 0 over 20 ms",
       {{0, 0}, {0.01, 0.05}, {0.02, 0}}, 35e6, 1100, 1.6e-5},
      {"tendon_1GPa", "E = 1 GPa, 1100 kg/m^3, damping time 1.6e-5 s, eps 0 -> 0.05 -> 0 over 20 ms",
       {{0, 0}, {0.01, 0.05}, {0.02, 0}}, 1e9, 1100, 1.6e-5},
      {"impact_10m/s", "platen at 10 m/s to eps -0.5, held to 50 ms", {{0, 0}, {impact_end, -0.5}, {0.05, -0.5}}},
  };
  std::vector<ExtremeRow> rows;
  // The explicit rows: each term set with the spec's integrator. The implicit
  // rows: backward Euler with the full model (every term), and BDF2 with the
  // continuum rung, at the step the case's output needs (its duration / 200)
  // however stiff the case is.
  struct Run {
    std::string integrator, terms;
  };
  std::vector<Run> runs;
  for (const auto& terms : term_sets) runs.push_back({spec.msd->integrator, terms});
  if (!msd::is_implicit(msd::parse_integrator(spec.msd->integrator))) runs.push_back({"backward_euler", "all"});
  // The continuum rung and the neo lattice (zero-length springs, dampers and
  // the per-cube bulk term: every term with an energy), implicit, where the
  // spec's material has a Poisson's ratio.
  if (spec.material.poisson_ratio) {
    runs.push_back({"bdf2", "continuum"});
    runs.push_back({"bdf2", "neo_lattice"});
    runs.push_back({"bdf2", "neo_lattice_repulsion"});
  }
  for (const Case& k : cases)
    for (const Run& run : runs) {
      const std::string& terms = run.terms;
      const bool implicit = msd::is_implicit(msd::parse_integrator(run.integrator));
      const double end = k.path.back().first;
      // The case's natural step: the spec's dt, scaled as the explicit limit
      // scales with the stiffness (sqrt of the modulus or volume-factor ratio);
      // for backward Euler, the output's.
      double natural = spec.msd->dt;
      if (k.youngs_modulus > 0 && E > 0) natural *= std::sqrt(E / k.youngs_modulus);
      if (k.volume_factor > 0 && spec.msd->volume_factor > 0)
        natural *= std::min(1.0, std::sqrt(spec.msd->volume_factor / k.volume_factor));
      if (implicit) natural = end / 200.0;
      // Tried in turn until a run stays finite: the natural step, then 1/4 and 1/16 of it.
      for (double factor : {1.0, 0.25, 0.0625}) {
        const double dt = natural * factor;
        const Spec s = spec_variant(spec, [&](YAML::Node& n) {
          YAML::Node path(YAML::NodeType::Sequence);
          for (const auto& [t, e] : k.path) {
            YAML::Node pt(YAML::NodeType::Sequence);
            pt.push_back(t);
            pt.push_back(e);
            pt.SetStyle(YAML::EmitterStyle::Flow);
            path.push_back(pt);
          }
          n["loading"]["path"] = path;
          YAML::Node m = n["msd"];
          set_term_set(m, terms);
          n["msd"]["integrator"] = run.integrator;
          n["msd"]["dt"] = dt;
          // The full model with a barrier: the thesis' face repulsion with its
          // floor at 1e-4 x0 (a log barrier up to there) on the neo lattice,
          // and Newton keeping every tet's orientation, so that the barrier
          // is never stepped across.
          if (terms == "neo_lattice_repulsion") {
            n["msd"]["repulsion_floor"] = 1e-4;
            if (implicit) n["msd"]["newton_keep_orientation"] = true;
          }
          // The volume factor scales the thesis' volume term; for the bulk
          // term, its modulus (bulk_factor); the continuum rung has neither.
          if (k.volume_factor >= 0) {
            if (terms == "neo_lattice" || terms == "neo_lattice_repulsion")
              n["msd"]["bulk_factor"] = k.volume_factor;
            else
              n["msd"]["volume_factor"] = k.volume_factor;
          }
          if (k.youngs_modulus > 0) n["material"]["youngs_modulus"] = k.youngs_modulus;
          if (k.density > 0) n["material"]["density"] = k.density;
          if (k.damping_time >= 0) n["material"]["damping_time"] = k.damping_time;
          n["output"]["interval"] = std::max(dt, end / 200.0);
          if (n["output"]["fields_interval"]) n["output"].remove("fields_interval");
        });
        ExtremeRow r{k.name, k.description, terms, run.integrator, dt, run_trial(s)};
        if (log)
          log("  " + k.name + " / " + run.integrator + " / " + terms + " dt " + json_number(dt, 3) + ": " +
              (r.outcome.finite ? "finite" : "FAILED at t = " + json_number(r.outcome.failure_time, 4) + " s") + ", " +
              json_number(r.outcome.wall_seconds, 3) + " s");
        rows.push_back(r);
        if (r.outcome.finite) break;
      }
    }
  return rows;
}

std::string format_dt_searches(const std::vector<DtSearch>& rows) {
  std::ostringstream s;
  char line[512];
  std::snprintf(line, sizeof line, "%-18s %-16s %10s %14s %14s %7s %s\n", "integrator", "terms", "spec dt/s",
                "stable dt/s", "unstable dt/s", "trials", "detector");
  s << line;
  for (const auto& d : rows) {
    std::snprintf(line, sizeof line, "%-18s %-16s %10.3g %14.4g %14s %7d %s\n", d.integrator.c_str(), d.terms.c_str(),
                  d.reference_dt, d.largest_stable_dt,
                  std::isnan(d.smallest_unstable_dt) ? "(cap)" : json_number(d.smallest_unstable_dt, 4).c_str(), d.trials,
                  d.unstable_reason.substr(0, 80).c_str());
    s << line;
  }
  return s.str();
}

std::string format_extremes(const std::vector<ExtremeRow>& rows) {
  std::ostringstream s;
  char line[600];
  std::snprintf(line, sizeof line, "%-20s %-16s %-16s %10s %-8s %10s %8s %8s %8s %10s %10s %s\n", "case", "integrator",
                "terms", "dt/s", "finite", "fail t/s", "inv max", "inv end", "|dV|max", "load min", "load max", "failure");
  s << line;
  for (const auto& r : rows) {
    const TrialOutcome& o = r.outcome;
    std::snprintf(line, sizeof line, "%-20s %-16s %-16s %10.3g %-8s %10s %8d %8d %8.3f %10.4g %10.4g %s\n",
                  r.name.c_str(), r.integrator.c_str(), r.terms.c_str(), r.dt, o.finite ? "yes" : "NO", o.finite ? "-" : json_number(o.failure_time, 4).c_str(),
                  o.max_inverted, o.final_inverted, o.volume_error(), o.min_load, o.max_load,
                  o.failure.substr(0, 90).c_str());
    s << line;
  }
  return s.str();
}

void write_stability_json(const std::string& spec, const std::vector<DtSearch>& dt,
                          const std::vector<ExtremeRow>& ex, const std::string& path) {
  tbio::Json searches = tbio::Json::array();
  for (const auto& d : dt)
    searches.push_back({{"integrator", d.integrator},
                        {"terms", d.terms},
                        {"reference_dt", d.reference_dt},
                        {"largest_stable_dt", d.largest_stable_dt},
                        {"smallest_unstable_dt", d.smallest_unstable_dt},
                        {"reason", d.unstable_reason},
                        {"trials", d.trials},
                        {"wall_seconds", d.wall_seconds}});
  tbio::Json extremes = tbio::Json::array();
  for (const auto& r : ex) {
    const auto& o = r.outcome;
    extremes.push_back({{"case", r.name},
                        {"description", r.description},
                        {"terms", r.terms},
                        {"integrator", r.integrator},
                        {"dt", r.dt},
                        {"finite", o.finite},
                        {"failure", o.failure},
                        {"failure_time", o.failure_time},
                        {"max_inverted", o.max_inverted},
                        {"final_inverted", o.final_inverted},
                        {"volume_error", o.volume_error()},
                        {"min_volume_ratio", o.min_volume_ratio},
                        {"max_volume_ratio", o.max_volume_ratio},
                        {"min_load", o.min_load},
                        {"max_load", o.max_load},
                        {"max_kinetic_energy", o.max_kinetic_energy},
                        {"steps", o.steps},
                        {"wall_seconds", o.wall_seconds}});
  }
  tbio::Json j;
  j["spec"] = spec;
  j["dt_search"] = std::move(searches);
  j["extremes"] = std::move(extremes);
  tbio::write_json_file(path, j);
}

}  // namespace bench
