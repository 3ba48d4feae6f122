#include "bench/calibration.hpp"

#include "bench/compare.hpp"

#include "bench/fem_runner.hpp"
#include "bench/msd_runner.hpp"
#include "bench/shared_io.hpp"
#include "msd/io/atomic_file.hpp"
#include "msd/io/input_file.hpp"

#include <unsupported/Eigen/NonLinearOptimization>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <regex>
#include <sstream>

namespace bench {

namespace fs = std::filesystem;

Spec with_parameters(const Spec& spec, const CalibrationParameters& p) {
  Spec s = spec;
  if (!s.msd) throw msd::Error(spec.path + ": the spec has no msd section to calibrate");
  s.msd->constants = "physical";
  s.msd->stiffness_scale = p.stiffness_scale;
  s.msd->repulsion_factor = p.repulsion_factor;
  s.msd->volume_factor = p.volume_factor;
  if (p.damping_time) s.msd->damping_time = p.damping_time;
  apply_edge_classes(*s.msd, p);
  return s;
}

std::map<std::string, std::vector<double>> simulate_msd(const Spec& spec) {
  const MsdProblem p = compile_msd(spec);
  std::map<std::string, std::vector<double>> out;
  for (const auto& c : p.columns) out[c.name];
  const msd::ExperimentHooks hooks = msd_hooks(p, [&](const std::vector<double>& row) {
    for (size_t k = 0; k < row.size(); ++k) out[p.columns[k].name].push_back(row[k]);
    return true;
  });
  integrate_msd(p, hooks);
  return out;
}

namespace {

struct Target {
  Spec spec;
  std::string series;
  std::vector<double> t, y, v;  // FEM
  double rms = 1.0;
  bool volume = false;
  double volume_weight = 2.0;
  // Ring-down specs (stage 2): the FEM's damping ratio and frequency.
  bool ring_down = false;
  double zeta = 0.0, frequency = 0.0;
  size_t index = 0;  // in the calibration's spec list
};

struct TargetError {
  size_t index = 0;
  double rel = 0.0, volume = 0.0;  // relative error of the fitted quantity, largest volume-ratio error
  double zeta = 0.0, frequency = 0.0;  // ring-down: the MSD's
};

// Residuals of one parameter set over `targets`, appended to r. Returns false
// if an MSD run failed (or its ring-down could not be measured).
bool residuals(const std::vector<const Target*>& targets, const CalibrationParameters& p, std::vector<double>& r,
               std::vector<TargetError>* errors = nullptr) {
  r.clear();
  for (const Target* tgp : targets) {
    const Target& tg = *tgp;
    std::map<std::string, std::vector<double>> s;
    try {
      s = simulate_msd(with_parameters(tg.spec, p));
    } catch (const msd::SimulationFailure&) {
      return false;
    }
    const auto& tm = s.at("time");
    TargetError e;
    e.index = tg.index;
    if (tg.ring_down) {
      const RingDown rd = analyse_ring_down_after(tm, s.at("tip_displacement"), tg.spec.loading.release);
      if (!(rd.damping_ratio > 0.0) || rd.peaks < 2) return false;
      const double d = (rd.damping_ratio - tg.zeta) / tg.zeta;
      r.push_back(d);
      e.rel = std::abs(d);
      e.zeta = rd.damping_ratio;
      e.frequency = rd.frequency;
      for (double v : s.at("volume_ratio")) e.volume = std::max(e.volume, std::abs(v - 1.0));
      if (errors) errors->push_back(e);
      continue;
    }
    const auto& ym = s.at(tg.series);
    const double n = static_cast<double>(tg.t.size());
    double sum = 0.0;
    for (size_t i = 0; i < tg.t.size(); ++i) {
      const double y = interpolate(tm, ym, tg.t[i]);
      if (std::isnan(y)) return false;  // the run did not reach a reference time
      const double d = (y - tg.y[i]) / tg.rms;
      r.push_back(d / std::sqrt(n));
      sum += d * d;
      if (tg.volume) {
        const double dv = interpolate(tm, s.at("volume_ratio"), tg.t[i]) - tg.v[i];
        r.push_back(tg.volume_weight * dv / std::sqrt(n));
        e.volume = std::max(e.volume, std::abs(dv));
      }
    }
    e.rel = std::sqrt(sum / n);
    if (errors) errors->push_back(e);
  }
  return true;
}

double logistic(double q, double lo, double hi) { return lo + (hi - lo) / (1.0 + std::exp(-q)); }

double inverse_logistic(double p, double lo, double hi) {
  const double s = std::clamp((p - lo) / (hi - lo), 1e-6, 1 - 1e-6);
  return std::log(s / (1 - s));
}

// The functor Eigen's Levenberg-Marquardt minimises: the residuals of the
// parameter set params(q) over the stage's targets, within an evaluation budget.
struct Fit {
  std::vector<const Target*> targets;
  std::function<CalibrationParameters(const Eigen::VectorXd&)> params;
  int m;
  int* evaluations;
  int budget;
  const std::function<void(const std::string&)>& log;
  mutable Eigen::VectorXd last_q, last_f;
  mutable double first_objective = -1.0;  // at the starting point

