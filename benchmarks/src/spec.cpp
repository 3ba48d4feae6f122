#include "bench/spec.hpp"

#include "bench/calibration.hpp"

#include "bench/shared_io.hpp"
#include "msd/core/types.hpp"
#include "msd/integrate/step.hpp"
#include "msd/io/input_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace bench {

namespace fs = std::filesystem;

namespace {

// A field read through its declaration (spec_parameters.cpp).
double number(const Fields& f, const char* path) { return tbio::read_number(f, spec_parameter(path)); }
long integer(const Fields& f, const char* path) { return tbio::read_integer(f, spec_parameter(path)); }
Eigen::Vector3d vector3(const Fields& f, const char* path) { return tbio::read_vector3(f, spec_parameter(path)); }
std::string choice(const Fields& f, const char* path) { return tbio::read_choice(f, spec_parameter(path)); }

// A declared number without a default: empty when the field is absent.
std::optional<double> optional_number(const Fields& f, const char* path) {
  const tbio::Parameter& p = spec_parameter(path);
  if (!f.has(p.key())) return std::nullopt;
  return tbio::read_number(f, p);
}

void one_of(const Fields& f, const std::string& key, const std::string& v,
            const std::vector<std::string>& options) {
  for (const auto& o : options)
    if (v == o) return;
  std::string list;
  for (const auto& o : options) list += (list.empty() ? "" : ", ") + o;
  throw msd::Error(f.where(key) + "'" + v + "' is not one of: " + list);
}

GeometrySpec parse_geometry(const Fields& f, const std::string& source) {
  GeometrySpec g;
  g.shape = choice(f, "geometry.shape");
  if (g.shape == "cylinder") {
    f.only({"shape", "radius", "height", "segments"});
    g.radius = number(f, "geometry.radius");
    g.height = number(f, "geometry.height");
    g.segments = static_cast<int>(integer(f, "geometry.segments"));
  } else if (g.shape == "box") {
    f.only({"shape", "size"});
    g.size = vector3(f, "geometry.size");
    for (int a = 0; a < 3; ++a)
      if (!(g.size[a] > 0.0)) throw msd::Error(f.where("size") + "every side must be positive (m)");
  } else if (g.shape == "cooks_membrane") {
    f.only({"shape"});  // fixed: 48 mm wide, left edge 44 mm, right edge 16 mm, 1 mm thick
  } else {
    f.only({"shape", "file"});
    const std::filesystem::path p(f.text("file"));
    const std::filesystem::path base = std::filesystem::path(source).parent_path();
    g.file = (p.is_absolute() || base.empty()) ? p.string() : (base / p).string();
  }
  return g;
}

MeshSpec parse_mesh(const Fields& f) {
  f.only({"spacing", "rule", "origin", "max_cubes", "memory_limit_gb"});
  MeshSpec m;
  m.spacing = number(f, "mesh.spacing");
  m.rule = choice(f, "mesh.rule");
  if (f.has("origin")) m.origin = vector3(f, "mesh.origin");
  m.max_cubes = integer(f, "mesh.max_cubes");
  if (f.has("memory_limit_gb")) m.memory_limit_gb = number(f, "mesh.memory_limit_gb");
  return m;
}

// A named entry of benchmarks/materials.yaml, merged under the spec's fields.
YAML::Node library_material(const Fields& f) {
  const std::string name = f.text("library");
  const std::string file = TISSUEBENCH_MATERIALS_FILE;
  const YAML::Node lib = load_yaml_file(file, "materials file");
  if (!lib[name]) {
    std::string names;
    for (const auto& kv : lib) names += (names.empty() ? "" : ", ") + kv.first.Scalar();
    throw msd::Error(f.where("library") + "no material '" + name + "' in " + file + " (known: " + names + ")");
  }
  YAML::Node merged = YAML::Clone(lib[name]);
  merged.remove("description");
  for (const auto& kv : f.node())
    if (kv.first.Scalar() != "library") merged[kv.first.Scalar()] = kv.second;
  if (!merged["name"]) merged["name"] = name;
  return merged;
}

MaterialSpec parse_material(const Fields& given) {
  given.only({"library", "name", "density", "youngs_modulus", "poisson_ratio", "shear_modulus", "bulk_modulus",
              "damping_time"});
  const Fields f = given.has("library") ? Fields(library_material(given), "material", given.file()) : given;
  MaterialSpec m;
  m.name = f.text_or("name", "");
  m.density = number(f, "material.density");
  m.youngs_modulus = optional_number(f, "material.youngs_modulus");
  m.poisson_ratio = optional_number(f, "material.poisson_ratio");
  m.shear_modulus = optional_number(f, "material.shear_modulus");
  m.bulk_modulus = optional_number(f, "material.bulk_modulus");
  if (m.shear_modulus.has_value() != m.bulk_modulus.has_value())
    throw msd::Error(f.where() + "give shear_modulus and bulk_modulus together");
  if (m.shear_modulus && (m.youngs_modulus || m.poisson_ratio))
    throw msd::Error(f.where() + "give either youngs_modulus/poisson_ratio or shear_modulus/bulk_modulus, not both");
  m.damping_time = optional_number(f, "material.damping_time");
  return m;
}

// msd.edge_classes: {CLASS: {stiffness, tension_exponent, compression_exponent}}
// for the classes of msd/forces/spring_law.hpp; a class not given keeps the thesis' spring.
void parse_edge_classes(const Fields& f, MsdSpec& m) {
  std::vector<std::string> names;
  for (int c = 0; c < msd::kEdgeClasses; ++c) names.emplace_back(msd::to_string(static_cast<msd::EdgeClass>(c)));
  f.only(std::set<std::string>(names.begin(), names.end()));
  for (int c = 0; c < msd::kEdgeClasses; ++c) {
    const std::string name = names[static_cast<size_t>(c)];
    const auto law = f.optional_section(name);
    if (!law) continue;
    law->only({"stiffness", "tension_exponent", "compression_exponent"});
    msd::SpringLaw& out = m.edge_laws[static_cast<size_t>(c)];
    const std::string base = "msd.edge_classes." + name + ".";
    out.stiffness = number(*law, (base + "stiffness").c_str());
    out.tension_exponent = number(*law, (base + "tension_exponent").c_str());
    out.compression_exponent = number(*law, (base + "compression_exponent").c_str());
    if (out.tension_exponent + out.compression_exponent == 0.0)
      throw msd::Error(law->where("tension_exponent") +
                       "and compression_exponent are both 0: the spring law would have no stiffness");
  }
}

}  // namespace

