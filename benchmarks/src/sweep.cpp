#include "bench/sweep.hpp"

#include "bench/compare.hpp"
#include "bench/fem_runner.hpp"
#include "bench/shared_io.hpp"
#include "fem/fem.hpp"
#include "msd/integrate/step.hpp"
#include "msd/io/atomic_file.hpp"
#include "tbio/json.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include <chrono>
#include <thread>

#include <csignal>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

extern char** environ;

namespace bench {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool same(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)); }



// Runs `argv` as a child process with the MPI launcher's variables removed from
// its environment (the child is a process of its own, not a rank of this job),
// stdout and stderr into `log`. Returns the exit code (128 + signal when
// killed) and the child's peak resident memory in kB.
int spawn(const std::vector<std::string>& argv, const std::string& log, long& maxrss_kb, double timeout = 0.0,
          bool* timed_out = nullptr) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<std::string> env_keep;
  for (char** e = environ; *e; ++e) {
    const std::string v = *e;
    bool mpi = false;
    for (const char* prefix : {"OMPI_", "PMIX_", "PMI_", "OPAL_", "HYDRA_", "MPI_LOCALNRANKS", "MPI_LOCALRANKID"})
      if (v.rfind(prefix, 0) == 0) mpi = true;
    if (!mpi) env_keep.push_back(v);
  }
  std::vector<char*> envp;
  for (auto& v : env_keep) envp.push_back(v.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &fa, nullptr, args.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw msd::Error("sweep: cannot start " + argv[0] + ": " + std::strerror(rc));
  int status = 0;
  struct rusage ru {};
  if (timed_out) *timed_out = false;
  if (timeout > 0.0) {
    // Poll until the child ends or its time is up (then it is killed).
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      const pid_t w = wait4(pid, &status, WNOHANG, &ru);
      if (w == pid) break;
      if (w < 0) throw msd::Error("sweep: lost the child process of " + log);
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout) {
        // SIGTERM first: the run stops at its next step and keeps its file
        // marked failed ("interrupted"); SIGKILL if it has not ended in 10 s.
        kill(pid, SIGTERM);
        if (timed_out) *timed_out = true;
        bool ended = false;
        for (int i = 0; i < 500 && !ended; ++i) {
          const pid_t e = wait4(pid, &status, WNOHANG, &ru);
          if (e < 0) throw msd::Error("sweep: lost the child process of " + log);
          ended = e == pid;
          if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        if (!ended) {
          kill(pid, SIGKILL);
          if (wait4(pid, &status, 0, &ru) < 0) throw msd::Error("sweep: lost the child process of " + log);
        }
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  } else if (wait4(pid, &status, 0, &ru) < 0) {
    throw msd::Error("sweep: lost the child process of " + log);
  }
  maxrss_kb = ru.ru_maxrss;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string tail_of(const std::string& file, size_t max_chars = 400) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string s = ss.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s.size() > max_chars ? s.substr(s.size() - max_chars) : s;
}


// Reads what the sweep reports of a point's results file.
void read_point(SweepPoint& p, const std::string& reference, double spec_spacing, std::string& load_series,
                double& load_rms_fem) {
  const Results r = read_results(p.results_file);
  p.status = r.status();
  if (r.meta.count("failure")) p.failure = r.meta.at("failure");
  if (r.timing.count("wall_seconds")) p.wall_seconds = r.timing.at("wall_seconds");
  if (r.timing.count("steps")) p.steps = static_cast<long>(r.timing.at("steps"));
  if (r.timing.count("model_rss_mb")) p.model_rss_mb = r.timing.at("model_rss_mb");
  if (r.series.count("time") && !r.series.at("time").empty()) p.simulated_seconds = r.series.at("time").back();
  if (r.series.count("inverted_elements"))
    for (double v : r.series.at("inverted_elements")) p.max_inverted = std::max(p.max_inverted, static_cast<int>(v));
  if (r.meta.count("mesh_counts"))
    std::sscanf(r.meta.at("mesh_counts").c_str(), "nodes %d, tets %d", &p.nodes, &p.tets);
  if (p.status != "complete") {
    p.failure_time = p.simulated_seconds;
    return;
  }
  if (p.simulated_seconds > 0.0) p.cost = p.wall_seconds / p.simulated_seconds;
  const Comparison c = compare_results(p.results_file, reference, same(p.spacing, spec_spacing));
  p.load_rel_rms = c.load_rel_rms;
  p.load_rel_rms_working = c.load_rel_rms_working;
  p.volume_ratio_max_error = c.volume_ratio_max_error;
  p.displacement_rel_rms = c.displacement_rel_rms;
  p.frequency_rel_error = c.frequency_rel_error;
  load_series = c.load_series;
  load_rms_fem = c.load_rms_fem;
}

}  // namespace

