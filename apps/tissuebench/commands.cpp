#include "commands.hpp"

#include "leg_commands.hpp"
#include "progress.hpp"

#include "bench/calibration.hpp"
#include "bench/compare.hpp"
#include "bench/convergence.hpp"
#include "bench/fem_runner.hpp"
#include "bench/guard.hpp"
#include "bench/msd_runner.hpp"
#include "bench/shared_io.hpp"
#include "bench/stability.hpp"
#include "bench/suite.hpp"
#include "bench/sweep.hpp"
#include "fem/fem.hpp"
#include "leg/scene.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/io/interrupt.hpp"
#include "msd/io/output_lock.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace app {

namespace fs = std::filesystem;

std::vector<std::string> default_suite() {
  return {"uniaxial_thesis_naive.yaml", "uniaxial_thesis_repulsion.yaml", "uniaxial_thesis_full.yaml"};
}

namespace {

bool root() { return fem::Session::rank() == 0; }

// The default leg's grid spacing at the reference stature (m): chosen so the
// cube count is close to the thesis' 959 (docs/leg-geometry.md).

void print_summary_header() {
  std::printf("%-28s %6s %5s %8s %8s %10s %10s %7s %7s %6s %7s %s\n", "spec", "tets", "nodes",
              "eps_min", "eps_max", "sig_min/Pa", "sig_max/Pa", "V/V0min", "V/V0max", "inv", "wall/s",
              "status");
}

void print_summary_row(const bench::RunSummary& s) {
  std::printf("%-28s %6d %5d %8.3f %8.3f %10.2f %10.2f %7.3f %7.3f %6d %7.2f %s\n", s.name.c_str(),
              s.tets, s.nodes, s.min_strain, s.max_strain, s.min_stress, s.max_stress,
              s.min_volume_ratio, s.max_volume_ratio, s.max_inverted, s.wall_seconds,
              s.complete ? "complete" : "FAILED");
}

void print_fem_row(const bench::RunSummary& s) {
  if (s.solver == "fem")
    std::printf("%-28s %-4s %8lu cells %9lu dofs  %6ld steps %8.2f s  %s", s.name.c_str(), s.solver.c_str(),
                s.cells, s.dofs, s.steps, s.wall_seconds, s.complete ? "complete" : "FAILED");
  else
    std::printf("%-28s %-4s %8d tets %9d nodes  %6ld steps %8.2f s  %s", s.name.c_str(), s.solver.c_str(), s.tets,
                s.nodes, s.steps, s.wall_seconds, s.complete ? "complete" : "FAILED");
  if (s.loading == bench::Loading::Uniaxial || s.loading == bench::Loading::SimpleShear)
    std::printf("  stress [%.4g, %.4g] Pa", s.min_stress, s.max_stress);
  if (s.min_volume_ratio < 1e299)
    std::printf("  V/V0 [%.4f, %.4f]", s.min_volume_ratio, s.max_volume_ratio);
  for (const auto& [k, v] : s.highlights) std::printf("  %s = %.6g", k.c_str(), v);
  std::printf("\n");
}

int report(const bench::Spec& spec, const bench::RunSummary& s) {
  if (!root()) return s.complete ? 0 : 1;
  if (s.solver == "msd" && s.loading == bench::Loading::Uniaxial) {
    print_summary_header();
    print_summary_row(s);
  } else {
    print_fem_row(s);
  }
  const std::string csv =
      (fs::path(s.out_path).parent_path() / fs::path(s.out_path).stem()).string().append(".csv");
  if (s.kept) std::printf("results: %s (and %s)\n", s.out_path.c_str(), csv.c_str());
  if (!s.complete) {
    std::cerr << "tissuebench run: " << spec.name << " (" << s.solver << ") " << (s.interrupted ? "stopped" : "failed")
              << ": " << s.failure << "\n";
    if (s.kept)
      std::cerr << "the results written up to then are kept in " << s.out_path << " (status: failed)\n";
    else
      std::cerr << "no results file could be written (" << s.out_path << " is untouched; nothing else was left)\n";
    return s.interrupted ? msd::interrupted_exit_code(s.interrupted) : 1;
  }
  return 0;
}

// The files a run writes must not be its inputs (`--out` naming the spec...).
void refuse_out_over_inputs(const RunArgs& args, const bench::Spec& spec, const std::vector<std::string>& outputs) {
  std::vector<std::string> inputs{args.spec, args.calibration, args.resume};
  if (!spec.geometry.file.empty()) inputs.push_back(spec.geometry.file);
  if (spec.msd && !spec.msd->calibration.empty()) {
    fs::path file = spec.msd->calibration;
    if (file.is_relative()) file = fs::path(args.spec).parent_path() / file;
    inputs.push_back(file.string());
  }
  std::vector<std::string> all;
  for (const std::string& o : outputs) {
    all.push_back(o);
    all.push_back((fs::path(o).parent_path() / fs::path(o).stem()).string() + ".csv");
  }
  msd::refuse_output_over_inputs("--out", all, inputs);
}

}  // namespace

