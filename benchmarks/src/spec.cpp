#include "bench/spec.hpp"

#include "bench/calibration.hpp"

#include "bench/shared_io.hpp"
#include "msd/core/types.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace bench {

namespace fs = std::filesystem;

namespace {

Eigen::Vector3d vec3(const Fields& f, const std::string& key) {
  const std::vector<double> v = f.number_list(key);
  if (v.size() != 3) throw msd::Error(f.where(key) + "expected three numbers [x, y, z]");
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

void positive(const Fields& f, const std::string& key, double v, const std::string& unit) {
  if (!(v > 0.0)) throw msd::Error(f.where(key) + "must be positive (" + unit + "), got " + std::to_string(v));
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
  g.shape = f.text("shape");
  one_of(f, "shape", g.shape, {"cylinder", "box", "cooks_membrane", "obj"});
  if (g.shape == "cylinder") {
    f.only({"shape", "radius", "height", "segments"});
    g.radius = f.number("radius");
    positive(f, "radius", g.radius, "m");
    g.height = f.number("height");
    positive(f, "height", g.height, "m");
    g.segments = static_cast<int>(f.integer_or("segments", 64));
    if (g.segments < 3 || g.segments > 100000)
      throw msd::Error(f.where("segments") + "must be between 3 and 100000");
  } else if (g.shape == "box") {
    f.only({"shape", "size"});
    g.size = vec3(f, "size");
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
  f.only({"spacing", "rule", "origin", "max_cubes"});
  MeshSpec m;
  m.spacing = f.number("spacing");
  positive(f, "spacing", m.spacing, "m");
  m.rule = f.text_or("rule", m.rule);
  one_of(f, "rule", m.rule, {"centre", "center", "inside", "overlap"});
  if (f.has("origin")) m.origin = vec3(f, "origin");
  m.max_cubes = f.integer_or("max_cubes", m.max_cubes);
  if (m.max_cubes < 1) throw msd::Error(f.where("max_cubes") + "must be at least 1");
  return m;
}

// A named entry of benchmarks/materials.yaml, merged under the spec's fields.
YAML::Node library_material(const Fields& f) {
  const std::string name = f.text("library");
  const std::string file = TISSUEBENCH_MATERIALS_FILE;
  YAML::Node lib;
  try {
    lib = YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    throw msd::Error(file + ": cannot read the materials file: " + e.msg);
  }
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
  m.density = f.number("density");
  positive(f, "density", m.density, "kg/m^3");
  if (f.has("youngs_modulus")) {
    m.youngs_modulus = f.number("youngs_modulus");
    positive(f, "youngs_modulus", *m.youngs_modulus, "Pa");
  }
  if (f.has("poisson_ratio")) {
    m.poisson_ratio = f.number("poisson_ratio");
    if (!(*m.poisson_ratio > -1.0 && *m.poisson_ratio < 0.5))
      throw msd::Error(f.where("poisson_ratio") + "must lie in (-1, 0.5)");
  }
  for (const char* k : {"shear_modulus", "bulk_modulus"})
    if (f.has(k)) {
      const double v = f.number(k);
      positive(f, k, v, "Pa");
      (std::string(k) == "shear_modulus" ? m.shear_modulus : m.bulk_modulus) = v;
    }
  if (m.shear_modulus.has_value() != m.bulk_modulus.has_value())
    throw msd::Error(f.where() + "give shear_modulus and bulk_modulus together");
  if (m.shear_modulus && (m.youngs_modulus || m.poisson_ratio))
    throw msd::Error(f.where() + "give either youngs_modulus/poisson_ratio or shear_modulus/bulk_modulus, not both");
  if (f.has("damping_time")) {
    m.damping_time = f.number("damping_time");
    if (*m.damping_time < 0.0) throw msd::Error(f.where("damping_time") + "must be >= 0 (s)");
  }
  return m;
}

MsdSpec parse_msd(const Fields& f) {
  f.only({"constants", "k_s", "k_d", "k_r", "k_v", "stiffness_scale", "repulsion_factor",
          "volume_factor", "damping_time", "repulsion_floor", "mass_lumping", "terms", "nonlinear_threshold",
          "integrator", "dt", "calibration", "rtol", "atol"});
  MsdSpec m;
  m.constants = f.text_or("constants", m.constants);
  one_of(f, "constants", m.constants, {"raw", "physical"});
  const bool raw = m.constants == "raw";
  for (const char* k : {"k_s", "k_d", "k_r", "k_v"})
    if (!raw && f.has(k))
      throw msd::Error(f.where(k) + "raw constants need 'constants: raw'");
  for (const char* k : {"stiffness_scale", "repulsion_factor", "volume_factor", "damping_time", "calibration"})
    if (raw && f.has(k))
      throw msd::Error(f.where(k) + "only meaningful with 'constants: physical'");
  if (f.has("calibration")) {
    for (const char* k : {"stiffness_scale", "repulsion_factor", "volume_factor", "damping_time"})
      if (f.has(k))
        throw msd::Error(f.where(k) + "given together with 'calibration', which sets it; give one or the other");
    m.calibration = f.text("calibration");
  }
  if (raw) {
    m.k_s = f.number("k_s");
    positive(f, "k_s", m.k_s, "N/m");
    m.k_d = f.number_or("k_d", 0.0);
    m.k_r = f.number_or("k_r", 0.0);
    m.k_v = f.number_or("k_v", 0.0);
    for (const char* k : {"k_d", "k_r", "k_v"})
      if (f.number_or(k, 0.0) < 0.0) throw msd::Error(f.where(k) + "must be >= 0");
  } else {
    m.stiffness_scale = f.number_or("stiffness_scale", 1.0);
    positive(f, "stiffness_scale", m.stiffness_scale, "dimensionless");
    m.repulsion_factor = f.number_or("repulsion_factor", 0.0);
    m.volume_factor = f.number_or("volume_factor", 0.0);
    for (const char* k : {"repulsion_factor", "volume_factor"})
      if (f.number_or(k, 0.0) < 0.0) throw msd::Error(f.where(k) + "must be >= 0");
    if (f.has("damping_time")) {
      m.damping_time = f.number("damping_time");
      if (!(*m.damping_time >= 0.0)) throw msd::Error(f.where("damping_time") + "must be >= 0 (s)");
    }
  }
  m.repulsion_floor = f.number_or("repulsion_floor", m.repulsion_floor);
  if (!(m.repulsion_floor > 0.0 && m.repulsion_floor < 1.0))
    throw msd::Error(f.where("repulsion_floor") + "must lie in (0, 1)");
  m.mass_lumping = f.text_or("mass_lumping", m.mass_lumping);
  one_of(f, "mass_lumping", m.mass_lumping, {"per_tet", "equal"});
  if (f.has("terms")) {
    m.terms = f.text_list("terms");
    for (const auto& t : m.terms)
      one_of(f, "terms", t, {"springs", "dampers", "repulsion", "volume"});
  }
  if (f.has("nonlinear_threshold")) {
    const YAML::Node n = f.node()["nonlinear_threshold"];
    if (n.IsScalar() && (n.Scalar() == "off" || n.Scalar() == "false")) {
      m.nonlinear_threshold = 0.0;
    } else {
      m.nonlinear_threshold = f.number("nonlinear_threshold");
      if (!(m.nonlinear_threshold > 0.0 && m.nonlinear_threshold <= 1.0))
        throw msd::Error(f.where("nonlinear_threshold") + "must be 'off' or in (0, 1]");
    }
  }
  m.integrator = f.text_or("integrator", m.integrator);
  one_of(f, "integrator", m.integrator,
         {"explicit_euler", "symplectic_euler", "semi_implicit_euler", "velocity_verlet", "cvode"});
  if (m.integrator == "cvode") {
    m.rtol = f.number_or("rtol", m.rtol);
    m.atol = f.number_or("atol", m.atol);
    positive(f, "rtol", m.rtol, "dimensionless");
    positive(f, "atol", m.atol, "m");
    if (f.has("dt")) throw msd::Error(f.where("dt") + "cvode chooses its own steps (give rtol and atol instead)");
  } else {
    for (const char* k : {"rtol", "atol"})
      if (f.has(k)) throw msd::Error(f.where(k) + "only meaningful with 'integrator: cvode'");
    m.dt = f.number("dt");
    positive(f, "dt", m.dt, "s");
  }
  return m;
}

unsigned unsigned_field(const Fields& f, const std::string& key, unsigned fallback, unsigned lo, unsigned hi) {
  const long v = f.integer_or(key, fallback);
  if (v < static_cast<long>(lo) || v > static_cast<long>(hi))
    throw msd::Error(f.where(key) + "must be between " + std::to_string(lo) + " and " + std::to_string(hi));
  return static_cast<unsigned>(v);
}

FemSpec parse_fem(const Fields& f) {
  f.only({"formulation", "degree", "refinement", "cells", "linear_solver", "residual_tolerance",
          "increment_tolerance", "max_iterations", "max_cuts", "max_increment", "relative_tolerance",
          "absolute_tolerance", "rayleigh_mass", "contact_penalty", "vtu"});
  FemSpec m;
  m.formulation = f.text_or("formulation", m.formulation);
  one_of(f, "formulation", m.formulation, {"three_field", "displacement"});
  m.degree = unsigned_field(f, "degree", m.degree, 1, 3);
  m.refinement = unsigned_field(f, "refinement", m.refinement, 0, 8);
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
  m.linear_solver = f.text_or("linear_solver", m.linear_solver);
  one_of(f, "linear_solver", m.linear_solver, {"direct", "amg"});
  for (const char* k : {"residual_tolerance", "increment_tolerance", "relative_tolerance", "absolute_tolerance"})
    if (f.has(k) && !(f.number(k) > 0.0 && f.number(k) < 1.0)) throw msd::Error(f.where(k) + "must lie in (0, 1)");
  m.residual_tolerance = f.number_or("residual_tolerance", m.residual_tolerance);
  m.increment_tolerance = f.number_or("increment_tolerance", m.increment_tolerance);
  m.relative_tolerance = f.number_or("relative_tolerance", m.relative_tolerance);
  m.absolute_tolerance = f.number_or("absolute_tolerance", m.absolute_tolerance);
  m.max_iterations = unsigned_field(f, "max_iterations", m.max_iterations, 1, 1000);
  m.max_cuts = unsigned_field(f, "max_cuts", m.max_cuts, 0, 30);
  m.max_increment = f.number_or("max_increment", 0.0);
  if (m.max_increment < 0.0) throw msd::Error(f.where("max_increment") + "must be >= 0");
  m.rayleigh_mass = f.number_or("rayleigh_mass", 0.0);
  if (m.rayleigh_mass < 0.0) throw msd::Error(f.where("rayleigh_mass") + "must be >= 0 (1/s)");
  m.contact_penalty = f.number_or("contact_penalty", m.contact_penalty);
  if (!(m.contact_penalty >= 1.0 && m.contact_penalty <= 1e8))
    throw msd::Error(f.where("contact_penalty") + "must lie in [1, 1e8] (a multiple of E / h)");
  if (f.has("vtu")) {
    const std::string v = f.text("vtu");
    if (v != "true" && v != "false") throw msd::Error(f.where("vtu") + "expected true or false");
    m.vtu = v == "true";
  }
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

Loading loading_type(const Fields& f) {
  const std::string name = f.text("type");
  if (const std::optional<Loading> l = find_loading(name)) return *l;
  throw msd::Error(f.where("type") + "'" + name + "' is not one of: " + loading_names());
}

LoadingSpec parse_loading(const Fields& f) {
  LoadingSpec l;
  l.type = loading_type(f);
  const std::vector<std::string> faces{"left", "right", "front", "back", "bottom", "top"};
  switch (l.type) {
    case Loading::Uniaxial: {
      f.only({"type", "platens", "path", "gravity"});
      l.platens = f.text_or("platens", l.platens);
      one_of(f, "platens", l.platens, {"bonded", "frictionless"});
      l.path = parse_path(f);
      for (const auto& [t, e] : l.path)
        if (!(e > -1.0)) throw msd::Error(f.where("path") + "nominal strain must stay above -1");
      break;
    }
    case Loading::SimpleShear: {
      f.only({"type", "boundary", "path"});
      l.boundary = f.text_or("boundary", l.boundary);
      one_of(f, "boundary", l.boundary, {"platens", "homogeneous"});
      l.path = parse_path(f);
      break;
    }
    case Loading::CooksMembrane: {
      f.only({"type", "force", "path"});
      l.force = f.number("force");
      l.path = f.has("path") ? parse_path(f) : std::vector<std::pair<double, double>>{{0.0, 0.0}, {1.0, 1.0}};
      break;
    }
    case Loading::Static: {
      f.only({"type", "fixed", "traction", "gravity", "path"});
      l.fixed = f.text_or("fixed", l.fixed);
      one_of(f, "fixed", l.fixed, faces);
      if (auto t = f.optional_section("traction")) {
        t->only({"face", "force"});
        l.traction_face = t->text("face");
        one_of(*t, "face", l.traction_face, faces);
        l.traction = vec3(*t, "force");
        if (l.traction_face == l.fixed) throw msd::Error(t->where("face") + "the traction face is the fixed face");
      }
      l.path = f.has("path") ? parse_path(f) : std::vector<std::pair<double, double>>{{0.0, 0.0}, {1.0, 1.0}};
      break;
    }
    case Loading::Indentation: {
      f.only({"type", "indenter", "path"});
      auto ind = f.section("indenter");
      ind.only({"shape", "radius", "axis", "depth", "response"});
      const std::string shape = ind.text_or("shape", "cylinder");
      one_of(ind, "shape", shape, {"cylinder"});
      l.indenter_radius = ind.number("radius");
      positive(ind, "radius", l.indenter_radius, "m");
      l.indenter_depth = ind.number("depth");
      positive(ind, "depth", l.indenter_depth, "m");
      l.indenter_axis = ind.text_or("axis", l.indenter_axis);
      one_of(ind, "axis", l.indenter_axis, {"x", "y"});
      l.indenter_response = ind.text_or("response", l.indenter_response);
      one_of(ind, "response", l.indenter_response, {"stick", "frictionless"});
      l.path = parse_path(f);
      for (const auto& [t, v] : l.path)
        if (!(v >= 0.0 && v <= 1.0)) throw msd::Error(f.where("path") + "depth factors must lie in [0, 1]");
      break;
    }
    case Loading::Vibration: {
      f.only({"type", "initial", "amplitude", "traction", "release", "duration", "gravity"});
      l.initial = f.text_or("initial", l.initial);
      one_of(f, "initial", l.initial, {"axial_mode", "axial_stretch", "preload"});
      l.duration = f.number("duration");
      positive(f, "duration", l.duration, "s");
      if (l.initial == "preload") {
        // "Stretch, release, ring down": a dead load on a face, ramped over the
        // first half of [0, release], held, and removed at `release`.
        auto t = f.section("traction");
        t.only({"face", "force"});
        l.traction_face = t.text("face");
        one_of(t, "face", l.traction_face, faces);
        l.traction = vec3(t, "force");
        l.release = f.number("release");
        positive(f, "release", l.release, "s");
        if (f.has("amplitude")) throw msd::Error(f.where("amplitude") + "not used with 'initial: preload'");
      } else {
        l.amplitude = f.number("amplitude");
      }
      l.path = {{0.0, 0.0}, {l.release + l.duration, 0.0}};
      break;
    }
  }
  if (f.has("gravity")) l.gravity = vec3(f, "gravity");
  return l;
}

}  // namespace

Spec parse_spec(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw msd::Error(source + ":" + std::to_string(e.mark.line + 1) + ":" +
                     std::to_string(e.mark.column + 1) + ": YAML syntax error: " + e.msg);
  }
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
    s.output.interval = o->number("interval");
    positive(*o, "interval", s.output.interval, "s");
    s.output.fields_interval = o->number_or("fields_interval", 0.0);
    if (s.output.fields_interval < 0.0) throw msd::Error(o->where("fields_interval") + "must be >= 0 (s)");
  }
  if (s.msd && !s.msd->calibration.empty()) {
    fs::path file = s.msd->calibration;
    if (file.is_relative()) file = fs::path(source).parent_path() / file;
    apply_calibration(s, file.string(), f.section("msd").where("calibration"));
  }
  if (s.msd && !s.mesh) throw msd::Error(f.where("msd") + "the msd solver needs a 'mesh' section");
  if (s.msd && s.msd->constants == "physical" && !s.material.youngs_modulus)
    throw msd::Error(f.where("material") + "youngs_modulus is required for 'msd.constants: physical'");
  return s;
}

Spec load_spec(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw msd::Error(path + ": cannot open spec file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_spec(ss.str(), path);
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