double SweepPoint::error() const { return std::isnan(load_rel_rms_working) ? load_rel_rms : load_rel_rms_working; }

std::vector<std::string> term_set(const std::string& name) {
  if (name == "all") return {"springs", "dampers", "repulsion", "volume"};
  if (name == "no_repulsion") return {"springs", "dampers", "volume"};
  if (name == "no_volume") return {"springs", "dampers", "repulsion"};
  if (name == "springs_dampers") return {"springs", "dampers"};
  if (name == "continuum") return {"neo_hookean", "dampers"};
  if (name == "neo_lattice") return {"springs", "dampers", "bulk"};
  if (name == "neo_lattice_repulsion") return {"springs", "dampers", "bulk", "repulsion"};
  throw msd::Error("sweep: unknown term set '" + name +
                   "' (expected all, no_repulsion, no_volume, springs_dampers, continuum, neo_lattice, neo_lattice_repulsion)");
}

void set_term_set(YAML::Node& msd, const std::string& name) {
  msd["terms"] = term_set(name);
  if (name == "continuum")
    msd["continuum_volume"] = "per_cube";
  else if (msd["continuum_volume"])
    msd.remove("continuum_volume");
  if (msd["bulk_factor"]) msd.remove("bulk_factor");  // the sets with the bulk term take its default
  if (name == "neo_lattice" || name == "neo_lattice_repulsion") {
    msd["zero_length_springs"] = true;
    msd.remove("edge_classes");
  } else if (msd["zero_length_springs"]) {
    msd.remove("zero_length_springs");
  }
}