int cmd_run(const RunArgs& args) {
  msd::install_interrupt_handlers();
  bench::Spec spec = bench::load_spec(args.spec);
  if (!args.calibration.empty()) {
    if (!spec.msd) throw msd::Error(args.spec + ": --calibration needs an msd section in the spec");
    if (!spec.msd->calibration.empty())
      throw msd::Error(args.spec + ": the spec already names a calibration (msd.calibration); --calibration would "
                       "override it silently");
    bench::apply_calibration(spec, args.calibration, "--calibration: ");
  }
  if ((args.checkpoint_every > 0.0 || !args.resume.empty()) && args.solver != "msd")
    throw msd::Error(std::string(args.resume.empty() ? "--checkpoint-every" : "--resume") +
                     ": only the msd solver can be checkpointed (the FEM solver's Newton and SUNDIALS IDA state "
                     "is not saved); use --solver msd");
  const std::string msd_out =
      args.solver == "both" ? (fs::path(args.out) / (spec.name + "_msd.h5")).string() : args.out;
  const std::string fem_out = (fs::path(args.out) / (spec.name + "_fem.h5")).string();
  bench::Checkpointing cp;
  cp.every = args.checkpoint_every;
  cp.resume = args.resume;
  std::vector<std::string> outputs{args.out};
  if (args.solver == "both") outputs = {msd_out, fem_out};
  if (args.checkpoint_every > 0.0 && bench::checkpoint_path_for(args.out) != args.resume)
    outputs.push_back(bench::checkpoint_path_for(args.out));  // resuming from it rewrites it: fine
  refuse_out_over_inputs(args, spec, outputs);
  ProgressLine progress(spec.name + " (" + args.solver + ")", !args.quiet && root());
  auto tick = [&](double t, double end) { progress.update(t, end); };
  if (args.solver == "msd") {
    if (!root()) return 0;  // the MSD model runs on one process
    const bench::RunSummary s = bench::run_msd(spec, args.out, tick, cp);
    progress.done();
    return report(spec, s);
  }
  if (args.solver == "fem") {
    const bench::RunSummary s = bench::run_fem(spec, args.out, tick);
    progress.done();
    return report(spec, s);
  }
  // both: args.out is a folder holding NAME_msd.h5 and NAME_fem.h5.
  bench::RunSummary m;
  if (root()) m = bench::run_msd(spec, msd_out, tick);
  progress.done();
  if (m.interrupted) return report(spec, m);
  ProgressLine fem_progress(spec.name + " (fem)", !args.quiet && root());
  const bench::RunSummary f = bench::run_fem(spec, fem_out, [&](double t, double end) { fem_progress.update(t, end); });
  fem_progress.done();
  const int a = root() ? report(spec, m) : 0;
  const int b = report(spec, f);
  if (a == 0 && b == 0 && root()) {
    const bench::Comparison c = bench::compare_results(m.out_path, f.out_path);
    const std::string json = (fs::path(args.out) / (spec.name + "_compare.json")).string();
    bench::write_comparison_json(c, json);
    std::printf("%scomparison: %s\n", bench::format_comparison(c).c_str(), json.c_str());
  }
  return std::max(a, b);
}

