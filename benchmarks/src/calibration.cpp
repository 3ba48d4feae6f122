#include "bench/calibration.hpp"

#include "bench/compare.hpp"

#include "bench/fem_runner.hpp"
#include "bench/msd_runner.hpp"
#include "bench/results_file.hpp"
#include "bench/series_tools.hpp"
#include "bench/sha256.hpp"

#include <unsupported/Eigen/NonLinearOptimization>
#include <yaml-cpp/yaml.h>

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
};

// Residuals of one parameter set, appended to r. Returns false if the MSD run failed.
bool residuals(const std::vector<Target>& targets, const CalibrationParameters& p, std::vector<double>& r,
               std::vector<std::pair<double, double>>* errors = nullptr) {
  r.clear();
  for (const Target& tg : targets) {
    std::map<std::string, std::vector<double>> s;
    try {
      s = simulate_msd(with_parameters(tg.spec, p));
    } catch (const msd::SimulationFailure&) {
      return false;
    }
    const auto& tm = s.at("time");
    const auto& ym = s.at(tg.series);
    const double n = static_cast<double>(tg.t.size());
    double sum = 0.0, vmax = 0.0;
    for (size_t i = 0; i < tg.t.size(); ++i) {
      const double y = interpolate(tm, ym, tg.t[i]);
      if (std::isnan(y)) return false;  // the run did not reach a reference time
      const double d = (y - tg.y[i]) / tg.rms;
      r.push_back(d / std::sqrt(n));
      sum += d * d;
      if (tg.volume) {
        const double dv = interpolate(tm, s.at("volume_ratio"), tg.t[i]) - tg.v[i];
        r.push_back(tg.volume_weight * dv / std::sqrt(n));
        vmax = std::max(vmax, std::abs(dv));
      }
    }
    if (errors) errors->push_back({std::sqrt(sum / n), vmax});
  }
  return true;
}

struct Fit {
  const std::vector<Target>& targets;
  const CalibrationBounds& b;
  int m;
  int* evaluations;
  int budget;
  const std::function<void(const std::string&)>& log;
  mutable Eigen::VectorXd last_q, last_f;

