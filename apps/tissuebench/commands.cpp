#include "commands.hpp"

#include "progress.hpp"

#include "bench/msd_runner.hpp"
#include "bench/results_file.hpp"
#include "msd/forces/element_forces.hpp"

#include <cstdio>
#include <filesystem>
#include <iostream>

namespace app {

namespace fs = std::filesystem;

std::vector<std::string> default_suite() {
  return {"uniaxial_thesis_naive.yaml", "uniaxial_thesis_repulsion.yaml", "uniaxial_thesis_full.yaml"};
}

namespace {

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

}  // namespace

int cmd_run(const RunArgs& args) {
  if (args.solver != "msd") {
    std::cerr << "tissuebench run: solver '" << args.solver
              << "' is not available in this build (available: msd)\n";
    return 2;
  }
  const bench::Spec spec = bench::load_spec(args.spec);
  ProgressLine progress(spec.name, !args.quiet);
  const bench::RunSummary s =
      bench::run_msd(spec, args.out, [&](double t, double end) { progress.update(t, end); });
  progress.done();
  print_summary_header();
  print_summary_row(s);
  std::printf("results: %s (and %s)\n", s.out_path.c_str(),
              (fs::path(s.out_path).parent_path() / fs::path(s.out_path).stem()).string().append(".csv").c_str());
  if (!s.complete) {
    std::cerr << "tissuebench run: " << spec.name << " failed: " << s.failure
              << "\nthe results written up to the failure are kept in " << s.out_path
              << " (status: failed)\n";
    return 1;
  }
  return 0;
}

int cmd_suite(const SuiteArgs& args) {
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

int cmd_inspect(const InspectArgs& args) {
  const bench::Spec spec = bench::load_spec(args.spec);
  const bench::MsdProblem p = bench::compile_msd(spec);
  std::printf("spec          %s (%s)\n", spec.name.c_str(), spec.path.c_str());
  std::printf("grid          %d x %d x %d cubes of h = %g m, rule %s\n", p.sample.grid.nx,
              p.sample.grid.ny, p.sample.grid.nz, p.sample.grid.spacing, spec.mesh.rule.c_str());
  std::printf("mesh          %ld cubes, %d tets, %d nodes, min quality %.3f\n", p.sample.cubes,
              p.model.num_elements(), p.model.num_nodes(), msd::min_quality(p.sample.mesh));
  std::printf("sample        l0 = %g m, A0 = %g m^2, V0 = %g m^3, mass = %g kg\n", p.setup.length,
              p.setup.area, p.setup.volume, p.model.mass.sum());
  std::printf("terms         %s, threshold %s\n", msd::force_terms_to_string(p.model.terms).c_str(),
              p.model.nonlinear_threshold > 0 ? std::to_string(p.model.nonlinear_threshold).c_str() : "off");
  for (const auto& [k, v] : bench::material_record(spec, p.model)) std::printf("  %-20s %g\n", k.c_str(), v);
  return 0;
}

}  // namespace app