int cmd_calibrate(const CalibrateArgs& args) {
  if (fem::Session::size() > 1) throw msd::Error("calibrate runs on one process (no mpirun)");
  std::vector<std::string> specs = args.specs;
  if (specs.empty())
    for (const char* n : {"calibrate_uniaxial.yaml", "calibrate_shear.yaml", "calibrate_ringdown.yaml"})
      specs.push_back((fs::path(TISSUEBENCH_SPECS_DIR) / n).string());
  auto log = [&](const std::string& line) {
    if (!args.quiet) std::printf("%s\n", line.c_str()), std::fflush(stdout);
  };
  std::optional<bench::CalibrationStart> start;
  if (!args.start.empty()) {
    start = bench::CalibrationStart{{}, args.start, ""};
    start->parameters = bench::read_calibration(args.start, &start->material);
  }
  const bench::CalibrationResult r = bench::calibrate(args.material, specs, args.out, {}, log,
                                                      args.max_evaluations, args.volume_weight,
                                                      args.max_damping_evaluations, args.edge_classes,
                                                      args.no_check ? std::vector<std::string>{}
                                                      : args.check_specs.empty() ? bench::shipped_benchmark_specs()
                                                                                 : args.check_specs,
                                                      start);
  const std::string file = (fs::path(args.out) / (args.material + ".yaml")).string();
  bench::write_calibration(r, file);
  std::printf("Calibration of %s: %s after %d iterations, %d evaluations\n", r.material.c_str(),
              r.optimiser_status.c_str(), r.iterations, r.evaluations);
  std::printf("%-20s %10s %10s\n", "parameter", "before", "after");
  std::printf("%-20s %10.4g %10.4g\n", "stiffness_scale", r.before.stiffness_scale, r.after.stiffness_scale);
  std::printf("%-20s %10.4g %10.4g\n", "repulsion_factor", r.before.repulsion_factor, r.after.repulsion_factor);
  std::printf("%-20s %10.4g %10.4g\n", "volume_factor", r.before.volume_factor, r.after.volume_factor);
  if (r.after.axis_stiffness) {
    std::printf("%-20s %10.4g %10.4g\n", "axis_stiffness", *r.before.axis_stiffness, *r.after.axis_stiffness);
    std::printf("%-20s %10.4g %10.4g\n", "compression_exp.", *r.before.compression_exponent,
                *r.after.compression_exponent);
  }
  if (r.damping_fitted)
    std::printf("%-20s %10.4g %10.4g   (stage 2: %s after %d evaluations)\n", "damping_time [s]",
                r.before.damping_time.value_or(0.0), r.after.damping_time.value_or(0.0), r.damping_status.c_str(),
                r.damping_evaluations);
  else
    std::printf("%-20s %10.4g %10s   (not fitted: no ring-down spec)\n", "damping_time [s]",
                r.before.damping_time.value_or(0.0), "-");
  std::printf("%-20s %10.4g %10.4g\n", "objective (stage 1)", r.objective_before, r.objective_after);
  std::printf("%-20s %-16s %12s %12s %12s %12s\n", "spec", "series", "relRMS before", "relRMS after",
              "dV max before", "dV max after");
  for (const auto& s : r.specs)
    std::printf("%-20s %-16s %12.4f %12.4f %12.4f %12.4f\n", s.spec.c_str(), s.load_series.c_str(),
                s.rel_rms_before, s.rel_rms_after, s.volume_max_error_before, s.volume_max_error_after);
  for (const auto& s : r.specs)
    if (s.ring_down())
      std::printf("%s: damping ratio FEM %.4f, MSD %.4f before, %.4f after; first frequency FEM %.3f Hz, MSD %.3f "
                  "before, %.3f after\n",
                  s.spec.c_str(), s.damping_ratio_fem, s.damping_ratio_before, s.damping_ratio_after, s.frequency_fem,
                  s.frequency_before, s.frequency_after);
  std::printf("calibration: %s (use: tissuebench run SPEC --calibration %s, or msd.calibration in a spec)\n",
              file.c_str(), file.c_str());
  return 0;
}

