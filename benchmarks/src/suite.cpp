#include "bench/suite.hpp"

#include "bench/calibration.hpp"
#include "bench/closed_form.hpp"
#include "bench/compare.hpp"
#include "bench/convergence.hpp"
#include "bench/fem_runner.hpp"
#include "bench/msd_runner.hpp"
#include "bench/shared_io.hpp"
#include "bench/stability.hpp"
#include "bench/sweep.hpp"
#include "fem/fem.hpp"
#include "tbio/json.hpp"

#include <Eigen/Core>
#include <H5public.h>
#include <sundials/sundials_config.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

namespace bench {

namespace fs = std::filesystem;

namespace {

// Recursively merges `edit` into `base`: maps key by key, anything else replaced.
void merge(YAML::Node base, const YAML::Node& edit) {
  for (const auto& kv : edit) {
    const std::string key = kv.first.as<std::string>();
    if (kv.second.IsMap() && base[key] && base[key].IsMap()) merge(base[key], kv.second);
    else base[key] = kv.second;
  }
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

// The value of the first line starting with `key` in a "key: value" or
// key="value" file (/proc/cpuinfo, /etc/os-release).
std::string first_line_with(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      std::string v = line.substr(key.size());
      v.erase(0, v.find_first_not_of(" \t:=\""));
      while (!v.empty() && (v.back() == '"' || v.back() == ' ')) v.pop_back();
      return v;
    }
  return "unknown";
}

std::string memory_gb() {
  std::istringstream in(first_line_with("/proc/meminfo", "MemTotal"));
  double kb = 0.0;
  return (in >> kb) ? json_number(kb / 1048576.0, 3) + " GB" : "unknown";
}

std::vector<std::string> string_list(const Fields& f, const std::string& key) {
  return f.has(key) ? f.text_list(key) : std::vector<std::string>{};
}

std::string edit_text(const Fields& f) {
  if (!f.has("edit")) return "";
  YAML::Emitter e;
  e << f.node()["edit"];
  return e.c_str();
}

}  // namespace

Spec suite_variant(const Spec& spec, const std::string& variant, const std::string& calibration_dir) {
  if (variant == "physical") return spec;
  if (!spec.msd) throw msd::Error(spec.path + ": the suite's msd variants need an msd section");
  if (variant == "thesis") {
    // The thesis' explicit Euler at the spec's step - or, where the spec's
    // integrator chooses its own steps or takes implicit ones far beyond any
    // explicit limit, at 1/100 of the output interval.
    const double dt = has_explicit_step(*spec.msd) ? spec.msd->dt : spec.output.interval / 100.0;
    return spec_variant(spec, [&](YAML::Node& n) {
      YAML::Node m;
      m["constants"] = "raw";
      m["k_s"] = 10.75;  // N/m, thesis 5.2.1
      m["k_d"] = 0.2;    // N s/m, thesis 5.2.1
      m["k_r"] = 3.0;    // N/m, our choice (the thesis gives none)
      m["k_v"] = 50.0;   // N/m, our choice
      m["mass_lumping"] = "equal";
      m["terms"] = std::vector<std::string>{"springs", "dampers", "repulsion", "volume"};
      m["nonlinear_threshold"] = "off";
      m["integrator"] = "explicit_euler";
      m["dt"] = dt;
      n["msd"] = m;
    });
  }
  if (variant == "calibrated" || variant == "lattice") {
    // calibrated: the three factors' fit (MATERIAL.yaml); lattice: the fit with
    // the edge classes (MATERIAL_lattice.yaml, calibrate --edge-classes).
    const YAML::Node root = YAML::Load(spec.text);
    if (!root["material"] || !root["material"]["library"])
      throw msd::Error(spec.path + ": the " + variant + " variant needs a material from the library (material.library)");
    const std::string file =
        (fs::absolute(calibration_dir) /
         (root["material"]["library"].as<std::string>() + (variant == "lattice" ? "_lattice" : "") + ".yaml"))
            .string();
    if (!fs::exists(file)) throw msd::Error(spec.path + ": no calibration " + file + " for its material");
    return spec_variant(spec, [&](YAML::Node& n) {
      for (const char* k : {"stiffness_scale", "repulsion_factor", "volume_factor", "damping_time", "calibration",
                            "edge_classes"})
        n["msd"].remove(k);
      n["msd"]["calibration"] = file;
      // The fitted lattice's volume term is 4-10 times the shipped one, and
      // the non-symmetric part of Newton's matrix with it: Newton on the
      // symmetric part alone (symmetric_ldlt) then crawls - the thesis cycle
      // took 0.25 s per BDF2 step against the whole 12 s cycle in under a
      // minute with sparse_lu (benchmarks/results/2026-12-04-edge-classes.md).
      if (variant == "lattice" && n["msd"]["newton_linear_solver"]) n["msd"]["newton_linear_solver"] = "sparse_lu";
    });
  }
  if (variant == "continuum") {
    // The model ladder's continuum rung on the same mesh, constants and steps:
    // the stable neo-Hookean tet from the material's E and nu with one volume
    // ratio per cube (msd/forces/stable_neo_hookean.hpp) and the spec's edge
    // dampers, in place of the springs, repulsion and volume terms.
    if (spec.msd->constants != "physical" || !spec.material.poisson_ratio)
      throw msd::Error(spec.path + ": the continuum variant needs physical constants and material.poisson_ratio");
    return spec_variant(spec, [&](YAML::Node& n) {
      n["msd"]["terms"] = std::vector<std::string>{"neo_hookean", "dampers"};
      n["msd"]["continuum_volume"] = "per_cube";
    });
  }
  if (variant == "physical_lattice" || variant == "neo_lattice") {
    // The lattice with every constant from E and nu, nothing fitted
    // (docs/msd-model.md section 4, the bulk term).
    //  - physical_lattice: isotropic springs whose shear modulus is the
    //    material's - face diagonals d = 3 mu / (s_lattice E) = 1.8 / (1 + nu),
    //    cube edges a = d / 2 - and the per-cube bulk term with K = lambda - mu,
    //    so the Cauchy-Born elasticity is the continuum's at small strain;
    //  - neo_lattice: zero-length springs with cotangent weights and the bulk
    //    term's neo-Hookean law (msd/forces/zero_length_springs.hpp), whose
    //    energy is the compressible neo-Hookean one at every strain.
    // The static loadings (uni-axial, shear, static) are solved
    // quasi-statically, as the FEM solves them; vibration and indentation keep
    // the spec's integrator (the quasi-static step holds no contact).
    const bool neo = variant == "neo_lattice";
    if (spec.msd->constants != "physical" || !spec.material.poisson_ratio ||
        !(*spec.material.poisson_ratio > (neo ? 0.0 : 0.25)))
      throw msd::Error(spec.path + ": the " + variant + " variant needs physical constants and material.poisson_ratio above " +
                       (neo ? "0" : "0.25"));
    const double d = 1.8 / (1.0 + *spec.material.poisson_ratio);
    const bool statics = spec.loading.type == Loading::Uniaxial || spec.loading.type == Loading::SimpleShear ||
                         spec.loading.type == Loading::Static;
    return spec_variant(spec, [&](YAML::Node& n) {
      for (const char* k : {"stiffness_scale", "repulsion_factor", "volume_factor", "calibration", "edge_classes",
                            "nonlinear_threshold", "continuum_volume"})
        n["msd"].remove(k);
      // Quasi-static, without the dampers: the solve never sees them, but the
      // sampled stresses and reactions evaluate the forces at the state's
      // velocity (the step's mean rate), which the FEM's static solution has
      // no counterpart of.
      n["msd"]["terms"] = statics ? std::vector<std::string>{"springs", "bulk"}
                                  : std::vector<std::string>{"springs", "dampers", "bulk"};
      if (neo) {
        n["msd"]["zero_length_springs"] = true;
      } else {
        n["msd"]["edge_classes"]["axis"]["stiffness"] = d / 2.0;
        n["msd"]["edge_classes"]["face_diagonal"]["stiffness"] = d;
      }
      if (statics) {
        // One equilibrium per output sample; the rung's static matrix (springs
        // and the bulk term, no dampers) is symmetric, so Newton on the
        // symmetric part is exact Newton.
        for (const char* k : {"rtol", "atol"}) n["msd"].remove(k);
        n["msd"]["integrator"] = "quasi_static";
        n["msd"]["dt"] = spec.output.interval;
        n["msd"]["newton_linear_solver"] = "symmetric_ldlt";
      }
    });
  }
  throw msd::Error("suite: unknown variant '" + variant + "' (thesis, physical, calibrated, lattice, continuum, physical_lattice, neo_lattice)");
}

SuiteTier load_tier(const std::string& path) {
  const YAML::Node root = load_yaml_file(path, "tier file");
  const Fields f(root, "", path);
  f.only({"tier", "description", "variants", "benchmarks", "sweeps", "stability", "verification", "convergence", "leg"});
  SuiteTier t;
  t.file = path;
  t.name = f.text("tier");
  t.description = f.text_or("description", "");
  t.variants = f.has("variants") ? f.text_list("variants") : std::vector<std::string>{"physical"};
  for (const auto& v : t.variants)
    if (v != "thesis" && v != "physical" && v != "calibrated" && v != "lattice" && v != "continuum" &&
        v != "physical_lattice" && v != "neo_lattice")
      throw msd::Error(f.where("variants") + "unknown variant '" + v +
                       "' (thesis, physical, calibrated, lattice, continuum, physical_lattice, neo_lattice)");
  auto items = [&](const std::string& key, const std::function<void(const Fields&)>& each) {
    const YAML::Node list = root[key];
    if (!list) return;
    if (!list.IsSequence()) throw msd::Error(f.where(key) + "expected a list");
    for (size_t i = 0; i < list.size(); ++i) {
      if (!list[i].IsMap()) throw msd::Error(f.where(key) + "item " + std::to_string(i) + " must be a mapping");
      each(Fields(list[i], key + "[" + std::to_string(i) + "]", path));
    }
  };
  items("benchmarks", [&](const Fields& b) {
    b.only({"spec", "edit"});
    t.benchmarks.push_back({b.text("spec"), edit_text(b)});
  });
  items("sweeps", [&](const Fields& s) {
    s.only({"spec", "spacing", "dt", "integrators", "terms", "thresholds", "fem_levels", "point_timeout", "quasi_static",
            "cvode"});
    SuiteTier::Sweep w;
    w.spec = s.text("spec");
    if (s.has("spacing")) w.spacing = s.number_list("spacing");
    if (s.has("dt")) w.dt = s.number_list("dt");
    w.integrators = string_list(s, "integrators");
    w.terms = string_list(s, "terms");
    for (const auto& th : string_list(s, "thresholds")) w.thresholds.push_back(th == "off" ? 0.0 : std::stod(th));
    for (const auto& l : string_list(s, "fem_levels")) {
      const auto colon = l.find(':');
      if (colon == std::string::npos) throw msd::Error(s.where("fem_levels") + "'" + l + "' is not DEGREE:REFINEMENT");
      w.fem_levels.emplace_back(std::stoul(l.substr(0, colon)), std::stoul(l.substr(colon + 1)));
    }
    w.point_timeout = s.number_or("point_timeout", 0.0);
    const auto flag = [&](const char* key, bool fallback) {
      const std::string v = s.text_or(key, fallback ? "true" : "false");
      if (v != "true" && v != "false") throw msd::Error(s.where(key) + "is true or false (got '" + v + "')");
      return v == "true";
    };
    w.quasi_static = flag("quasi_static", false);
    w.cvode = flag("cvode", true);
    t.sweeps.push_back(w);
  });
  items("stability", [&](const Fields& s) {
    s.only({"spec", "integrators", "terms", "dt_search", "extremes"});
    SuiteTier::Stability st;
    st.spec = s.text("spec");
    st.integrators = string_list(s, "integrators");
    st.terms = string_list(s, "terms");
    st.dt_search = s.text_or("dt_search", "false") == "true";
    st.extremes = s.text_or("extremes", "true") == "true";
    t.stability.push_back(st);
  });
  if (f.has("verification")) t.verification = f.text_list("verification");
  items("convergence", [&](const Fields& c) {
    c.only({"spec", "levels", "degree", "edit"});
    SuiteTier::Convergence cv;
    cv.spec = c.text("spec");
    for (double l : c.number_list("levels")) cv.levels.push_back(static_cast<int>(l));
    cv.degree = static_cast<unsigned>(c.integer_or("degree", 1));
    cv.edit_yaml = edit_text(c);
    t.convergence.push_back(cv);
  });
  if (f.has("leg")) t.leg = f.text_list("leg");
  if (t.benchmarks.empty()) throw msd::Error(f.where("benchmarks") + "the tier lists no benchmarks");
  return t;
}

tbio::Json provenance_json() {
  auto version = [](int major, int minor, int patch) {
    return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
  };
  tbio::Json j;
  j["cpu"] = first_line_with("/proc/cpuinfo", "model name");
  j["cores"] = std::thread::hardware_concurrency();
  j["memory"] = memory_gb();
  j["os"] = first_line_with("/etc/os-release", "PRETTY_NAME");
  j["compiler"] = std::string("gcc ") + __VERSION__;
  j["eigen"] = version(EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
  j["hdf5"] = version(H5_VERS_MAJOR, H5_VERS_MINOR, H5_VERS_RELEASE);
  j["sundials"] = SUNDIALS_VERSION;
  j["deal_ii"] = fem::library_version();
  j["tissuebench"] = tissuebench_version();
  j["git_revision"] = git_revision();
  return j;
}

namespace {

struct VerificationRow {
  std::string name, quantity, source;
  double value = 0.0, reference = 0.0, rel_error = 0.0;
};

// Runs one verify_*.yaml and measures it against its closed form or published value.
VerificationRow verify(const Spec& spec, const std::string& file) {
  const RunSummary s = run_fem(spec, file);
  if (!s.complete) throw msd::Error(spec.path + ": the verification run failed: " + s.failure);
  const Results r = read_results(file);
  const fem::NeoHookean m = fem_material(spec);
  VerificationRow v;
  v.name = spec.name;
  switch (spec.loading.type) {
    case Loading::Uniaxial: {
      v.quantity = "nominal stress (max error over the path / max stress)";
      v.source = "closed form, homogeneous uni-axial stress";
      double err = 0.0, scale = 0.0;
      const auto& e = r.series.at("strain");
      for (size_t i = 0; i < e.size(); ++i) {
        const double c = neo_hookean_uniaxial(m.mu, m.kappa, e[i]).nominal_stress;
        err = std::max(err, std::abs(r.series.at("nominal_stress")[i] - c));
        scale = std::max(scale, std::abs(c));
      }
      v.value = err;
      v.reference = scale;
      v.rel_error = err / scale;
      break;
    }
    case Loading::SimpleShear: {
      v.quantity = "shear stress (max error / max stress)";
      v.source = "closed form, sigma_xz = mu gamma";
      double err = 0.0, scale = 0.0;
      const auto& g = r.series.at("shear_strain");
      for (size_t i = 0; i < g.size(); ++i) {
        const double c = neo_hookean_simple_shear(m.mu, g[i])[0];
        err = std::max(err, std::abs(r.series.at("shear_stress")[i] - c));
        scale = std::max(scale, std::abs(c));
      }
      v.value = err;
      v.reference = scale;
      v.rel_error = err / scale;
      break;
    }
    case Loading::Static: {
      v.quantity = "self-weight sag of the free end, m";
      v.source = "closed form, rho g L^2 / 2E (small strain)";
      const double E = 9 * m.kappa * m.mu / (3 * m.kappa + m.mu), L = spec.geometry.size.z();
      v.value = -r.series.at("tip_displacement_z").back();
      v.reference = m.density * 9.81 * L * L / (2 * E);
      v.rel_error = (v.value - v.reference) / v.reference;
      break;
    }
    case Loading::CooksMembrane:
      v.quantity = "vertical displacement of the loaded edge's mid-point (48, 52) mm, m";
      v.source = "Pelteret & McBride 2016 (deal.II code gallery): converged 14.74 mm";
      v.value = r.series.at("mid_edge_displacement").back();
      v.reference = 14.74e-3;
      v.rel_error = (v.value - v.reference) / v.reference;
      break;
    case Loading::Vibration: {
      v.quantity = "first axial frequency, Hz";
      v.source = "closed form, sqrt(E / rho) / 4L";
      v.value = r.metrics.at("first_frequency");
      const double E = 9 * m.kappa * m.mu / (3 * m.kappa + m.mu);
      v.reference = bar_first_frequency(E, m.density, spec.geometry.size.z());
      v.rel_error = (v.value - v.reference) / v.reference;
      break;
    }
    case Loading::Indentation:
      throw msd::Error(spec.path + ": no closed form for loading '" + loading_name(spec.loading.type) +
                       "' in the suite's verification");
  }
  return v;
}

Spec edited(const Spec& spec, const std::string& edit_yaml) {
  if (edit_yaml.empty()) return spec;
  const YAML::Node e = YAML::Load(edit_yaml);
  return spec_variant(spec, [&](YAML::Node& n) { merge(n, e); });
}

}  // namespace

namespace {

void log_line(const SuiteOptions& o, const std::string& s) {
  if (o.log) o.log(s);
}

Progress progress_for(const SuiteOptions& o, const std::string& label) {
  return o.progress ? o.progress(label) : Progress{};
}

// A benchmark's FEM spec and its MSD variants.
struct Job {
  Spec fem;
  std::vector<std::pair<std::string, Spec>> variants;
};

// Every spec the tier names, read (and its variants made) before anything runs.
struct SuiteSpecs {
  std::vector<Job> jobs;
  std::vector<Spec> sweeps, stability, verification, convergence;
};

// A file a tier names: beside the tier file first, then in `folder`.
std::string find_tier_file(const SuiteTier& tier, const std::string& folder, const std::string& name) {
  const fs::path beside = fs::path(tier.file).parent_path() / name;
  return fs::exists(beside) ? beside.string() : (fs::path(folder) / name).string();
}

SuiteSpecs read_suite_specs(const SuiteTier& tier, const SuiteOptions& o) {
  auto spec_file = [&](const std::string& name) { return find_tier_file(tier, o.specs_dir, name); };
  SuiteSpecs specs;
  for (const auto& b : tier.benchmarks) {
    Job j{edited(load_spec(spec_file(b.spec)), b.edit_yaml), {}};
    for (const auto& v : tier.variants) j.variants.emplace_back(v, suite_variant(j.fem, v, o.calibration_dir));
    specs.jobs.push_back(std::move(j));
  }
  for (const auto& s : tier.sweeps) specs.sweeps.push_back(load_spec(spec_file(s.spec)));
  for (const auto& s : tier.stability) specs.stability.push_back(load_spec(spec_file(s.spec)));
  for (const auto& s : tier.verification) specs.verification.push_back(load_spec(spec_file(s)));
  for (const auto& c : tier.convergence) specs.convergence.push_back(edited(load_spec(spec_file(c.spec)), c.edit_yaml));
  return specs;
}

// One MSD variant of a benchmark, run and compared with the FEM reference; its
// entry of the manifest's variant list. Counts a failed run in `failed`.
tbio::Json run_variant(const Job& j, const std::string& variant, const Spec& spec, const std::string& fem_file,
                        const fs::path& dir, const SuiteOptions& o, int& failed) {
  const fs::path vdir = dir / variant;
  const std::string msd_file = (vdir / (spec.name + "_msd.h5")).string();
  const std::string cmp_file = (vdir / (spec.name + "_compare.json")).string();
  log_line(o, "[" + j.fem.name + "] MSD, " + variant);
  fs::remove(cmp_file);
  const RunSummary s = run_msd(spec, msd_file, progress_for(o, spec.name + " (msd, " + variant + ")"));
  tbio::Json bj;
  bj["variant"] = variant;
  bj["spec_sha256"] = sha256_hex(spec.text);
  bj["msd_file"] = fs::relative(msd_file, dir).string();
  bj["status"] = s.complete ? "complete" : "failed";
  bj["failure"] = s.failure;
  bj["wall_seconds"] = s.wall_seconds;
  if (s.complete) {
    const Comparison c = compare_results(msd_file, fem_file);
    write_comparison_json(c, cmp_file);
    bj["compare_file"] = fs::relative(cmp_file, dir).string();
    log_line(o, "  " + c.load_series + " relative RMS error " + json_number(100.0 * c.load_rel_rms, 3) + " %");
  } else {
    ++failed;
    log_line(o, "  failed: " + s.failure);
  }
  return bj;
}

// The benchmarks: each FEM reference, then its MSD variants. Returns the
// manifest's benchmark entries; `fem_of_text` maps spec text to FEM file.
tbio::Json run_benchmarks(const std::vector<Job>& jobs, const fs::path& dir, const SuiteOptions& o, int& failed,
                          std::map<std::string, std::string>& fem_of_text) {
  tbio::Json bj = tbio::Json::array();
  for (size_t k = 0; k < jobs.size(); ++k) {
    const Job& j = jobs[k];
    const std::string fem_file = (dir / "fem" / (j.fem.name + "_fem.h5")).string();
    log_line(o, "[" + j.fem.name + "] FEM reference");
    const bool reused = ensure_fem_reference(j.fem, fem_file, progress_for(o, j.fem.name + " (fem)"));
    if (reused) log_line(o, "  reused " + fem_file + " (same spec text)");
    fem_of_text[j.fem.text] = fem_file;
    tbio::Json b;
    b["name"] = j.fem.name;
    b["spec"] = j.fem.path;
    b["spec_sha256"] = sha256_hex(j.fem.text);
    b["loading"] = loading_name(j.fem.loading.type);
    b["description"] = j.fem.description;
    b["fem_file"] = fs::relative(fem_file, dir).string();
    b["variants"] = tbio::Json::array();
    for (const auto& [variant, spec] : j.variants)
      b["variants"].push_back(run_variant(j, variant, spec, fem_file, dir, o, failed));
    bj.push_back(std::move(b));
  }
  return bj;
}

// The speed-accuracy sweeps (reusing the benchmarks' FEM references); returns
// the manifest's list of sweep files.
tbio::Json run_sweeps(const SuiteTier& tier, const std::vector<Spec>& specs, const fs::path& dir,
                      const SuiteOptions& o, const std::map<std::string, std::string>& fem_of_text) {
  tbio::Json sj = tbio::Json::array();
  for (size_t k = 0; k < tier.sweeps.size(); ++k) {
    const auto& w = tier.sweeps[k];
    SweepGrid g;
    g.spacing = w.spacing;
    g.dt = w.dt;
    g.integrators = w.integrators;
    g.term_sets = w.terms;
    g.thresholds = w.thresholds;
    g.fem_levels = w.fem_levels;
    g.quasi_static = w.quasi_static;
    g.cvode = w.cvode;
    SweepOptions so;
    so.out_dir = (dir / "sweep").string();
    so.executable = o.executable;
    so.point_timeout = w.point_timeout;
    if (fem_of_text.count(specs[k].text)) so.reference = fem_of_text.at(specs[k].text);
    log_line(o, "[sweep " + specs[k].name + "]");
    const SweepResult r = run_sweep(specs[k], g, so);
    const std::string json = (dir / "sweep" / (specs[k].name + "_sweep.json")).string();
    write_sweep_json(r, json);
    write_sweep_csv(r, (dir / "sweep" / (specs[k].name + "_sweep.csv")).string());
    sj.push_back(fs::relative(json, dir).string());
  }
  return sj;
}

// The stability searches and extremes; returns the manifest's list of files.
tbio::Json run_stability_checks(const SuiteTier& tier, const std::vector<Spec>& specs, const fs::path& dir,
                                const SuiteOptions& o) {
  tbio::Json tj = tbio::Json::array();
  for (size_t k = 0; k < tier.stability.size(); ++k) {
    const auto& st = tier.stability[k];
    const Spec& spec = specs[k];
    log_line(o, "[stability " + spec.name + "]");
    std::vector<DtSearch> searches;
    std::vector<ExtremeRow> extremes;
    if (st.dt_search)
      for (const auto& i : st.integrators)
        for (const auto& t : st.terms) searches.push_back(search_dt(spec, i, t, {}, {}));
    if (st.extremes) extremes = run_extremes(spec, st.terms, {});
    fs::create_directories(dir / "stability");
    const std::string json = (dir / "stability" / (spec.name + "_stability.json")).string();
    write_stability_json(spec.name, searches, extremes, json);
    tj.push_back(fs::relative(json, dir).string());
  }
  return tj;
}

// The FEM verification against closed forms; returns the manifest's entries.
tbio::Json run_verifications(const std::vector<Spec>& specs, const fs::path& dir, const SuiteOptions& o) {
  tbio::Json vj = tbio::Json::array();
  for (size_t k = 0; k < specs.size(); ++k) {
    const Spec& spec = specs[k];
    log_line(o, "[verification " + spec.name + "]");
    const VerificationRow v = verify(spec, (dir / "verification" / (spec.name + "_fem.h5")).string());
    log_line(o, "  " + v.quantity + ": " + json_number(v.value, 5) + " (reference " + json_number(v.reference, 5) +
               ", relative error " + json_number(v.rel_error, 3) + ")");
    vj.push_back({{"name", v.name},
                  {"quantity", v.quantity},
                  {"source", v.source},
                  {"value", v.value},
                  {"reference", v.reference},
                  {"rel_error", v.rel_error}});
  }
  return vj;
}

// The FEM refinement studies; returns the manifest's list of files.
tbio::Json run_convergence_studies(const SuiteTier& tier, const std::vector<Spec>& specs, const fs::path& dir,
                                   const SuiteOptions& o) {
  tbio::Json cj = tbio::Json::array();
  for (size_t k = 0; k < tier.convergence.size(); ++k) {
    const auto& cv = tier.convergence[k];
    const Spec& spec = specs[k];
    log_line(o, "[convergence " + spec.name + "]");
    const fs::path cdir = dir / "convergence";
    fs::create_directories(cdir);
    const ConvergenceStudy st = run_convergence(spec, cv.levels, cv.degree, cdir.string());
    const std::string json = (cdir / (spec.name + "_convergence.json")).string();
    write_convergence_json(st, json);
    log_line(o, "  observed order " + json_number(st.observed_order, 3) + ", estimated finest-level error " +
               json_number(100.0 * st.finest_relative_error, 3) + " %");
    cj.push_back(fs::relative(json, dir).string());
  }
  return cj;
}

// The manifest's parts, each a JSON array from the runs above.
struct ManifestParts {
  tbio::Json benchmarks, sweeps, stability, verification, convergence, leg = tbio::Json::array();
};

// Writes DIR/suite.json (whole or not at all).
std::string write_manifest(const SuiteTier& tier, const fs::path& dir, double wall, const ManifestParts& parts,
                           int failed) {
  const std::string manifest = (dir / "suite.json").string();
  tbio::Json m;
  m["tier"] = tier.name;
  m["description"] = tier.description;
  m["tier_file"] = tier.file;
  m["created"] = utc_now();
  m["wall_seconds"] = tbio::rounded(wall, 5);
  m["provenance"] = provenance_json();
  m["variants"] = tier.variants;
  m["benchmarks"] = parts.benchmarks;
  m["sweeps"] = parts.sweeps;
  m["stability"] = parts.stability;
  m["verification"] = parts.verification;
  m["convergence"] = parts.convergence;
  m["leg"] = parts.leg;
  m["failed_runs"] = failed;
  tbio::write_json_file(manifest, m);
  return manifest;
}

// The tier's leg scenes, found in the scenes folder (or beside the tier file)
// and read, so a bad scene stops the suite before anything runs.
std::vector<std::string> leg_scene_files(const SuiteTier& tier, const SuiteOptions& o) {
  std::vector<std::string> files;
  if (!tier.leg.empty() && (!o.check_leg || !o.run_leg))
    throw msd::Error(tier.file + ": leg: this program cannot run leg scenes");
  for (const std::string& name : tier.leg) {
    const std::string file = find_tier_file(tier, o.scenes_dir, name);
    if (!fs::exists(file))
      throw msd::Error(tier.file + ": leg: no scene '" + name + "' (looked in " + o.scenes_dir + ")");
    o.check_leg(file);
    files.push_back(file);
  }
  return files;
}

// Each leg scene whole into DIR/leg/SCENE; a failed run is a result (counted).
tbio::Json run_leg_scenes(const std::vector<std::string>& files, const fs::path& dir, const SuiteOptions& o,
                          int& failed) {
  tbio::Json out = tbio::Json::array();
  for (const std::string& file : files) {
    const std::string name = fs::path(file).stem().string();
    const Progress progress = o.progress ? o.progress(name + " (leg)") : Progress{};
    tbio::Json entry = o.run_leg(file, (dir / "leg" / name).string(), progress);
    for (const auto& r : entry["runs"])
      if (r.value("status", "") != "complete") ++failed;
    log_line(o, "leg " + name + ": " + entry.value("status", "?"));
    out.push_back(std::move(entry));
  }
  return out;
}

}  // namespace

int run_suite(const SuiteTier& tier, const SuiteOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path dir = o.out_dir;
  const SuiteSpecs specs = read_suite_specs(tier, o);  // bad input stops the suite before any run
  const std::vector<std::string> leg_files = leg_scene_files(tier, o);
  fs::create_directories(dir);
  int failed = 0;
  std::map<std::string, std::string> fem_of_text;  // spec text -> FEM file (reused by the sweeps)
  ManifestParts parts;
  parts.benchmarks = run_benchmarks(specs.jobs, dir, o, failed, fem_of_text);
  parts.sweeps = run_sweeps(tier, specs.sweeps, dir, o, fem_of_text);
  parts.stability = run_stability_checks(tier, specs.stability, dir, o);
  parts.verification = run_verifications(specs.verification, dir, o);
  parts.convergence = run_convergence_studies(tier, specs.convergence, dir, o);
  parts.leg = run_leg_scenes(leg_files, dir, o, failed);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string manifest = write_manifest(tier, dir, wall, parts, failed);
  log_line(o, "suite " + tier.name + ": " + json_number(wall, 4) + " s; manifest " + manifest);
  return failed;
}

}  // namespace bench