std::vector<SweepPoint> sweep_points(const Spec& spec, const SweepGrid& g) {
  if (!spec.msd || !spec.mesh) throw msd::Error(spec.path + ": a sweep needs the spec's mesh and msd sections");
  const MsdSpec& ms = *spec.msd;
  std::vector<double> hs = g.spacing.empty() ? std::vector<double>{spec.mesh->spacing, 2 * spec.mesh->spacing}
                                             : g.spacing;
  const double base_dt = ms.integrator == "cvode" ? spec.output.interval / 100 : ms.dt;
  std::vector<double> dts = g.dt.empty() ? std::vector<double>{base_dt, 2.5 * base_dt} : g.dt;
  std::vector<std::string> ints =
      g.integrators.empty() ? std::vector<std::string>{"symplectic_euler", "velocity_verlet", "explicit_euler"}
                            : g.integrators;
  std::vector<std::string> terms =
      g.term_sets.empty() ? std::vector<std::string>{"all", "no_repulsion", "no_volume", "springs_dampers"}
                          : g.term_sets;
  std::vector<double> thr = g.thresholds.empty() ? std::vector<double>{0.0, 0.7} : g.thresholds;
  for (double h : hs)
    if (!(h > 0.0)) throw msd::Error("sweep: mesh spacings must be positive");
  for (double d : dts)
    if (!(d > 0.0)) throw msd::Error("sweep: time steps must be positive");
  for (double d : dts)
    if (d > spec.output.interval)
      throw msd::Error("sweep: time step " + json_number(d) + " s is longer than the spec's output interval " +
                       json_number(spec.output.interval) + " s");
  for (double t : thr)
    if (t < 0.0 || t > 1.0) throw msd::Error("sweep: thresholds lie in [0, 1] (0 = off)");
  for (const auto& i : ints) {
    if (i == "cvode") throw msd::Error("sweep: cvode is added per spatial configuration (see --no-cvode)");
    msd::parse_integrator(i);  // throws on an unknown name
  }
  for (const auto& t : terms) term_set(t);
  std::vector<SweepPoint> pts;
  for (double h : hs)
    for (const auto& t : terms)
      for (double th : thr) {
        for (const auto& i : ints)
          for (double d : dts) {
            SweepPoint p;
            p.spacing = h;
            p.terms = t;
            p.threshold = th;
            p.integrator = i;
            p.dt = d;
            pts.push_back(p);
          }
        if (g.quasi_static && (spec.loading.type == Loading::Uniaxial || spec.loading.type == Loading::SimpleShear ||
                               spec.loading.type == Loading::Static)) {
          SweepPoint p;
          p.spacing = h;
          p.terms = t;
          p.threshold = th;
          p.integrator = "quasi_static";
          p.dt = spec.output.interval;
          pts.push_back(p);
        }
        if (g.cvode && spec.loading.type != Loading::Indentation) {  // CVODE cannot integrate contact
          SweepPoint p;
          p.spacing = h;
          p.terms = t;
          p.threshold = th;
          p.integrator = "cvode";
          p.dt = kNaN;
          pts.push_back(p);
        }
      }
  for (size_t k = 0; k < pts.size(); ++k) pts[k].id = static_cast<int>(k);
  return pts;
}

std::string point_spec_text(const Spec& spec, const SweepPoint& p) {
  YAML::Node n = YAML::Load(spec.text);
  n["mesh"]["spacing"] = p.spacing;
  YAML::Node m = n["msd"];
  m["integrator"] = p.integrator;
  if (p.integrator == "cvode") {
    m.remove("dt");
    m["rtol"] = 1e-8;
    m["atol"] = 1e-10;
  } else {
    m.remove("rtol");
    m.remove("atol");
    m["dt"] = p.dt;
  }
  set_term_set(m, p.terms);
  // Newton's fields belong to the implicit steps: an explicit or CVODE point
  // of a spec shipped with BDF2 (vibration.yaml) drops them.
  if (p.integrator == "cvode" || !msd::is_implicit(msd::parse_integrator(p.integrator)))
    for (const std::string& k : newton_fields()) m.remove(k);
  if (p.integrator == "quasi_static") {
    // No dampers: the solve has no rate, and the sampled stress would add
    // them at the step's mean rate. Newton on the symmetric part is exact
    // Newton where every term has an energy (not the thesis' volume term).
    std::vector<std::string> terms;
    for (const auto& t : term_set(p.terms))
      if (t != "dampers") terms.push_back(t);
    m["terms"] = terms;
    const bool potential = std::find(terms.begin(), terms.end(), "volume") == terms.end();
    m["newton_linear_solver"] = potential ? "symmetric_ldlt" : "sparse_lu";
  }
  if (p.threshold > 0.0) m["nonlinear_threshold"] = p.threshold;
  else m["nonlinear_threshold"] = "off";
  // A calibration fits the thesis' springs: the neo-Hookean lattice takes every constant from E and nu.
  if (spec.msd && !spec.msd->calibration.empty() && p.terms != "neo_lattice")
    m["calibration"] = fs::absolute(spec.msd->calibration).string();
  YAML::Emitter e;
  e << n;
  std::ostringstream s;
  s << "# sweep point " << p.id << " of " << spec.path << " (tissuebench sweep)\n" << e.c_str() << "\n";
  return s.str();
}