int cmd_sweep(const SweepArgs& args) {
  const bench::Spec spec = bench::load_spec(args.spec);
  bench::SweepGrid g;
  g.spacing = args.spacing;
  g.dt = args.dt;
  g.integrators = args.integrators;
  g.term_sets = args.terms;
  for (const auto& t : args.thresholds) {
    if (t == "off") {
      g.thresholds.push_back(0.0);
      continue;
    }
    try {
      g.thresholds.push_back(std::stod(t));
    } catch (const std::exception&) {
      throw msd::Error("--thresholds: '" + t + "' is neither 'off' nor a number");
    }
  }
  g.cvode = !args.no_cvode;
  g.quasi_static = args.quasi_static;
  for (const auto& l : args.fem_levels) {
    unsigned degree = 0, refinement = 0;
    char colon = 0;
    std::istringstream in(l);
    if (!(in >> degree >> colon >> refinement) || colon != ':' || !in.eof() || degree < 1 || degree > 3 ||
        refinement > 6)
      throw msd::Error("--fem-levels: '" + l + "' is not DEGREE:REFINEMENT (degree 1-3, refinement 0-6)");
    g.fem_levels.emplace_back(degree, refinement);
  }
  bench::SweepOptions o;
  o.out_dir = args.out;
  o.reference = args.reference;
  o.point_timeout = args.point_timeout;
  o.executable = fs::canonical("/proc/self/exe").string();
  if (!args.quiet)
    o.log = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
  const bench::SweepResult r = bench::run_sweep(spec, g, o);
  if (!root()) return 0;
  const std::string json = (fs::path(args.out) / (spec.name + "_sweep.json")).string();
  const std::string csv = (fs::path(args.out) / (spec.name + "_sweep.csv")).string();
  bench::write_sweep_json(r, json);
  bench::write_sweep_csv(r, csv);
  std::printf("%s", bench::format_sweep(r).c_str());
  std::printf("sweep: %s (and %s)\n", json.c_str(), csv.c_str());
  return 0;
}

int cmd_stability(const StabilityArgs& args) {
  if (!root()) return 0;  // the MSD model runs on one process
  const bench::Spec spec = bench::load_spec(args.spec);
  for (const auto& t : args.terms) bench::term_set(t);  // bad names fail before anything runs
  std::function<void(const std::string&)> log;
  if (!args.quiet)
    log = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
  std::vector<bench::DtSearch> searches;
  std::vector<bench::ExtremeRow> extremes;
  if (!args.no_dt_search)
    for (const auto& i : args.integrators) {
      msd::parse_integrator(i);
      for (const auto& t : args.terms) searches.push_back(bench::search_dt(spec, i, t, {}, log));
    }
  if (!args.no_extremes) extremes = bench::run_extremes(spec, args.terms, log);
  fs::create_directories(args.out);
  const std::string json = (fs::path(args.out) / (spec.name + "_stability.json")).string();
  bench::write_stability_json(spec.name, searches, extremes, json);
  if (!searches.empty())
    std::printf("Largest stable time step of %s (h = %g m; detector: non-finite / blow-up, energy growth x10, "
                "unrecoverable inversion)\n%s",
                spec.name.c_str(), spec.mesh ? spec.mesh->spacing : 0.0, bench::format_dt_searches(searches).c_str());
  if (!extremes.empty())
    std::printf("Extreme loads of %s (load: %s)\n%s", spec.name.c_str(),
                spec.loading.type == bench::Loading::Uniaxial ? "nominal stress, Pa" : "-", bench::format_extremes(extremes).c_str());
  std::printf("stability: %s\n", json.c_str());
  return 0;
}