  int values() const { return m; }
  int operator()(const Eigen::VectorXd& q, Eigen::VectorXd& f) const {
    std::vector<double> r;
    const CalibrationParameters p = params(q);
    if (last_q.size() == q.size() && last_q == q) {  // Eigen evaluates f, then df at the same point
      f = last_f;
      return 0;
    }
    if (*evaluations >= budget) return -1;  // Eigen stops ("user asked") keeping the last accepted point
    ++*evaluations;
    if (!residuals(targets, p, r) || static_cast<int>(r.size()) != m) {
      f.setConstant(m, 1e3);  // an unstable set: push the optimiser away
      if (log) log("  evaluation " + std::to_string(*evaluations) + ": unstable");
      return 0;
    }
    f = Eigen::Map<Eigen::VectorXd>(r.data(), m);
    last_q = q;
    last_f = f;
    if (first_objective < 0.0) first_objective = f.squaredNorm();
    if (log) {
      std::ostringstream s;
      s << std::setprecision(5) << "  evaluation " << *evaluations << ": scale " << p.stiffness_scale
        << ", repulsion " << p.repulsion_factor << ", volume " << p.volume_factor;
      if (p.axis_stiffness) s << ", axis " << *p.axis_stiffness;
      if (p.compression_exponent) s << ", n " << *p.compression_exponent;
      if (p.damping_time) s << ", damping_time " << *p.damping_time;
      s << " -> objective " << f.squaredNorm();
      log(s.str());
    }
    return 0;
  }
  int df(const Eigen::VectorXd& q, Eigen::MatrixXd& J) const {
    Eigen::VectorXd f0(m), f1(m);
    if ((*this)(q, f0) < 0) return -1;
    J.resize(m, q.size());
    for (int k = 0; k < q.size(); ++k) {
      Eigen::VectorXd qk = q;
      const double h = 1e-3 * std::max(1.0, std::abs(q[k]));
      qk[k] += h;
      if ((*this)(qk, f1) < 0) return -1;
      J.col(k) = (f1 - f0) / h;
    }
    return 0;
  }
};

struct Minimum {
  std::string status;
  int iterations = 0;
  double objective = 0.0;  // at the accepted point
};

// Runs Levenberg-Marquardt from q (left at the accepted point).
Minimum minimise(Fit& fit, Eigen::VectorXd& q, int budget) {
  Eigen::LevenbergMarquardt<Fit> lm(fit);
  lm.parameters.maxfev = 10 * budget;  // the budget is enforced by Fit (Jacobian columns count)
  lm.parameters.ftol = 1e-6;
  lm.parameters.xtol = 1e-6;
  const Eigen::LevenbergMarquardtSpace::Status status = lm.minimize(q);
  const char* names[] = {"improper input", "converged (relative reduction)", "converged (relative error)",
                         "converged (both)", "converged (cosinus)", "too many function evaluations",
                         "ftol too small", "xtol too small", "gtol too small", "evaluation budget spent"};
  const int code = static_cast<int>(status);
  return {(code >= 0 && code < 10) ? names[code] : "status " + std::to_string(code), static_cast<int>(lm.iter),
          lm.fnorm * lm.fnorm};
}

// Stage 1's variables q (the logistic map's inverse of each bounded
// parameter): scale, repulsion, volume, and with the edge classes the axis
// stiffness and the compression exponent; and back.
Eigen::VectorXd elastic_variables(const CalibrationParameters& p, const CalibrationBounds& b) {
  Eigen::VectorXd q(p.axis_stiffness ? 5 : 3);
  q.head(3) << inverse_logistic(p.stiffness_scale, b.scale_lo, b.scale_hi),
      inverse_logistic(p.repulsion_factor, b.repulsion_lo, b.repulsion_hi),
      inverse_logistic(p.volume_factor, b.volume_lo, b.volume_hi);
  if (p.axis_stiffness)
    q.tail(2) << inverse_logistic(*p.axis_stiffness, b.axis_lo, b.axis_hi),
        inverse_logistic(p.compression_exponent.value_or(0.0), b.exponent_lo, b.exponent_hi);
  return q;
}

// Young's modulus of a spec's material (0 when it gives none).
double youngs_modulus(const MaterialSpec& m) {
  if (m.youngs_modulus) return *m.youngs_modulus;
  if (m.shear_modulus && m.bulk_modulus)
    return 9.0 * *m.bulk_modulus * *m.shear_modulus / (3.0 * *m.bulk_modulus + *m.shear_modulus);
  return 0.0;
}

// What a check run's explicit step is multiplied by when the check replaces
// the spec's own material: the explicit step's two limits scale with the
// material - the wave limit h / c with 1 / sqrt(E / rho), the dampers' limit
// (k_d = damping_time x k) with rho / (damping_time E) - so the step keeps
// the spec's margin under both: the smaller of the two ratios when below 1,
// else 1 (implicit steps, CVODE, a softer material: the shipped step stands).
double explicit_step_shrink(const Spec& own, const Spec& replaced) {
  if (!replaced.msd || !has_explicit_step(*replaced.msd)) return 1.0;
  const MaterialSpec &a = own.material, &b = replaced.material;
  const double ea = youngs_modulus(a), eb = youngs_modulus(b);
  if (!(ea > 0.0 && eb > 0.0 && a.density > 0.0 && b.density > 0.0)) return 1.0;
  double shrink = std::min(1.0, std::sqrt((ea / a.density) / (eb / b.density)));
  const double ta = a.damping_time.value_or(0.0), tb = b.damping_time.value_or(0.0);
  if (ta > 0.0 && tb > 0.0) shrink = std::min(shrink, (ta * ea / a.density) / (tb * eb / b.density));
  return shrink;
}

// A fit's start (calibrate --start) must lie strictly inside the bounds: the
// optimiser's variables are logistic transforms of the parameters, infinite
// on a bound. Edge classes in the file need an edge-class fit.
void check_start(const CalibrationStart& start, const std::string& material, const CalibrationBounds& b,
                 bool edge_classes) {
  if (start.material != material)
    throw msd::Error(start.file + ": material: '" + start.material + "' is not the fit's '" + material +
                     "' (a fit starts from a calibration of the same material)");
  const CalibrationParameters& s0 = start.parameters;
  const auto inside = [&](const char* name, double v, double lo, double hi) {
    if (!(v > lo && v < hi))
      throw msd::Error(start.file + ": parameters." + name + " = " + json_number(v) +
                       " is not strictly inside calibrate's bounds (" + json_number(lo) + ", " + json_number(hi) +
                       "): the fit cannot start there");
  };
  inside("stiffness_scale", s0.stiffness_scale, b.scale_lo, b.scale_hi);
  inside("repulsion_factor", s0.repulsion_factor, b.repulsion_lo, b.repulsion_hi);
  inside("volume_factor", s0.volume_factor, b.volume_lo, b.volume_hi);
  if (s0.axis_stiffness && !edge_classes)
    throw msd::Error(start.file + ": parameters.axis_stiffness: a start with edge classes needs --edge-classes");
  if (s0.axis_stiffness) {
    inside("axis_stiffness", *s0.axis_stiffness, b.axis_lo, b.axis_hi);
    inside("compression_exponent", s0.compression_exponent.value_or(0.0), b.exponent_lo, b.exponent_hi);
  }
  if (s0.damping_time) inside("damping_time", *s0.damping_time, b.damping_lo, b.damping_hi);
}

// The fit's starting point from a checked start: the elastic parameters (and
// the edge classes, for an edge-class fit) and stage 2's damping_time.
void take_start(const CalibrationStart& start, bool edge_classes, CalibrationResult& res) {
  const CalibrationParameters& s0 = start.parameters;
  res.before.stiffness_scale = s0.stiffness_scale;
  res.before.repulsion_factor = s0.repulsion_factor;
  res.before.volume_factor = s0.volume_factor;
  if (edge_classes && s0.axis_stiffness) {
    res.before.axis_stiffness = s0.axis_stiffness;
    res.before.compression_exponent = s0.compression_exponent.value_or(0.0);
  }
  if (s0.damping_time) res.damping_start = *s0.damping_time;
  res.start_file = start.file;
}

CalibrationParameters elastic_parameters(const Eigen::VectorXd& q, const CalibrationBounds& b,
                                         std::optional<double> damping_time) {
  CalibrationParameters p{logistic(q[0], b.scale_lo, b.scale_hi), logistic(q[1], b.repulsion_lo, b.repulsion_hi),
                          logistic(q[2], b.volume_lo, b.volume_hi), damping_time, std::nullopt, std::nullopt};
  if (q.size() == 5) {
    p.axis_stiffness = logistic(q[3], b.axis_lo, b.axis_hi);
    p.compression_exponent = logistic(q[4], b.exponent_lo, b.exponent_hi);
  }
  return p;
}

// What a calibration spec's MSD run is fitted to: the load curve (stage 1) or
// the ring-down's damping ratio (stage 2).
std::string load_series_of(const Spec& s) {
  switch (s.loading.type) {
    case Loading::Uniaxial:
    case Loading::SimpleShear: return load_series_name(s.loading.type);
    case Loading::Vibration: return "damping_ratio";
    case Loading::CooksMembrane:
    case Loading::Static:
    case Loading::Indentation: break;
  }
  throw msd::Error(s.path + ": calibration specs must be uniaxial or simple_shear (stage 1) or vibration (stage 2)");
}

}  // namespace

CalibrationResult calibrate(const std::string& material, const std::vector<std::string>& spec_files,
                            const std::string& out_dir, const CalibrationBounds& bounds,
                            const std::function<void(const std::string&)>& log, int max_evaluations,
                            double volume_weight, int max_damping_evaluations, bool edge_classes,
                            const std::vector<std::string>& check_specs,
                            const std::optional<CalibrationStart>& start) {
  if (!(volume_weight >= 0.0)) throw msd::Error("calibration: the volume weight must be >= 0");
  if (start) check_start(*start, material, bounds, edge_classes);  // before any FEM run
  {  // the material first: an unknown name is the user's, not a shipped spec's
    const YAML::Node lib = load_yaml_file(TISSUEBENCH_MATERIALS_FILE, "materials file");
    if (!lib[material]) {
      std::string names;
      for (const auto& kv : lib) names += (names.empty() ? "" : ", ") + kv.first.Scalar();
      throw msd::Error("--material: no material '" + material + "' in " + std::string(TISSUEBENCH_MATERIALS_FILE) +
                       " (known: " + names + ")");
    }
  }
  CalibrationResult res;
  res.material = material;
  res.volume_weight = volume_weight;
  fs::create_directories(out_dir);
  std::vector<Target> targets;
  for (const auto& file : spec_files) {
    const std::string text = std::regex_replace(msd::read_input_file(file, "calibration spec"), std::regex("library: *[A-Za-z_]+"), "library: " + material);
    Target tg;
    tg.index = targets.size();
    tg.spec = parse_spec(text, file);
    if (!tg.spec.msd) throw msd::Error(file + ": a calibration spec needs an msd section");
    if (tg.spec.msd->damping_time)
      throw msd::Error(file + ": msd.damping_time: a calibration spec takes the material's (stage 2 fits it)");
    tg.series = load_series_of(tg.spec);
    tg.ring_down = tg.series == "damping_ratio";
    if (tg.ring_down && tg.spec.loading.initial != "preload")
      throw msd::Error(file + ": loading.initial: a ring-down calibration spec starts from a preload (an "
                              "equilibrium both solvers share)");
    tg.volume = tg.spec.loading.type == Loading::Uniaxial && volume_weight > 0.0;
    tg.volume_weight = volume_weight;
    targets.push_back(std::move(tg));
  }
  if (std::all_of(targets.begin(), targets.end(), [](const Target& t) { return t.ring_down; }))
    throw msd::Error("calibration: no uniaxial or simple_shear spec among the calibration specs (stage 1 needs one)");
  for (Target& tg : targets) {
    const std::string& file = tg.spec.path;
    const std::string fem_file = (fs::path(out_dir) / (tg.spec.name + "_" + material + "_fem.h5")).string();
    if (log) log("FEM reference: " + tg.spec.name + " (" + material + ")");
    if (ensure_fem_reference(tg.spec, fem_file) && log) log("  reused " + fem_file + " (same spec text)");
    const Results r = read_results(fem_file);
    SpecError e;
    if (tg.ring_down) {
      tg.zeta = r.metrics.count("damping_ratio") ? r.metrics.at("damping_ratio") : 0.0;
      tg.frequency = r.metrics.count("first_frequency") ? r.metrics.at("first_frequency") : 0.0;
      if (!(tg.zeta > 0.0))
        throw msd::Error(file + ": the FEM ring-down has no measurable damping ratio (" + fem_file + ")");
      e.damping_ratio_fem = tg.zeta;
      e.frequency_fem = tg.frequency;
    } else {
      tg.t = r.series.at("time");
      tg.y = r.series.at(tg.series);
      tg.v = r.series.at("volume_ratio");
      double sum = 0.0;
      for (double v : tg.y) sum += v * v;
      tg.rms = std::sqrt(sum / static_cast<double>(tg.y.size()));
    }
    res.fem_version = r.meta.at("version");
    res.fem_git_revision = r.meta.at("git_revision");
    e.spec = tg.spec.name;
    e.sha256 = sha256_hex(tg.spec.text);
    e.load_series = tg.series;
    res.specs.push_back(e);
  }
  std::vector<const Target*> all, quasi_static, ring_downs;
  for (const Target& tg : targets) {
    all.push_back(&tg);
    (tg.ring_down ? ring_downs : quasi_static).push_back(&tg);
  }
  const Spec& first = targets.front().spec;
  res.before = {first.msd->stiffness_scale, first.msd->repulsion_factor, first.msd->volume_factor,
                first.material.damping_time.value_or(0.0), std::nullopt, std::nullopt};
  if (edge_classes) {  // the Cauchy-Born isotropic lattice, and a mid-range compression exponent
    res.before.axis_stiffness = 0.5;
    res.before.compression_exponent = 1.0;
  }
  res.damping_start = res.before.damping_time.value_or(0.0);
  if (start) take_start(*start, edge_classes, res);  // checked above

  auto record = [&](const std::vector<TargetError>& err, bool after) {
    for (const TargetError& t : err) {
      SpecError& e = res.specs[t.index];
      (after ? e.rel_rms_after : e.rel_rms_before) = t.rel;
      (after ? e.volume_max_error_after : e.volume_max_error_before) = t.volume;
      (after ? e.damping_ratio_after : e.damping_ratio_before) = t.zeta;
      (after ? e.frequency_after : e.frequency_before) = t.frequency;
    }
  };
  std::vector<double> r;
  std::vector<TargetError> err;
  if (!residuals(all, res.before, r, &err)) throw msd::Error("calibration: the starting constants are unstable");
  record(err, false);

  // Stage 1: the elastic factors on the quasi-static specs (damping: the material's).
  if (log) log("stage 1: stiffness scale, repulsion and volume factors on the quasi-static specs");
  const int m_quasi_static = static_cast<int>(r.size() - ring_downs.size());  // a ring-down adds one residual
  Eigen::VectorXd q = elastic_variables(res.before, bounds);
  const std::optional<double> tau0 = res.before.damping_time;
  Fit fit{quasi_static,
          [&bounds, tau0](const Eigen::VectorXd& x) { return elastic_parameters(x, bounds, tau0); },
          m_quasi_static, &res.evaluations, max_evaluations, log, {}, {}};
  const Minimum m1 = minimise(fit, q, max_evaluations);
  res.optimiser_status = m1.status;
  res.iterations = m1.iterations;
  res.objective_before = fit.first_objective;
  res.objective_after = m1.objective;
  res.after = fit.params(q);

  // Stage 2: the dampers' time constant on the ring-down specs, the elastic factors fixed.
  if (!ring_downs.empty()) {
    res.damping_fitted = true;
    if (log) log("stage 2: the dampers' time constant on the ring-down specs");
    const CalibrationParameters elastic = res.after;
    Eigen::VectorXd qd(1);
    qd << inverse_logistic(res.damping_start, bounds.damping_lo, bounds.damping_hi);
    Fit dfit{ring_downs,
             [&bounds, elastic](const Eigen::VectorXd& x) {
               CalibrationParameters p = elastic;
               p.damping_time = logistic(x[0], bounds.damping_lo, bounds.damping_hi);
               return p;
             },
             static_cast<int>(ring_downs.size()), &res.damping_evaluations, max_damping_evaluations, log, {}, {}};
    const Minimum m2 = minimise(dfit, qd, max_damping_evaluations);
    if (dfit.first_objective < 0.0)
      throw msd::Error("calibration: the stage-1 constants with stage 2's starting damping_time " +
                       json_number(res.damping_start) + " s are unstable on the ring-down spec");
    res.damping_status = m2.status;
    res.damping_iterations = m2.iterations;
    res.damping_objective_before = dfit.first_objective;
    res.damping_objective_after = m2.objective;
    res.after = dfit.params(qd);
  }
  if (!residuals(all, res.after, r, &err)) throw msd::Error("calibration: the fitted constants are unstable");
  record(err, true);
  res.checked_on = check_fitted_set(material, res.after, check_specs, log);
  const std::time_t now = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  res.created = buf;
  return res;
}

std::vector<std::string> shipped_benchmark_specs() {
  std::vector<std::string> files;
  for (const char* n : {"uniaxial", "shear", "bending", "bending_gravity", "vibration", "indentation"})
    files.push_back((fs::path(TISSUEBENCH_SPECS_DIR) / (std::string(n) + ".yaml")).string());
  return files;
}

std::vector<std::string> check_fitted_set(const std::string& material, const CalibrationParameters& p,
                                          const std::vector<std::string>& spec_files,
                                          const std::function<void(const std::string&)>& log) {
  std::vector<std::string> names;
  for (const auto& file : spec_files) {
    const std::string own = msd::read_input_file(file, "check spec");
    const std::string text = std::regex_replace(own, std::regex("library: *[A-Za-z_]+"), "library: " + material);
    Spec spec = with_parameters(parse_spec(text, file), p);
    const double shrink = explicit_step_shrink(parse_spec(own, file), spec);
    if (shrink < 1.0) {
      // An explicit step keeps the spec's margin: the shipped step was
      // chosen for the spec's own material, and a stiffer one (passive muscle
      // on the indentation: 5x E, the dampers' limit 0.23x) blows up at it
      // with its physical constants already. Whole steps per output interval.
      const double interval = spec.output.interval;
      const double dt = interval / std::ceil(interval / (spec.msd->dt * shrink) - 1e-9);
      if (log)
        log("check: " + spec.name + " with " + material + ": explicit step " + json_number(spec.msd->dt, 4) +
            " s -> " + json_number(dt, 4) + " s (the material's stable step is " + json_number(shrink, 3) +
            " times the spec's own material's)");
      spec.msd->dt = dt;
    }
    // Implicit paths with exact Newton (the converged steps are the same): a
    // fitted volume term several times the shipped one makes Newton's matrix
    // far from symmetric, and Newton on its symmetric part alone crawls (the
    // thesis cycle: 0.25 s per step, against the whole cycle in under a minute).
    if (spec.msd->newton_linear_solver == "symmetric_ldlt") spec.msd->newton_linear_solver = "sparse_lu";
    if (log) log("check: the fitted set on " + spec.name);
    std::map<std::string, std::vector<double>> s;
    try {
      s = simulate_msd(spec);
    } catch (const msd::SimulationFailure& e) {
      throw msd::Error("calibration: the fitted set fails on " + file + ": " + e.what() +
                       " (the calibration file is not written)");
    }
    const auto inverted = s.find("inverted_elements");
    if (inverted != s.end())
      for (size_t i = 0; i < inverted->second.size(); ++i)
        if (inverted->second[i] > 0.0)
          throw msd::Error("calibration: the fitted set inverts " + std::to_string(std::lround(inverted->second[i])) +
                           " element(s) on " + file + " at t = " + std::to_string(s.at("time")[i]) +
                           " s (the calibration file is not written)");
    names.push_back(spec.name);
  }
  return names;
}

void write_calibration(const CalibrationResult& r, const std::string& path) {
  msd::write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);  // round-trips exactly
    out << "# MSD constants of " << r.material << " calibrated against the FEM reference\n"
        << "# (tissuebench calibrate; objective and optimiser: benchmarks/include/bench/calibration.hpp).\n"
        << "material: " << r.material << "\n"
        << "parameters:\n  stiffness_scale: " << r.after.stiffness_scale << "\n  repulsion_factor: "
        << r.after.repulsion_factor << "\n  volume_factor: " << r.after.volume_factor << "\n";
    if (r.after.axis_stiffness)
      out << "  axis_stiffness: " << *r.after.axis_stiffness
          << "   # msd.edge_classes.axis.stiffness (face_diagonal: 1)\n  compression_exponent: "
          << r.after.compression_exponent.value_or(0.0)
          << "   # msd.edge_classes.{axis,face_diagonal}.compression_exponent (tension_exponent: 1)\n";
    const double tau0 = r.before.damping_time.value_or(0.0);
    if (r.damping_fitted && r.after.damping_time)
      out << "  damping_time: " << *r.after.damping_time << "   # s, msd.damping_time (stage 2; the material's: "
          << tau0 << ")\n";
    else
      out << "material_damping_time: " << tau0
          << "   # s, not fitted (no ring-down spec): the MSD keeps the material's\n";
    out << "starting_parameters:";
    if (!r.start_file.empty()) out << "   # from " << r.start_file << " (calibrate --start)";
    out << "\n  stiffness_scale: " << r.before.stiffness_scale << "\n  repulsion_factor: "
        << r.before.repulsion_factor << "\n  volume_factor: " << r.before.volume_factor
        << "\n  damping_time: " << r.damping_start << "   # stage 2's start (stage 1 runs with the material's)\n";
    if (r.before.axis_stiffness)
      out << "  axis_stiffness: " << *r.before.axis_stiffness << "\n  compression_exponent: "
          << r.before.compression_exponent.value_or(0.0) << "\n";
    out
        << "volume_weight: " << r.volume_weight << "\n"
        << "objective: {before: " << r.objective_before << ", after: " << r.objective_after << "}   # stage 1\n"
        << "optimiser: {method: Eigen LevenbergMarquardt (MINPACK lmder), status: \"" << r.optimiser_status
        << "\", iterations: " << r.iterations << ", evaluations: " << r.evaluations << "}\n";
    if (r.damping_fitted)
      out << "damping_stage: {objective_before: " << r.damping_objective_before
          << ", objective_after: " << r.damping_objective_after << ", status: \"" << r.damping_status
          << "\", iterations: " << r.damping_iterations << ", evaluations: " << r.damping_evaluations << "}\n";
    out << "specs:   # errors before (the starting constants with the material's damping_time) and after (the "
           "calibrated set)\n";
    for (const auto& s : r.specs) {
      out << "  - {name: " << s.spec << ", sha256: " << s.sha256 << ", series: " << s.load_series
          << ", rel_rms_before: " << s.rel_rms_before << ", rel_rms_after: " << s.rel_rms_after
          << ", volume_max_error_before: " << s.volume_max_error_before
          << ", volume_max_error_after: " << s.volume_max_error_after;
      if (s.ring_down())
        out << ", damping_ratio_fem: " << s.damping_ratio_fem << ", damping_ratio_before: " << s.damping_ratio_before
            << ", damping_ratio_after: " << s.damping_ratio_after << ", frequency_fem: " << s.frequency_fem
            << ", frequency_before: " << s.frequency_before << ", frequency_after: " << s.frequency_after;
      out << "}\n";
    }
    if (!r.checked_on.empty()) {
      out << "checked_on: [";
      for (size_t i = 0; i < r.checked_on.size(); ++i) out << (i ? ", " : "") << r.checked_on[i];
      out << "]   # run with the fitted set after the fit: no blow-up, no inverted element\n";
    }
    out << "reference: {solver: fem, version: \"" << r.fem_version << "\", git_revision: \"" << r.fem_git_revision
        << "\"}\ncreated: " << r.created << "\n";
  });
}

}  // namespace bench