void mark_pareto(std::vector<SweepPoint>& pts) {
  for (auto& p : pts) {
    p.pareto = false;
    if (p.status != "complete" || std::isnan(p.cost) || std::isnan(p.error())) continue;
    bool dominated = false;
    for (const auto& q : pts) {
      if (&q == &p || q.status != "complete" || std::isnan(q.cost) || std::isnan(q.error())) continue;
      if (q.cost <= p.cost && q.error() <= p.error() && (q.cost < p.cost || q.error() < p.error())) {
        dominated = true;
        break;
      }
    }
    p.pareto = !dominated;
  }
}

void fill_time_errors(std::vector<SweepPoint>& pts, const std::string& load_series, double load_rms_fem) {
  if (load_series.empty() || !(load_rms_fem > 0.0)) return;
  std::map<int, Results> cvode_runs;  // each CVODE point's file, read once
  for (auto& p : pts) {
    if (p.integrator == "cvode" || p.integrator == "quasi_static" || p.status != "complete") continue;
    const SweepPoint* ref = nullptr;
    for (const auto& q : pts)
      if (q.integrator == "cvode" && q.status == "complete" && same(q.spacing, p.spacing) && q.terms == p.terms &&
          same(q.threshold, p.threshold))
        ref = &q;
    if (!ref) continue;
    if (!cvode_runs.count(ref->id)) cvode_runs.emplace(ref->id, read_results(ref->results_file));
    const Results& b = cvode_runs.at(ref->id);
    const Results a = read_results(p.results_file);
    if (!a.series.count(load_series) || !b.series.count(load_series)) continue;
    const auto& ta = a.series.at("time");
    const auto& tb = b.series.at("time");
    const auto& ya = a.series.at(load_series);
    const auto& yb = b.series.at(load_series);
    double sum = 0.0;
    long n = 0;
    for (size_t i = 0; i < tb.size(); ++i) {
      const double y = interpolate(ta, ya, tb[i]);
      if (std::isnan(y)) continue;
      sum += (y - yb[i]) * (y - yb[i]);
      ++n;
    }
    if (n > 0) p.time_error = std::sqrt(sum / static_cast<double>(n)) / load_rms_fem;
  }
}

namespace {

// Cost of one FEM results file: wall seconds per simulated (load) second.
FemCostRow fem_cost_row(const std::string& file) {
  const Results f = read_results(file);
  FemCostRow row;
  row.results_file = file;
  row.label = f.meta.count("element") ? f.meta.at("element") : std::string("fem");
  if (f.timing.count("dofs")) row.dofs = static_cast<unsigned long>(f.timing.at("dofs"));
  if (f.timing.count("cells")) row.cells = static_cast<unsigned long>(f.timing.at("cells"));
  if (f.timing.count("wall_seconds")) row.wall_seconds = f.timing.at("wall_seconds");
  if (f.series.count("time") && !f.series.at("time").empty()) row.simulated_seconds = f.series.at("time").back();
  if (row.simulated_seconds > 0) row.cost = row.wall_seconds / row.simulated_seconds;
  return row;
}

}  // namespace