int cmd_compare(const CompareArgs& args) {
  if (!root()) return 0;
  const bench::Comparison c = bench::compare_results(args.msd, args.fem);
  std::printf("%s", bench::format_comparison(c).c_str());
  if (!args.json.empty()) {
    bench::write_comparison_json(c, args.json);
    std::printf("comparison: %s\n", args.json.c_str());
  }
  return 0;
}

int cmd_check(const CheckArgs& args) {
  if (!root()) return 0;
  if (args.dirs.size() > 1 && !args.update)
    throw msd::Error("check: several folders are for --update (a baseline from repeated runs); check one at a time");
  if (args.update && args.dirs.size() > 1) {
    std::vector<std::map<std::string, double>> runs;
    for (const auto& d : args.dirs) runs.push_back(bench::collect_metrics(d));
    bench::Baseline old;
    if (args.tier.empty() && fs::exists(args.baseline)) old = bench::read_baseline(args.baseline);
    std::vector<bench::Spread> spreads;
    std::vector<std::string> changes;
    const bench::Baseline b =
        bench::baseline_from_runs(runs, args.tier.empty() ? old.tier : args.tier, spreads, changes);
    if (b.metrics.empty()) throw msd::Error("check --update: no metric is present in every folder");
    bench::write_baseline(b, args.baseline);
    std::printf("baseline %s from %zu runs: %zu metrics, tolerances from the measured spread\n", args.baseline.c_str(),
                runs.size(), b.metrics.size());
    std::printf("  %-64s %14s %14s %10s %10s\n", "metric", "min", "max", "spread %", "tol %");
    for (const auto& s : spreads)
      std::printf("  %-64s %14.8g %14.8g %10.4g %10.4g\n", s.key.c_str(), s.min, s.max, 100.0 * s.relative(),
                  100.0 * b.metrics.at(s.key).tolerance);
    for (const auto& c : changes) std::printf("  %s\n", c.c_str());
    return 0;
  }
  const std::string& dir = args.dirs.at(0);
  // A malformed baseline is bad input whatever the folder holds: read it first.
  const bench::Baseline baseline = args.update ? bench::Baseline{} : bench::read_baseline(args.baseline);
  const std::map<std::string, double> metrics = bench::collect_metrics(dir);
  if (args.update) {
    bench::Baseline old;
    if (fs::exists(args.baseline)) old = bench::read_baseline(args.baseline);
    if (!args.tier.empty()) old.tier = args.tier;
    std::vector<std::string> changes;
    const bench::Baseline b = bench::updated_baseline(metrics, old, changes);
    bench::write_baseline(b, args.baseline);
    std::printf("baseline %s updated from %s: %zu metrics, %zu changes\n", args.baseline.c_str(), dir.c_str(),
                b.metrics.size(), changes.size());
    for (const auto& c : changes) std::printf("  %s\n", c.c_str());
    return 0;
  }
  const bench::GuardReport r = bench::check_metrics(metrics, baseline);
  for (const auto& n : r.notes) std::printf("  note: %s\n", n.c_str());
  if (r.ok()) {
    std::printf("check: all %d baseline metrics hold (%s against %s)\n", r.checked, dir.c_str(),
                args.baseline.c_str());
    return 0;
  }
  std::printf("check: %zu of %d baseline metrics moved beyond their tolerance or are missing (%s against %s):\n",
              r.failures.size(), r.total, dir.c_str(), args.baseline.c_str());
  for (const auto& f : r.failures) std::printf("  %s\n", f.c_str());
  return 1;
}