const std::vector<std::string>& newton_fields() {
  static const std::vector<std::string> fields{"newton_tolerance", "newton_max_iterations", "newton_max_step_cuts",
                                               "newton_reuse_factorization", "newton_linear_solver", "newton_keep_orientation",
                                               "newton_anderson_depth"};
  return fields;
}

bool has_explicit_step(const MsdSpec& msd) {
  return msd.integrator != "cvode" && !msd::is_implicit(msd::parse_integrator(msd.integrator));
}

namespace {

MsdSpec parse_msd(const Fields& f) {
  f.only({"constants", "k_s", "k_d", "k_r", "k_v", "stiffness_scale", "repulsion_factor",
          "volume_factor", "damping_time", "repulsion_floor", "mass_lumping", "terms", "nonlinear_threshold",
          "integrator", "dt", "calibration", "rtol", "atol", "threads", "forces", "newton_tolerance",
          "newton_max_iterations", "newton_max_step_cuts", "newton_reuse_factorization", "newton_linear_solver",
          "newton_keep_orientation", "newton_anderson_depth",
          "continuum_volume", "edge_classes", "bulk_factor", "zero_length_springs"});
  MsdSpec m;
  m.constants = choice(f, "msd.constants");
  const bool raw = m.constants == "raw";
  for (const char* k : {"k_s", "k_d", "k_r", "k_v"})
    if (!raw && f.has(k))
      throw msd::Error(f.where(k) + "raw constants need 'constants: raw'");
  for (const char* k : {"stiffness_scale", "repulsion_factor", "volume_factor", "damping_time", "calibration", "bulk_factor",
                        "zero_length_springs"})
    if (raw && f.has(k))
      throw msd::Error(f.where(k) + "only meaningful with 'constants: physical'");
  if (f.has("calibration")) {
    for (const char* k : {"stiffness_scale", "repulsion_factor", "volume_factor", "damping_time", "edge_classes", "bulk_factor"})
      if (f.has(k))
        throw msd::Error(f.where(k) + "given together with 'calibration', which sets it; give one or the other");
    m.calibration = f.text("calibration");
  }
  if (raw) {
    m.k_s = number(f, "msd.k_s");
    m.k_d = number(f, "msd.k_d");
    m.k_r = number(f, "msd.k_r");
    m.k_v = number(f, "msd.k_v");
  } else {
    m.stiffness_scale = number(f, "msd.stiffness_scale");
    m.repulsion_factor = number(f, "msd.repulsion_factor");
    m.volume_factor = number(f, "msd.volume_factor");
    m.bulk_factor = number(f, "msd.bulk_factor");
    m.damping_time = optional_number(f, "msd.damping_time");
  }
  m.repulsion_floor = number(f, "msd.repulsion_floor");
  m.mass_lumping = choice(f, "msd.mass_lumping");
  if (f.has("terms")) {
    m.terms = f.text_list("terms");
    for (const auto& t : m.terms)
      one_of(f, "terms", t, {"springs", "dampers", "repulsion", "volume", "neo_hookean", "bulk"});
  }
  const auto has_term = [&](const char* t) { return std::find(m.terms.begin(), m.terms.end(), t) != m.terms.end(); };
  if (has_term("bulk") && has_term("neo_hookean"))
    throw msd::Error(f.where("terms") + "bulk and neo_hookean are two volume terms: choose one");
  if (f.has("bulk_factor") && !has_term("bulk"))
    throw msd::Error(f.where("bulk_factor") + "only meaningful with the bulk term in 'terms'");
  if (auto classes = f.optional_section("edge_classes")) parse_edge_classes(*classes, m);
  if (f.has("zero_length_springs")) {
    m.zero_length_springs = tbio::read_flag(f, spec_parameter("msd.zero_length_springs"));
    if (m.zero_length_springs && !(has_term("springs") && has_term("bulk")))
      throw msd::Error(f.where("zero_length_springs") +
                       "needs the springs and the bulk term in 'terms' (the bulk term's rest pressure holds the springs' pull)");
    if (m.zero_length_springs && f.has("calibration"))
      throw msd::Error(f.where("calibration") +
                       "does not apply with zero_length_springs (the calibrations fit the thesis' springs; no calibration for them is shipped)");
    if (m.zero_length_springs && f.has("edge_classes"))
      throw msd::Error(f.where("edge_classes") +
                       "does not apply with zero_length_springs (their weights are the cotangent weights)");
  }
  m.continuum_volume = choice(f, "msd.continuum_volume");
  if (f.has("continuum_volume") && std::find(m.terms.begin(), m.terms.end(), "neo_hookean") == m.terms.end())
    throw msd::Error(f.where("continuum_volume") + "only meaningful with the neo_hookean term in 'terms'");
  if (f.has("nonlinear_threshold")) {
    // `off` (or `false`) is the default, 0; otherwise a fraction in (0, 1].
    const YAML::Node n = f.node()["nonlinear_threshold"];
    const bool off = n.IsScalar() && (n.Scalar() == "off" || n.Scalar() == "false");
    m.nonlinear_threshold = off ? 0.0 : number(f, "msd.nonlinear_threshold");
  }
  m.integrator = choice(f, "msd.integrator");
  m.threads = static_cast<int>(integer(f, "msd.threads"));
  m.forces = choice(f, "msd.forces");
  if (m.integrator == "cvode") {
    m.rtol = number(f, "msd.rtol");
    m.atol = number(f, "msd.atol");
    if (f.has("dt")) throw msd::Error(f.where("dt") + "cvode chooses its own steps (give rtol and atol instead)");
  } else {
    for (const char* k : {"rtol", "atol"})
      if (f.has(k)) throw msd::Error(f.where(k) + "only meaningful with 'integrator: cvode'");
    m.dt = number(f, "msd.dt");
  }
  if (m.integrator != "cvode" && msd::is_implicit(msd::parse_integrator(m.integrator))) {
    m.newton_tolerance = number(f, "msd.newton_tolerance");
    m.newton_max_iterations = static_cast<int>(integer(f, "msd.newton_max_iterations"));
    m.newton_max_step_cuts = static_cast<int>(integer(f, "msd.newton_max_step_cuts"));
    m.newton_reuse_factorization = tbio::read_flag(f, spec_parameter("msd.newton_reuse_factorization"));
    m.newton_linear_solver = choice(f, "msd.newton_linear_solver");
    m.newton_keep_orientation = tbio::read_flag(f, spec_parameter("msd.newton_keep_orientation"));
    m.newton_anderson_depth = static_cast<int>(integer(f, "msd.newton_anderson_depth"));
  } else {
    for (const std::string& k : newton_fields())
      if (f.has(k)) throw msd::Error(f.where(k) + "only meaningful with 'integrator: backward_euler', 'bdf2' or 'quasi_static'");
  }
  return m;
}

FemSpec parse_fem(const Fields& f) {
  f.only({"formulation", "degree", "refinement", "cells", "linear_solver", "residual_tolerance",
          "increment_tolerance", "max_iterations", "max_cuts", "max_increment", "relative_tolerance",
          "absolute_tolerance", "rayleigh_mass", "contact_penalty", "vtu"});
  FemSpec m;
  m.formulation = choice(f, "fem.formulation");
  m.degree = static_cast<unsigned>(integer(f, "fem.degree"));
  m.refinement = static_cast<unsigned>(integer(f, "fem.refinement"));
  if (f.has("cells")) {
    const std::vector<double> c = f.number_list("cells");
    if (c.size() != 3) throw msd::Error(f.where("cells") + "expected three cell counts [nx, ny, nz]");
    std::array<unsigned, 3> cells{};
    for (int a = 0; a < 3; ++a) {
      if (!(c[a] >= 1 && c[a] <= 4096 && c[a] == std::floor(c[a])))
        throw msd::Error(f.where("cells") + "cell counts must be whole numbers from 1 to 4096");
      cells[a] = static_cast<unsigned>(c[a]);
    }
    m.cells = cells;
  }
  m.linear_solver = choice(f, "fem.linear_solver");
  m.residual_tolerance = number(f, "fem.residual_tolerance");
  m.increment_tolerance = number(f, "fem.increment_tolerance");
  m.relative_tolerance = number(f, "fem.relative_tolerance");
  m.absolute_tolerance = number(f, "fem.absolute_tolerance");
  m.max_iterations = static_cast<unsigned>(integer(f, "fem.max_iterations"));
  m.max_cuts = static_cast<unsigned>(integer(f, "fem.max_cuts"));
  m.max_increment = number(f, "fem.max_increment");
  m.rayleigh_mass = number(f, "fem.rayleigh_mass");
  m.contact_penalty = number(f, "fem.contact_penalty");
  // Only the words true and false, as before (read_flag alone would also take yes, on, ...).
  if (f.has("vtu") && f.text("vtu") != "true" && f.text("vtu") != "false")
    throw msd::Error(f.where("vtu") + "expected true or false");
  m.vtu = tbio::read_flag(f, spec_parameter("fem.vtu"));
  return m;
}

std::vector<std::pair<double, double>> parse_path(const Fields& f) {
  std::vector<std::pair<double, double>> path;
  const YAML::Node p = f.node()["path"];
  if (p && p.IsScalar()) {
    if (p.Scalar() != "thesis_cycle")
      throw msd::Error(f.where("path") + "expected 'thesis_cycle' or a list of [time, value]");
    path = {{0.0, 0.0}, {2.0, -0.5}, {4.0, 0.0}, {8.0, 1.0}, {12.0, 0.0}};
  } else {
    path = f.pair_list("path");
  }
  if (path.size() < 2 || path.front().first != 0.0)
    throw msd::Error(f.where("path") + "needs at least two [time, value] points starting at time 0");
  for (size_t i = 1; i < path.size(); ++i)
    if (!(path[i].first > path[i - 1].first))
      throw msd::Error(f.where("path") + "times must increase strictly (point " + std::to_string(i) + ")");
  return path;
}

// A dead load {face, force} (static, vibration with preload).
void parse_traction(const Fields& t, LoadingSpec& l) {
  t.only({"face", "force"});
  l.traction_face = choice(t, "loading.traction.face");
  l.traction = vector3(t, "loading.traction.force");
}

void parse_indenter(const Fields& ind, LoadingSpec& l) {
  ind.only({"shape", "radius", "axis", "depth", "response"});
  choice(ind, "loading.indenter.shape");
  l.indenter_radius = number(ind, "loading.indenter.radius");
  l.indenter_depth = number(ind, "loading.indenter.depth");
  l.indenter_axis = choice(ind, "loading.indenter.axis");
  l.indenter_response = choice(ind, "loading.indenter.response");
}

LoadingSpec parse_loading(const Fields& f) {
  LoadingSpec l;
  l.type = *find_loading(choice(f, "loading.type"));
  const std::vector<std::pair<double, double>> unit_ramp{{0.0, 0.0}, {1.0, 1.0}};
  switch (l.type) {
    case Loading::Uniaxial: {
      f.only({"type", "platens", "path", "gravity"});
      l.platens = choice(f, "loading.platens");
      l.path = parse_path(f);
      for (const auto& [t, e] : l.path)
        if (!(e > -1.0)) throw msd::Error(f.where("path") + "nominal strain must stay above -1");
      break;
    }
    case Loading::SimpleShear: {
      f.only({"type", "boundary", "path"});
      l.boundary = choice(f, "loading.boundary");
      l.path = parse_path(f);
      break;
    }
    case Loading::CooksMembrane: {
      f.only({"type", "force", "path"});
      l.force = number(f, "loading.force");
      l.path = f.has("path") ? parse_path(f) : unit_ramp;
      break;
    }
    case Loading::Static: {
      f.only({"type", "fixed", "traction", "gravity", "path"});
      l.fixed = choice(f, "loading.fixed");
      if (auto t = f.optional_section("traction")) {
        parse_traction(*t, l);
        if (l.traction_face == l.fixed) throw msd::Error(t->where("face") + "the traction face is the fixed face");
      }
      l.path = f.has("path") ? parse_path(f) : unit_ramp;
      break;
    }
    case Loading::Indentation: {
      f.only({"type", "indenter", "path"});
      parse_indenter(f.section("indenter"), l);
      l.path = parse_path(f);
      for (const auto& [t, v] : l.path)
        if (!(v >= 0.0 && v <= 1.0)) throw msd::Error(f.where("path") + "depth factors must lie in [0, 1]");
      break;
    }
    case Loading::Vibration: {
      f.only({"type", "initial", "amplitude", "traction", "release", "duration", "gravity"});
      l.initial = choice(f, "loading.initial");
      l.duration = number(f, "loading.duration");
      if (l.initial == "preload") {
        // "Stretch, release, ring down": a dead load on a face, ramped over the
        // first half of [0, release], held, and removed at `release`.
        parse_traction(f.section("traction"), l);
        l.release = number(f, "loading.release");
        if (f.has("amplitude")) throw msd::Error(f.where("amplitude") + "not used with 'initial: preload'");
      } else {
        l.amplitude = number(f, "loading.amplitude");
      }
      l.path = {{0.0, 0.0}, {l.release + l.duration, 0.0}};
      break;
    }
  }
  l.gravity = vector3(f, "loading.gravity");
  return l;
}

}  // namespace