namespace {

// The FEM reference of the sweep (all ranks together): the given file, or the
// spec's own run beside the points (reused when the spec text is unchanged).
std::string fem_reference(const Spec& spec, const SweepOptions& o, const fs::path& dir, int rank) {
  const std::string file = o.reference.empty() ? (dir / (spec.name + "_fem.h5")).string() : o.reference;
  if (o.reference.empty()) {
    if (o.log && rank == 0) o.log("FEM reference: " + file);
    const bool reused = ensure_fem_reference(spec, file);
    if (o.log && rank == 0 && reused) o.log("  reused (same spec text)");
  } else if (!fs::exists(o.reference)) {
    throw msd::Error(o.reference + ": no such FEM results file");
  }
  return file;
}

// The FEM at the grid's other accuracy levels (all ranks together; reused when
// unchanged); returns their results files.
std::vector<std::string> run_fem_levels(const Spec& spec, const SweepGrid& grid, const SweepOptions& o,
                                        const fs::path& dir, int rank) {
  std::vector<std::string> level_files;
  for (const auto& [degree, refinement] : grid.fem_levels) {
    if (degree < 1 || degree > 3) throw msd::Error("sweep: FEM level degree must be 1, 2 or 3");
    Spec level = spec;
    level.fem.degree = degree;
    level.fem.refinement = refinement;
    // The spec text is the results file's identity: record the level in it.
    level.text += "\n# sweep FEM level: degree " + std::to_string(degree) + ", refinement " +
                  std::to_string(refinement) + "\n";
    level_files.push_back((dir / (spec.name + "_fem_q" + std::to_string(degree) + "r" + std::to_string(refinement) +
                                  ".h5")).string());
    if (o.log && rank == 0) o.log("FEM level Q" + std::to_string(degree) + ", refinement " + std::to_string(refinement) +
                                  ": " + level_files.back());
    ensure_fem_reference(level, level_files.back());
  }
  return level_files;
}

void name_point_files(std::vector<SweepPoint>& pts, const Spec& spec, const fs::path& points_dir) {
  for (auto& p : pts) {
    const std::string stem = spec.name + "_p" + std::to_string(1000 + p.id).substr(1);
    p.spec_file = (points_dir / (stem + ".yaml")).string();
    p.results_file = (points_dir / (stem + ".h5")).string();
    p.log_file = (points_dir / (stem + ".log")).string();
  }
}

// A point already run from the identical spec text (complete, failed or timed
// out with the same limit) is kept: an interrupted sweep resumes.
bool ran_before(const SweepPoint& p, const std::string& text, const SweepOptions& o) {
  if (!fs::exists(p.results_file) || !fs::exists(p.results_file + ".rss")) return false;
  try {
    const Results old = read_results(p.results_file);
    const bool same_text = old.meta.count("spec") && old.meta.at("spec") == text;
    const bool interrupted = old.meta.count("failure") && old.meta.at("failure").find("interrupted by signal") == 0;
    const bool finished = old.status() == "complete" || (old.status() == "failed" && !interrupted);
    std::ifstream tf(p.results_file + ".timeout");
    double limit = -1.0;
    const bool same_timeout = (tf >> limit) && std::abs(limit - o.point_timeout) < 1e-9;
    return same_text && (finished || same_timeout);
  } catch (const std::exception&) {
    return false;  // unreadable: run again
  }
}

// Runs one point as a child `tissuebench run` (its peak memory and a timeout
// mark beside its results file); throws when the child could not run.
void run_point(const SweepPoint& p, const std::string& text, const SweepOptions& o, int rank, size_t count) {
  msd::write_file_atomically(p.spec_file, [&](std::ostream& f) { f << text; });
  long rss = 0;
  fs::remove(p.results_file);
  fs::remove(p.results_file + ".timeout");
  bool timed_out = false;
  const int code = spawn({o.executable, "run", p.spec_file, "--solver", "msd", "--out", p.results_file, "--quiet"},
                         p.log_file, rss, o.point_timeout, &timed_out);
  if (timed_out)
    msd::write_file_atomically(p.results_file + ".timeout", [&](std::ostream& f) { f << o.point_timeout << "\n"; });
  if (o.log) {
    std::ostringstream s;
    s << "  point " << p.id << "/" << count << " (rank " << rank << "): h " << p.spacing << ", "
      << p.integrator << (p.integrator == "cvode" ? "" : ", dt " + json_number(p.dt, 4)) << ", " << p.terms
      << ", threshold " << (p.threshold > 0 ? json_number(p.threshold, 3) : "off") << " -> exit " << code;
    o.log(s.str());
  }
  // Peak memory goes beside the results (rank 0 reads it when merging).
  msd::write_file_atomically(p.results_file + ".rss", [&](std::ostream& f) { f << rss << "\n"; });
  if (!timed_out && (code == 2 || !fs::exists(p.results_file)))
    throw msd::Error("sweep point " + std::to_string(p.id) + " (" + p.spec_file + ") did not run: " +
                     tail_of(p.log_file));
}

// Rank 0: a point's outcome from its files (a timed-out point from its mark).
void merge_point(SweepPoint& p, SweepResult& res, double spec_spacing) {
  double limit = 0.0;
  if ((std::ifstream(p.results_file + ".timeout") >> limit)) {
    p.status = "timeout";
    p.failure = "stopped after " + json_number(limit, 4) + " s of wall time (sweep --point-timeout)";
    if (fs::exists(p.results_file)) {
      try {
        const Results r = read_results(p.results_file);
        if (r.series.count("time") && !r.series.at("time").empty()) p.failure_time = r.series.at("time").back();
      } catch (const std::exception&) {
      }
    }
    return;
  }
  read_point(p, res.reference_file, spec_spacing, res.load_series, res.load_rms_fem);
  std::ifstream in(p.results_file + ".rss");
  long rss = 0;
  if (in >> rss) p.peak_rss_mb = static_cast<double>(rss) / 1024.0;
}

// The cost of each FEM level and its load curve's error against the reference.
std::vector<FemCostRow> fem_level_rows(const SweepGrid& grid, const std::vector<std::string>& level_files,
                                       const SweepResult& res) {
  const Results f = read_results(res.reference_file);
  std::vector<FemCostRow> rows;
  for (size_t k = 0; k < level_files.size(); ++k) {
    FemCostRow row = fem_cost_row(level_files[k]);
    row.degree = grid.fem_levels[k].first;
    row.refinement = grid.fem_levels[k].second;
    if (!res.load_series.empty() && f.series.count(res.load_series) && res.load_rms_fem > 0.0) {
      const Results lv = read_results(level_files[k]);
      const auto& tf = f.series.at("time");
      const auto& yf = f.series.at(res.load_series);
      double sum = 0.0;
      long n = 0;
      for (size_t i = 0; i < tf.size(); ++i) {
        const double y = interpolate(lv.series.at("time"), lv.series.at(res.load_series), tf[i]);
        if (std::isnan(y)) continue;
        sum += (y - yf[i]) * (y - yf[i]);
        ++n;
      }
      if (n > 0) row.load_rel_rms = std::sqrt(sum / static_cast<double>(n)) / res.load_rms_fem;
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

SweepResult run_sweep(const Spec& spec, const SweepGrid& grid, const SweepOptions& o) {
  const int rank = fem::Session::rank(), size = fem::Session::size();
  std::vector<SweepPoint> pts = sweep_points(spec, grid);
  const fs::path dir = o.out_dir;
  const fs::path points_dir = dir / (spec.name + "_points");
  if (rank == 0) fs::create_directories(points_dir);
  fem::Session::barrier();

  SweepResult res;
  res.spec = spec.name;
  res.spec_path = spec.path;
  res.ranks = size;
  res.reference_file = fem_reference(spec, o, dir, rank);
  const std::vector<std::string> level_files = run_fem_levels(spec, grid, o, dir, rank);
  fem::Session::barrier();

  // Points: rank r runs i mod size == r.
  name_point_files(pts, spec, points_dir);
  for (const auto& p : pts) {
    if (p.id % size != rank) continue;
    const std::string text = point_spec_text(spec, p);
    if (ran_before(p, text, o)) {
      if (o.log) o.log("  point " + std::to_string(p.id) + ": kept from an earlier run (same spec)");
      continue;
    }
    run_point(p, text, o, rank, pts.size());
  }
  fem::Session::barrier();
  if (rank != 0) return {};

  // Merge on rank 0.
  {
    long rss = 0;
    const std::string log = (points_dir / "baseline.log").string();
    spawn({o.executable, "--version"}, log, rss);
    res.baseline_rss_mb = static_cast<double>(rss) / 1024.0;
  }
  for (auto& p : pts) merge_point(p, res, spec.mesh->spacing);
  fill_time_errors(pts, res.load_series, res.load_rms_fem);
  mark_pareto(pts);
  res.points = std::move(pts);

  res.fem = fem_cost_row(res.reference_file);
  res.fem.degree = spec.fem.degree;
  res.fem.refinement = spec.fem.refinement;
  res.fem.load_rel_rms = 0.0;
  res.fem_levels = fem_level_rows(grid, level_files, res);
  return res;
}

void write_sweep_json(const SweepResult& r, const std::string& path) {
  tbio::Json j;
  j["spec"] = r.spec;
  j["spec_path"] = r.spec_path;
  j["load_series"] = r.load_series;
  j["load_rms_fem"] = r.load_rms_fem;
  j["reference"] = r.reference_file;
  j["ranks"] = r.ranks;
  j["baseline_rss_mb"] = r.baseline_rss_mb;
  j["fem"] = {{"label", r.fem.label},
              {"dofs", r.fem.dofs},
              {"cells", r.fem.cells},
              {"wall_seconds", r.fem.wall_seconds},
              {"simulated_seconds", r.fem.simulated_seconds},
              {"cost", r.fem.cost}};
  j["fem_levels"] = tbio::Json::array();
  for (const FemCostRow& l : r.fem_levels)
    j["fem_levels"].push_back({{"label", l.label},
                               {"degree", l.degree},
                               {"refinement", l.refinement},
                               {"dofs", l.dofs},
                               {"cells", l.cells},
                               {"wall_seconds", l.wall_seconds},
                               {"simulated_seconds", l.simulated_seconds},
                               {"cost", l.cost},
                               {"load_rel_rms", l.load_rel_rms},
                               {"file", l.results_file}});
  j["points"] = tbio::Json::array();
  for (const SweepPoint& p : r.points)
    j["points"].push_back({{"id", p.id},
                           {"spacing", p.spacing},
                           {"dt", p.dt},
                           {"integrator", p.integrator},
                           {"terms", p.terms},
                           {"threshold", p.threshold},
                           {"status", p.status},
                           {"failure", p.failure},
                           {"failure_time", p.failure_time},
                           {"tets", p.tets},
                           {"nodes", p.nodes},
                           {"steps", p.steps},
                           {"wall_seconds", p.wall_seconds},
                           {"simulated_seconds", p.simulated_seconds},
                           {"cost", p.cost},
                           {"peak_rss_mb", p.peak_rss_mb},
                           {"model_rss_mb", p.model_rss_mb},
                           {"load_rel_rms", p.load_rel_rms},
                           {"load_rel_rms_working", p.load_rel_rms_working},
                           {"volume_ratio_max_error", p.volume_ratio_max_error},
                           {"displacement_rel_rms", p.displacement_rel_rms},
                           {"frequency_rel_error", p.frequency_rel_error},
                           {"time_error", p.time_error},
                           {"max_inverted", p.max_inverted},
                           {"pareto", p.pareto},
                           {"results_file", p.results_file}});
  tbio::write_json_file(path, j);
}

void write_sweep_csv(const SweepResult& r, const std::string& path) {
  msd::write_file_atomically(path, [&](std::ostream& out) {
    out << "id,spacing,dt,integrator,terms,threshold,status,failure_time,tets,nodes,steps,wall_seconds,"
           "simulated_seconds,cost,peak_rss_mb,model_rss_mb,load_rel_rms,load_rel_rms_working,volume_ratio_max_error,"
           "displacement_rel_rms,frequency_rel_error,time_error,max_inverted,pareto\n";
    auto c = [](double v) { return std::isnan(v) ? std::string() : json_number(v); };
    for (const auto& p : r.points)
      out << p.id << "," << c(p.spacing) << "," << c(p.dt) << "," << p.integrator << "," << p.terms << ","
          << c(p.threshold) << "," << p.status << "," << c(p.failure_time) << "," << p.tets << "," << p.nodes << ","
          << p.steps << "," << c(p.wall_seconds) << "," << c(p.simulated_seconds) << "," << c(p.cost) << ","
          << c(p.peak_rss_mb) << "," << c(p.model_rss_mb) << "," << c(p.load_rel_rms) << "," << c(p.load_rel_rms_working) << ","
          << c(p.volume_ratio_max_error) << "," << c(p.displacement_rel_rms) << "," << c(p.frequency_rel_error)
          << "," << c(p.time_error) << "," << p.max_inverted << "," << (p.pareto ? 1 : 0) << "\n";
  });
}

std::string format_sweep(const SweepResult& r) {
  std::ostringstream s;
  char line[512];
  s << "Speed-accuracy sweep of " << r.spec << " (" << r.points.size() << " points, " << r.ranks
    << " process(es)); errors relative to the FEM " << r.load_series << " RMS " << json_number(r.load_rms_fem, 4)
    << "; '*' = Pareto front (cost vs working-range error)\n";
  std::snprintf(line, sizeof line, "%4s %7s %8s %-16s %-15s %5s %6s %8s %8s %7s %8s %8s %8s %8s %8s %s\n", "id",
                "h/mm", "dt/ms", "integrator", "terms", "thr", "tets", "cost", "+RSS/MB", "status", "err%", "errWR%",
                "dVmax", "disp%", "time%", "");
  s << line;
  auto pct = [](double v) { return std::isnan(v) ? std::string("-") : json_number(100.0 * v, 3); };
  for (const auto& p : r.points) {
    std::snprintf(line, sizeof line, "%4d %7.2f %8s %-16s %-15s %5s %6d %8s %8.1f %7s %8s %8s %8s %8s %8s %s\n", p.id,
                  1e3 * p.spacing, std::isnan(p.dt) ? "adapt" : json_number(1e3 * p.dt, 3).c_str(), p.integrator.c_str(),
                  p.terms.c_str(), p.threshold > 0 ? json_number(p.threshold, 2).c_str() : "off", p.tets,
                  std::isnan(p.cost) ? "-" : json_number(p.cost, 3).c_str(), p.model_rss_mb,
                  p.status == "complete" ? "ok" : p.status == "timeout" ? "TIMEOUT" : "FAILED", pct(p.load_rel_rms).c_str(),
                  pct(p.load_rel_rms_working).c_str(),
                  std::isnan(p.volume_ratio_max_error) ? "-" : json_number(p.volume_ratio_max_error, 3).c_str(),
                  pct(p.displacement_rel_rms).c_str(), pct(p.time_error).c_str(), p.pareto ? "*" : "");
    s << line;
  }
  std::snprintf(line, sizeof line,
                "FEM reference (%s): %lu cells, %lu dofs, %.2f s for %.3g s simulated: cost %.3g (wall s per "
                "simulated s)\n",
                r.fem.label.c_str(), r.fem.cells, r.fem.dofs, r.fem.wall_seconds, r.fem.simulated_seconds, r.fem.cost);
  s << line;
  for (const auto& l : r.fem_levels) {
    std::snprintf(line, sizeof line,
                  "FEM level Q%u, refinement %u (%s): %lu cells, %lu dofs, cost %.3g; load curve %s %% from the "
                  "reference\n",
                  l.degree, l.refinement, l.label.c_str(), l.cells, l.dofs, l.cost,
                  std::isnan(l.load_rel_rms) ? "-" : json_number(100.0 * l.load_rel_rms, 3).c_str());
    s << line;
  }
  std::snprintf(line, sizeof line,
                "cost: wall s per simulated s; +RSS: the run's peak resident memory above the process's before the "
                "model was built (whole process peaks in the JSON; a tissuebench process that runs nothing: "
                "%.1f MB, mostly shared libraries)\n",
                r.baseline_rss_mb);
  s << line;
  return s.str();
}

}  // namespace bench