namespace {

// The thesis' three uni-axial experiments, MSD only (`suite --tier thesis`).
int thesis_suite(const SuiteArgs& args) {
  const std::string dir = args.specs_dir.empty() ? TISSUEBENCH_SPECS_DIR : args.specs_dir;
  // Read every spec first: a bad one stops the suite before anything runs.
  std::vector<bench::Spec> specs;
  for (const auto& name : default_suite()) specs.push_back(bench::load_spec((fs::path(dir) / name).string()));
  fs::create_directories(args.out);
  std::vector<bench::RunSummary> rows;
  for (const auto& spec : specs) {
    ProgressLine progress(spec.name, !args.quiet);
    rows.push_back(bench::run_msd(spec, (fs::path(args.out) / (spec.name + ".h5")).string(),
                                  [&](double t, double end) { progress.update(t, end); }));
  }
  std::printf("Thesis uni-axial experiments (5.2.1-5.2.5), MSD model, revision %s\n",
              bench::git_revision().c_str());
  print_summary_header();
  bool ok = true;
  for (const auto& r : rows) {
    print_summary_row(r);
    ok = ok && r.complete;
  }
  std::printf("results in %s/ (HDF5 + CSV per spec; layout: benchmarks/RESULTS.md)\n", args.out.c_str());
  return ok ? 0 : 1;
}

}  // namespace

int cmd_suite(const SuiteArgs& args) {
  if (args.tier == "thesis") return root() ? thesis_suite(args) : 0;
  const std::string tier_file = args.tier == "quick" || args.tier == "full"
                                    ? (fs::path(TISSUEBENCH_SUITES_DIR) / (args.tier + ".yaml")).string()
                                    : args.tier;
  if (!fs::exists(tier_file))
    throw msd::Error("--tier: '" + args.tier + "' is neither quick, full, thesis nor a tier file");
  const bench::SuiteTier tier = bench::load_tier(tier_file);
  bench::SuiteOptions o;
  o.out_dir = args.out;
  o.specs_dir = args.specs_dir.empty() ? TISSUEBENCH_SPECS_DIR : args.specs_dir;
  o.calibration_dir = TISSUEBENCH_CALIBRATION_DIR;
  o.executable = fs::canonical("/proc/self/exe").string();
  if (!args.quiet && root())
    o.log = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
  o.scenes_dir = std::string(TISSUEBENCH_DATA_DIR) + "/scenes";
  o.check_leg = [](const std::string& file) { (void)leg::read_leg_scene(file); };
  o.run_leg = [](const std::string& file, const std::string& out, const bench::Progress& progress) {
    return run_leg_for_suite(file, out, progress);
  };
  std::vector<std::unique_ptr<ProgressLine>> lines;
  o.progress = [&](const std::string& label) -> bench::Progress {
    if (!lines.empty()) lines.back()->done();  // one bar per run: the last one ends its line
    lines.push_back(std::make_unique<ProgressLine>(label, !args.quiet && root()));
    ProgressLine* p = lines.back().get();
    return [p](double t, double end) { p->update(t, end); };
  };
  const int failed = bench::run_suite(tier, o);
  if (!root()) return 0;
  // The summary table: every comparison's main errors.
  std::printf("\nSuite %s: MSD against FEM (relative RMS of the load curve; working range where defined)\n",
              tier.name.c_str());
  std::printf("%-22s %-11s %10s %10s %10s %10s\n", "benchmark", "variant", "load %", "work. %", "dV max", "cost x");
  for (const auto& v : tier.variants) {
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(fs::path(args.out) / v)) files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      if (f.size() < 13 || f.compare(f.size() - 13, 13, "_compare.json") != 0) continue;
      const YAML::Node j = YAML::LoadFile(f);
      auto num = [&](const char* k) {
        return j[k] && !j[k].IsNull() ? j[k].as<double>() : std::numeric_limits<double>::quiet_NaN();
      };
      auto cell = [](double x) { return std::isnan(x) ? std::string("-") : bench::json_number(x, 3); };
      std::printf("%-22s %-11s %10s %10s %10s %10s\n", j["spec"].as<std::string>().c_str(), v.c_str(),
                  cell(100 * num("load_rel_rms")).c_str(), cell(100 * num("load_rel_rms_working")).c_str(),
                  cell(num("volume_ratio_max_error")).c_str(), cell(num("cost_ratio")).c_str());
    }
  }
  if (failed) std::printf("%d MSD run(s) failed (blow-ups are results: see %s/suite.json)\n", failed, args.out.c_str());
  if (args.no_report) return 0;
  const std::string cmd = "/usr/bin/python3 " + (fs::path(TISSUEBENCH_REPORTS_DIR) / "make_report.py").string() +
                          " '" + args.out + "'";
  std::fflush(stdout);
  const int code = std::system(cmd.c_str());
  if (code != 0) {
    std::fprintf(stderr, "tissuebench: error: the report failed (%s exited %d); the results are in %s\n", cmd.c_str(),
                 code, args.out.c_str());
    return 1;
  }
  return 0;
}