Spec parse_spec(const std::string& text, const std::string& source) {
  const YAML::Node root = tbio::parse_yaml(text, source);
  if (!root || root.IsNull()) throw msd::Error(source + ": the spec is empty");
  const Fields f(root, "", source);
  f.only({"name", "description", "geometry", "mesh", "material", "msd", "fem", "loading", "output"});
  Spec s;
  s.path = source;
  s.text = text;
  s.name = f.text("name");
  s.description = f.text_or("description", "");
  s.geometry = parse_geometry(f.section("geometry"), source);
  if (f.has("mesh")) s.mesh = parse_mesh(f.section("mesh"));
  s.material = parse_material(f.section("material"));
  if (f.has("msd")) s.msd = parse_msd(f.section("msd"));
  if (f.has("fem")) s.fem = parse_fem(f.section("fem"));
  s.loading = parse_loading(f.section("loading"));
  if (s.loading.type == Loading::Indentation) {
    const Fields l = f.section("loading");
    if (s.geometry.shape != "box") throw msd::Error(l.where("type") + "indentation needs a box geometry");
    if (!(s.loading.indenter_depth < s.geometry.size.z()))
      throw msd::Error(l.section("indenter").where("depth") + "must be less than the block's height (" +
                       std::to_string(s.geometry.size.z()) + " m)");
  }
  if (auto o = f.optional_section("output")) {
    o->only({"interval", "fields_interval"});
    s.output.interval = number(*o, "output.interval");
    s.output.fields_interval = number(*o, "output.fields_interval");
  }
  if (s.msd && !s.msd->calibration.empty()) {
    fs::path file = s.msd->calibration;
    if (file.is_relative()) file = fs::path(source).parent_path() / file;
    apply_calibration(s, file.string(), f.section("msd").where("calibration"));
  }
  if (s.msd && !s.mesh) throw msd::Error(f.where("msd") + "the msd solver needs a 'mesh' section");
  // A time step against the loading's time scale: at least ten steps over the
  // run (dt = 1000 s on a 1 s loading would take one step and look complete).
  const double end = s.loading.type == Loading::Vibration ? s.loading.release + s.loading.duration
                     : s.loading.path.empty()             ? 0.0
                                                          : s.loading.path.back().first;
  if (s.msd && s.msd->integrator != "cvode" && end > 0.0 && s.msd->dt > end / 10.0)
    throw msd::Error(f.section("msd").where("dt") + "dt = " + tbio::json_number(s.msd->dt) +
                     " s leaves fewer than ten steps over the loading, which lasts " + tbio::json_number(end) +
                     " s: use at most " + tbio::json_number(end / 10.0) + " s");
  if (s.msd && s.msd->integrator == "quasi_static" && s.loading.type == Loading::Indentation)
    throw msd::Error(f.section("msd").where("integrator") +
                     "quasi_static does not hold contact with the indenter yet (docs/msd-model.md section 5): use bdf2, backward_euler or an explicit integrator");
  if (s.msd && s.msd->integrator == "quasi_static" && s.loading.type == Loading::Vibration)
    throw msd::Error(f.section("msd").where("integrator") +
                     "quasi_static solves equilibria without inertia, and a vibration is inertia: use bdf2, backward_euler or an explicit integrator");
  if (s.msd && s.msd->constants == "physical" && !s.material.youngs_modulus)
    throw msd::Error(f.where("material") + "youngs_modulus is required for 'msd.constants: physical'");
  for (const char* term : {"neo_hookean", "bulk"})
    if (s.msd && std::find(s.msd->terms.begin(), s.msd->terms.end(), term) != s.msd->terms.end()) {
      if (s.msd->constants != "physical")
        throw msd::Error(f.section("msd").where("terms") + "the " + term + " term needs 'constants: physical' (E and Poisson's ratio)");
      if (!s.material.poisson_ratio)
        throw msd::Error(f.where("material") + "poisson_ratio is required for the msd term " + term);
      if (std::string(term) == "bulk" && !s.msd->zero_length_springs && !(*s.material.poisson_ratio > 0.25))
        throw msd::Error(f.where("material") + "poisson_ratio must be above 0.25 for the msd term bulk (springs alone have 1/4; got " +
                         tbio::json_number(*s.material.poisson_ratio) + ")");
      if (std::string(term) == "bulk" && s.msd->zero_length_springs && !(*s.material.poisson_ratio > 0.0))
        throw msd::Error(f.where("material") + "poisson_ratio must be above 0 for the msd term bulk with zero_length_springs (lambda > 0; got " +
                         tbio::json_number(*s.material.poisson_ratio) + ")");
    }
  return s;
}

Spec load_spec(const std::string& path) {
  return parse_spec(msd::read_input_file(path, "spec file"), path);
}

std::vector<std::pair<double, double>> preload_path(const LoadingSpec& l) {
  const int pieces = 16;
  const double T = 0.5 * l.release;
  std::vector<std::pair<double, double>> path;
  for (int k = 0; k <= pieces; ++k) {
    const double s = static_cast<double>(k) / pieces;
    path.emplace_back(s * T, 0.5 * (1.0 - std::cos(M_PI * s)));
  }
  path.back().second = 1.0;
  path.emplace_back(l.release, 1.0);
  path.emplace_back(l.release * (1 + 1e-9), 0.0);
  path.emplace_back(l.release + l.duration, 0.0);
  return path;
}

}  // namespace bench