  static double map(double q, double lo, double hi) { return lo + (hi - lo) / (1.0 + std::exp(-q)); }
  CalibrationParameters params(const Eigen::VectorXd& q) const {
    return {map(q[0], b.scale_lo, b.scale_hi), map(q[1], b.repulsion_lo, b.repulsion_hi),
            map(q[2], b.volume_lo, b.volume_hi)};
  }
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
    if (log) {
      std::ostringstream s;
      s << std::setprecision(5) << "  evaluation " << *evaluations << ": scale " << p.stiffness_scale
        << ", repulsion " << p.repulsion_factor << ", volume " << p.volume_factor << " -> objective "
        << f.squaredNorm();
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

double inverse_map(double p, double lo, double hi) {
  const double s = std::clamp((p - lo) / (hi - lo), 1e-6, 1 - 1e-6);
  return std::log(s / (1 - s));
}

std::string load_series_of(const Spec& s) {
  if (s.loading.type != "uniaxial" && s.loading.type != "simple_shear")
    throw msd::Error(s.path + ": calibration specs must be uniaxial or simple_shear");
  return load_series_name(s.loading.type);
}

}  // namespace

CalibrationResult calibrate(const std::string& material, const std::vector<std::string>& spec_files,
                            const std::string& out_dir, const CalibrationBounds& bounds,
                            const std::function<void(const std::string&)>& log, int max_evaluations,
                            double volume_weight) {
  if (!(volume_weight >= 0.0)) throw msd::Error("calibration: the volume weight must be >= 0");
  CalibrationResult res;
  res.material = material;
  res.volume_weight = volume_weight;
  fs::create_directories(out_dir);
  std::vector<Target> targets;
  for (const auto& file : spec_files) {
    std::ifstream in(file);
    if (!in) throw msd::Error(file + ": cannot open calibration spec");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = std::regex_replace(ss.str(), std::regex("library: *[A-Za-z_]+"), "library: " + material);
    Target tg;
    tg.spec = parse_spec(text, file);
    if (!tg.spec.msd) throw msd::Error(file + ": a calibration spec needs an msd section");
    tg.series = load_series_of(tg.spec);
    tg.volume = tg.spec.loading.type == "uniaxial" && volume_weight > 0.0;
    tg.volume_weight = volume_weight;
    const std::string fem_file = (fs::path(out_dir) / (tg.spec.name + "_" + material + "_fem.h5")).string();
    if (log) log("FEM reference: " + tg.spec.name + " (" + material + ")");
    if (ensure_fem_reference(tg.spec, fem_file) && log) log("  reused " + fem_file + " (same spec text)");
    const Results r = read_results(fem_file);
    tg.t = r.series.at("time");
    tg.y = r.series.at(tg.series);
    tg.v = r.series.at("volume_ratio");
    double sum = 0.0;
    for (double v : tg.y) sum += v * v;
    tg.rms = std::sqrt(sum / static_cast<double>(tg.y.size()));
    res.fem_version = r.meta.at("version");
    res.fem_git_revision = r.meta.at("git_revision");
    SpecError e;
    e.spec = tg.spec.name;
    e.sha256 = sha256_hex(tg.spec.text);
    e.load_series = tg.series;
    res.specs.push_back(e);
    targets.push_back(std::move(tg));
  }
  const Spec& first = targets.front().spec;
  res.before = {first.msd->stiffness_scale, first.msd->repulsion_factor, first.msd->volume_factor};
  res.damping_time = first.material.damping_time.value_or(0.0);

  std::vector<double> r0;
  std::vector<std::pair<double, double>> err0;
  if (!residuals(targets, res.before, r0, &err0)) throw msd::Error("calibration: the starting constants are unstable");
  res.objective_before = 0.0;
  for (double v : r0) res.objective_before += v * v;
  for (size_t k = 0; k < err0.size(); ++k) {
    res.specs[k].rel_rms_before = err0[k].first;
    res.specs[k].volume_max_error_before = err0[k].second;
  }
  Eigen::VectorXd q(3);
  q << inverse_map(res.before.stiffness_scale, bounds.scale_lo, bounds.scale_hi),
      inverse_map(res.before.repulsion_factor, bounds.repulsion_lo, bounds.repulsion_hi),
      inverse_map(res.before.volume_factor, bounds.volume_lo, bounds.volume_hi);
  Fit fit{targets, bounds, static_cast<int>(r0.size()), &res.evaluations, max_evaluations, log, {}, {}};
  Eigen::LevenbergMarquardt<Fit> lm(fit);
  lm.parameters.maxfev = 10 * max_evaluations;  // the budget is enforced by Fit (Jacobian columns count)
  lm.parameters.ftol = 1e-6;
  lm.parameters.xtol = 1e-6;
  const Eigen::LevenbergMarquardtSpace::Status status = lm.minimize(q);
  res.iterations = static_cast<int>(lm.iter);
  const char* names[] = {"improper input", "converged (relative reduction)", "converged (relative error)",
                         "converged (both)", "converged (cosinus)", "too many function evaluations",
                         "ftol too small", "xtol too small", "gtol too small", "evaluation budget spent"};
  const int code = static_cast<int>(status);
  res.optimiser_status = (code >= 0 && code < 10) ? names[code] : "status " + std::to_string(code);
  res.after = fit.params(q);
  std::vector<double> r1;
  std::vector<std::pair<double, double>> err1;
  residuals(targets, res.after, r1, &err1);
  res.objective_after = 0.0;
  for (double v : r1) res.objective_after += v * v;
  for (size_t k = 0; k < err1.size(); ++k) {
    res.specs[k].rel_rms_after = err1[k].first;
    res.specs[k].volume_max_error_after = err1[k].second;
  }
  const std::time_t now = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  res.created = buf;
  return res;
}

void write_calibration(const CalibrationResult& r, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw msd::Error(path + ": cannot write the calibration");
  out << std::setprecision(17);  // round-trips exactly
  out << "# MSD constants of " << r.material << " calibrated against the FEM reference\n"
      << "# (tissuebench calibrate; objective and optimiser: benchmarks/include/bench/calibration.hpp).\n"
      << "material: " << r.material << "\n"
      << "parameters:\n  stiffness_scale: " << r.after.stiffness_scale << "\n  repulsion_factor: "
      << r.after.repulsion_factor << "\n  volume_factor: " << r.after.volume_factor << "\n"
      << "damping_time: " << r.damping_time << "   # not fitted (see the header)\n"
      << "starting_parameters:\n  stiffness_scale: " << r.before.stiffness_scale << "\n  repulsion_factor: "
      << r.before.repulsion_factor << "\n  volume_factor: " << r.before.volume_factor << "\n"
      << "volume_weight: " << r.volume_weight << "\n"
      << "objective: {before: " << r.objective_before << ", after: " << r.objective_after << "}\n"
      << "optimiser: {method: Eigen LevenbergMarquardt (MINPACK lmder), status: \"" << r.optimiser_status
      << "\", iterations: " << r.iterations << ", evaluations: " << r.evaluations << "}\n"
      << "specs:\n";
  for (const auto& s : r.specs)
    out << "  - {name: " << s.spec << ", sha256: " << s.sha256 << ", series: " << s.load_series
        << ", rel_rms_before: " << s.rel_rms_before << ", rel_rms_after: " << s.rel_rms_after
        << ", volume_max_error_before: " << s.volume_max_error_before
        << ", volume_max_error_after: " << s.volume_max_error_after << "}\n";
  out << "reference: {solver: fem, version: \"" << r.fem_version << "\", git_revision: \"" << r.fem_git_revision
      << "\"}\ncreated: " << r.created << "\n";
}

CalibrationParameters read_calibration(const std::string& path, std::string* material) {
  YAML::Node n;
  try {
    n = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw msd::Error(path + ": cannot read the calibration file: " + e.msg);
  }
  if (material) *material = n["material"] ? n["material"].as<std::string>() : "";
  const YAML::Node p = n["parameters"];
  if (!p) throw msd::Error(path + ": no 'parameters' in the calibration file");
  CalibrationParameters c;
  try {
    c.stiffness_scale = p["stiffness_scale"].as<double>();
    c.repulsion_factor = p["repulsion_factor"].as<double>();
    c.volume_factor = p["volume_factor"].as<double>();
  } catch (const YAML::Exception& e) {
    throw msd::Error(path + ": parameters.stiffness_scale, repulsion_factor and volume_factor are required: " +
                     e.msg);
  }
  if (!(c.stiffness_scale > 0.0) || c.repulsion_factor < 0.0 || c.volume_factor < 0.0)
    throw msd::Error(path + ": calibrated parameters out of range");
  return c;
}

void apply_calibration(Spec& spec, const std::string& file, const std::string& where) {
  if (!spec.msd || spec.msd->constants != "physical")
    throw msd::Error(where + file + ": a calibration applies to 'msd.constants: physical'");
  std::string material;
  CalibrationParameters c;
  try {
    c = read_calibration(file, &material);
  } catch (const msd::Error& e) {
    throw msd::Error(where + e.what());
  }
  if (!material.empty() && material != spec.material.name)
    throw msd::Error(where + file + ": calibrated for material '" + material + "', but the spec's material is '" +
                     (spec.material.name.empty() ? std::string("(unnamed)") : spec.material.name) + "'");
  spec.msd->stiffness_scale = c.stiffness_scale;
  spec.msd->repulsion_factor = c.repulsion_factor;
  spec.msd->volume_factor = c.volume_factor;
  spec.msd->calibration = file;
}

}  // namespace bench