int cmd_converge(const ConvergeArgs& args) {
  const bench::Spec spec = bench::load_spec(args.spec);
  const unsigned degree = args.degree ? args.degree : spec.fem.degree;
  if (root()) fs::create_directories(args.out);
  ProgressLine progress(spec.name + " (convergence)", !args.quiet && root());
  const bench::ConvergenceStudy st = bench::run_convergence(
      spec, args.levels, degree, args.out, [&](double t, double end) { progress.update(t, end); });
  progress.done();
  if (!root()) return 0;
  const std::string json = (fs::path(args.out) / (spec.name + "_p" + std::to_string(degree) + "_convergence.json")).string();
  bench::write_convergence_json(st, json);
  std::printf("Refinement study of %s (Q%u), quantity %s [%s]\n", spec.name.c_str(), degree, st.quantity.c_str(),
              st.units.c_str());
  std::printf("%6s %9s %10s %10s %14s %14s\n", "level", "cells", "dofs", "wall/s", "peak value", "RMS diff");
  for (size_t k = 0; k < st.levels.size(); ++k) {
    const auto& L = st.levels[k];
    std::printf("%6d %9lu %10lu %10.2f %14.8g", L.level, L.run.cells, L.run.dofs, L.run.wall_seconds,
                bench::peak(L.values));
    if (k > 0) std::printf(" %14.4g", st.differences[k - 1]);
    std::printf("\n");
  }
  std::printf("observed order %.3f; estimated RMS error of the finest level %.4g %s (%.3g %% of max |value|)\n",
              st.observed_order, st.finest_error, st.units.c_str(), 100.0 * st.finest_relative_error);
  std::printf("study: %s\n", json.c_str());
  return 0;
}

int cmd_inspect(const InspectArgs& args) {
  if (!root()) return 0;
  const bench::Spec spec = bench::load_spec(args.spec);
  const bench::MsdProblem p = bench::compile_msd(spec);
  std::printf("spec          %s (%s)\n", spec.name.c_str(), spec.path.c_str());
  std::printf("grid          %d x %d x %d cubes of h = %g m, rule %s\n", p.sample.grid.nx,
              p.sample.grid.ny, p.sample.grid.nz, p.sample.grid.spacing, spec.mesh->rule.c_str());
  std::printf("mesh          %ld cubes, %d tets, %d nodes, min quality %.3f\n", p.sample.cubes,
              p.model.num_elements(), p.model.num_nodes(), msd::min_quality(p.sample.mesh));
  std::printf("sample        size %g m, V0 = %g m^3, mass = %g kg, loading %s\n", p.size,
              msd::total_volume(p.model.rest_positions, p.sample.mesh.tets), p.model.mass.sum(), bench::loading_name(p.loading));
  if (p.loading == bench::Loading::Uniaxial || p.loading == bench::Loading::SimpleShear)
    std::printf("platens       l0 = %g m, A0 = %g m^2\n", p.platens.length, p.platens.area);
  std::printf("terms         %s, threshold %s\n", msd::force_terms_to_string(p.model.terms).c_str(),
              p.model.nonlinear_threshold > 0 ? std::to_string(p.model.nonlinear_threshold).c_str() : "off");
  for (const auto& [k, v] : bench::material_record(spec, p.model)) std::printf("  %-20s %g\n", k.c_str(), v);
  return 0;
}

}  // namespace app
