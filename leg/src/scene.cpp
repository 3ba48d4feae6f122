#include "leg/scene.hpp"

#include "tbio/series_tools.hpp"
#include "tbio/yaml_fields.hpp"
#include "msd/io/input_file.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace leg {

namespace {

using tbio::Fields;

constexpr double kDeg = M_PI / 180.0;

// A field read through its declaration (scene_parameters.cpp).
double number(const Fields& f, const char* path) { return tbio::read_number(f, leg_scene_parameter(path)); }
msd::Vec3 vector3(const Fields& f, const char* path) { return tbio::read_vector3(f, leg_scene_parameter(path)); }

LegBox box(const Fields& f, const std::string& name) {
  f.only({"name", "lo", "hi"});
  LegBox b;
  b.name = f.text_or("name", name);
  b.lo = f.vec3("lo");
  b.hi = f.vec3("hi");
  if ((b.lo.array() >= b.hi.array()).any()) throw msd::Error(f.where("hi") + "must exceed lo on every axis");
  return b;
}

// [[t, v], ...] with increasing t, each v times `scale`.
msd::Keyframes<double> scalar_keyframes(const Fields& f, const std::string& key, double scale) {
  msd::Keyframes<double> k;
  for (const auto& [t, v] : f.pair_list(key)) {
    if (!k.empty() && !(t > k.times().back())) throw msd::Error(f.where(key) + "times must increase");
    k.add(t, scale * v);
  }
  if (k.empty()) throw msd::Error(f.where(key) + "needs at least one [time, value] pair");
  return k;
}

// [[t, dx, dy, dz], ...] with increasing t.
msd::Keyframes<msd::Vec3> vector_keyframes(const Fields& f, const std::string& key) {
  msd::Keyframes<msd::Vec3> k;
  const YAML::Node list = f.node()[key];
  if (!list.IsSequence() || list.size() == 0) throw msd::Error(f.where(key) + "needs a list of [t, dx, dy, dz]");
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].IsSequence() || list[i].size() != 4)
      throw msd::Error(f.where(key) + "entry " + std::to_string(i) + " needs four numbers [t, dx, dy, dz]");
    double v[4];
    try {
      for (size_t c = 0; c < 4; ++c) v[c] = list[i][c].as<double>();
    } catch (const YAML::Exception&) {
      throw msd::Error(f.where(key) + "entry " + std::to_string(i) + " is not four numbers");
    }
    if (!k.empty() && !(v[0] > k.times().back())) throw msd::Error(f.where(key) + "times must increase");
    k.add(v[0], msd::Vec3(v[1], v[2], v[3]));
  }
  return k;
}

msd::TissueMaterial material(const Fields& f) {
  f.only({"density", "youngs_modulus", "damping_time", "stiffness_scale", "repulsion_factor", "volume_factor",
          "repulsion_floor", "poisson_ratio"});
  msd::TissueMaterial m;
  m.mode = msd::ConstantsMode::Physical;
  m.density = number(f, "materials.*.density");
  m.youngs_modulus = number(f, "materials.*.youngs_modulus");
  m.damping_time = number(f, "materials.*.damping_time");
  m.stiffness_scale = number(f, "materials.*.stiffness_scale");
  m.repulsion_factor = number(f, "materials.*.repulsion_factor");
  m.volume_factor = number(f, "materials.*.volume_factor");
  m.repulsion_floor = number(f, "materials.*.repulsion_floor");
  if (f.has("poisson_ratio")) m.poisson_ratio = number(f, "materials.*.poisson_ratio");
  msd::check_material(m, f.where());
  return m;
}

void activation_pair(const Fields& f, double& front, double& back) {
  f.only({"front", "back"});
  front = number(f, "muscles.activation.front");
  back = number(f, "muscles.activation.back");
}

fs::path relative_to(const std::string& scene_file, const std::string& p) {
  const fs::path q(p);
  return q.is_absolute() ? q : fs::path(scene_file).parent_path() / q;
}

// A file a scene names must exist; a name the system cannot even look up (too
// long, a folder that is a file, ...) is refused the same way, never with the
// exception of fs::exists (tests/fuzz/regressions/).
void require_file(const fs::path& p, const std::string& where) {
  std::error_code ec;
  if (fs::exists(p, ec)) return;
  throw msd::Error(where + (ec ? "cannot look up " + p.string() + ": " + ec.message() : "no such file: " + p.string()));
}

// name, geometry, time stepping, gravity, terms, threshold.
void read_run(const Fields& f, const std::string& path, LegScene& s) {
  s.name = f.text_or("name", fs::path(path).stem().string());
  s.description = f.text_or("description", "");
  if (f.has("geometry")) {
    const fs::path g = relative_to(path, f.text("geometry"));
    require_file(g, f.where("geometry"));
    s.geometry = g.string();
  } else {
    s.geometry = std::string(TISSUEBENCH_DATA_DIR) + "/leg/leg.yaml";
  }
  s.mesh_pull = tbio::read_flag(f, leg_scene_parameter("mesh_pull"));
  s.duration = number(f, "duration");
  s.dt = number(f, "dt");
  s.output_interval = number(f, "output_interval");
  if (s.dt > s.duration / 10.0)
    throw msd::Error(f.where("dt") + "dt = " + tbio::json_number(s.dt) + " s leaves fewer than ten steps over the " +
                     "duration (" + tbio::json_number(s.duration) + " s): use at most " +
                     tbio::json_number(s.duration / 10.0) + " s");
  const double steps_per_frame = s.output_interval / s.dt;
  if (!(s.output_interval > 0.0) || std::abs(steps_per_frame - std::round(steps_per_frame)) > 1e-6 * steps_per_frame ||
      std::round(steps_per_frame) < 1.0)
    throw msd::Error(f.where("output_interval") + "must be a positive whole number of steps dt (" +
                     tbio::json_number(s.output_interval) + " s / " + tbio::json_number(s.dt) + " s)");
  msd::LegModelOptions& o = s.model;
  o.gravity = vector3(f, "gravity");
  if (f.has("terms")) {
    o.terms = 0;
    for (const std::string& t : f.text_list("terms")) {
      try {
        o.terms |= msd::parse_force_term(t);
      } catch (const msd::Error& e) {
        throw msd::Error(f.where("terms") + e.what());
      }
      if (t == "bulk")
        throw msd::Error(f.where("terms") + "bulk: the lattice's bulk term runs in benchmark specs only (the leg's "
                                            "continuum element is neo_hookean)");
    }
  }
  o.nonlinear_threshold = number(f, "nonlinear_threshold");
  o.threads = static_cast<int>(tbio::read_integer(f, leg_scene_parameter("threads")));
  o.reference_forces = tbio::read_choice(f, leg_scene_parameter("forces")) == "reference";
  s.integrator = msd::parse_integrator(tbio::read_choice(f, leg_scene_parameter("integrator")));
  if (const auto n = f.optional_section("newton")) {
    if (!msd::is_implicit(s.integrator))
      throw msd::Error(f.where("newton") + "only meaningful with 'integrator: backward_euler' or 'bdf2'");
    n->only({"tolerance", "max_iterations", "max_step_cuts", "reuse_factorization", "linear_solver", "keep_orientation",
             "anderson_depth"});
    o.newton.tolerance = number(*n, "newton.tolerance");
    o.newton.max_iterations = static_cast<int>(tbio::read_integer(*n, leg_scene_parameter("newton.max_iterations")));
    o.newton.max_step_cuts = static_cast<int>(tbio::read_integer(*n, leg_scene_parameter("newton.max_step_cuts")));
    o.newton.reuse_factorization = tbio::read_flag(*n, leg_scene_parameter("newton.reuse_factorization"));
    o.newton.linear_solver = msd::parse_linear_solver(tbio::read_choice(*n, leg_scene_parameter("newton.linear_solver")));
    o.newton.keep_orientation = tbio::read_flag(*n, leg_scene_parameter("newton.keep_orientation"));
    o.newton.anderson_depth = static_cast<int>(tbio::read_integer(*n, leg_scene_parameter("newton.anderson_depth")));
  }
}

// knee: the hinge, its range, how it is driven, its passive structures.
void read_knee(const Fields& knee, LegScene& s) {
  knee.only({"centre", "axis", "range_deg", "initial_angle_deg", "initial_velocity_deg", "angle_deg", "release", "torque",
             "damping", "limit_stiffness", "passive_range_deg", "joint_space_radius"});
  msd::LegModelOptions& o = s.model;
  o.joint_space_radius = number(knee, "knee.joint_space_radius");
  o.knee_centre = vector3(knee, "knee.centre");
  o.knee_axis = vector3(knee, "knee.axis");
  if (!(o.knee_axis.norm() > 0.0)) throw msd::Error(knee.where("axis") + "must be a nonzero vector");
  o.knee_axis.normalize();
  if (knee.has("range_deg")) {
    const auto r = knee.number_list("range_deg");
    if (r.size() != 2 || !(r[0] < r[1])) throw msd::Error(knee.where("range_deg") + "needs [min, max] with min < max");
    o.min_flexion = r[0] * kDeg;
    o.max_flexion = r[1] * kDeg;
  }
  s.initial_angle = number(knee, "knee.initial_angle_deg") * kDeg;
  s.initial_velocity = number(knee, "knee.initial_velocity_deg") * kDeg;
  if (s.initial_angle < o.min_flexion || s.initial_angle > o.max_flexion)
    throw msd::Error(knee.where("initial_angle_deg") + "lies outside range_deg");
  if (knee.has("angle_deg")) s.knee_angle = scalar_keyframes(knee, "angle_deg", kDeg);
  if (knee.has("release")) {
    if (s.knee_angle.empty()) throw msd::Error(knee.where("release") + "releases a scripted knee: give angle_deg too");
    s.knee_release = number(knee, "knee.release");
  }
  for (double a : s.knee_angle.values())
    if (a < o.min_flexion - 1e-12 || a > o.max_flexion + 1e-12)
      throw msd::Error(knee.where("angle_deg") + "an angle lies outside range_deg");
  if (knee.has("torque")) s.joint_torque = scalar_keyframes(knee, "torque", 1.0);
  o.joint_damping = number(knee, "knee.damping");
  o.limit_stiffness = number(knee, "knee.limit_stiffness");
  o.passive_lo = o.min_flexion;
  o.passive_hi = o.max_flexion;
  if (knee.has("passive_range_deg")) {
    const auto r = knee.number_list("passive_range_deg");
    if (r.size() != 2 || !(r[0] <= r[1])) throw msd::Error(knee.where("passive_range_deg") + "needs [lo, hi], lo <= hi");
    o.passive_lo = r[0] * kDeg;
    o.passive_hi = r[1] * kDeg;
  }
}

// hip: the pivot and [[t, x, y, z, qw, qx, qy, qz], ...] in order of time.
void read_hip(const Fields& f, LegScene& s) {
  f.only({"pivot", "keyframes"});
  msd::PoseKeyframes k(vector3(f, "hip.pivot"));
  const YAML::Node list = f.node()["keyframes"];
  if (!list || !list.IsSequence() || list.size() == 0)
    throw msd::Error(f.where("keyframes") + "needs a list of [t, x, y, z, qw, qx, qy, qz]");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string entry = "way-point " + std::to_string(i + 1) + " ";
    if (!list[i].IsSequence() || list[i].size() != 8)
      throw msd::Error(f.where("keyframes") + entry + "needs eight numbers [t, x, y, z, qw, qx, qy, qz]");
    double v[8];
    try {
      for (size_t c = 0; c < 8; ++c) v[c] = list[i][c].as<double>();
    } catch (const YAML::Exception&) {
      throw msd::Error(f.where("keyframes") + entry + "is not eight numbers");
    }
    try {
      k.add(v[0], msd::Vec3(v[1], v[2], v[3]), Eigen::Quaterniond(v[4], v[5], v[6], v[7]));
    } catch (const msd::Error& e) {
      throw msd::Error(f.where("keyframes") + e.what());
    }
  }
  s.hip = std::move(k);
}

void read_tendons(const Fields& t, LegScene& s) {
  t.only({"modulus", "moduli", "strand_area", "insertions", "route", "attach", "engage_at", "pretension", "toe_strain",
          "failure_strain"});
  msd::LegModelOptions& o = s.model;
  if (const auto m = t.optional_section("moduli")) {
    for (const auto& kv : m->node()) {
      const std::string name = kv.first.as<std::string>();
      o.tendon_moduli[name] = m->positive(name);
    }
  }
  if (t.has("engage_at")) s.tendons_engage_at = number(t, "tendons.engage_at");
  s.insert_at_path_end = tbio::read_choice(t, leg_scene_parameter("tendons.insertions")) == "path";
  s.model.tendons_direct = tbio::read_choice(t, leg_scene_parameter("tendons.route")) == "direct";
  s.model.tendons_at_fibre_ends = tbio::read_choice(t, leg_scene_parameter("tendons.attach")) == "fibre_ends";
  if (s.model.tendons_at_fibre_ends && !s.model.tendons_direct)
    throw msd::Error(t.where("attach") + "fibre_ends needs route: direct (a strand from every fibre end cannot run "
                     "through the path's tissue nodes)");
  o.tendon_modulus = number(t, "tendons.modulus");
  o.strand_area = number(t, "tendons.strand_area");
  o.tendon_toe_strain = number(t, "tendons.toe_strain");
  s.tendon_failure_strain = number(t, "tendons.failure_strain");
  if (const auto p = t.optional_section("pretension")) {
    p->only({"fraction", "start", "duration"});
    s.pretension_fraction = number(*p, "tendons.pretension.fraction");
    s.pretension_start = number(*p, "tendons.pretension.start");
    s.pretension_duration = number(*p, "tendons.pretension.duration");
  }
}

void read_muscles(const Fields& m, const std::string& path, LegScene& s) {
  m.only({"max_stress", "force_length_zero", "unit_angle_deg", "front_line", "back_line", "script", "activation", "law",
          "hill", "activation_time", "deactivation_time", "pcsa", "optimal_at_deg"});
  msd::LegModelOptions& o = s.model;
  o.max_muscle_stress = number(m, "muscles.max_stress");
  if (const auto a = m.optional_section("pcsa")) {
    a->only({"front", "back"});
    if (a->has("front")) o.front_pcsa = number(*a, "muscles.pcsa.front");
    if (a->has("back")) o.back_pcsa = number(*a, "muscles.pcsa.back");
  }
  if (const auto a = m.optional_section("optimal_at_deg")) {
    a->only({"front", "back"});
    o.front_optimal_angle = number(*a, "muscles.optimal_at_deg.front") * kDeg;
    o.back_optimal_angle = number(*a, "muscles.optimal_at_deg.back") * kDeg;
    for (const auto& [side, angle] : {std::pair{"front", o.front_optimal_angle}, std::pair{"back", o.back_optimal_angle}})
      if (angle < o.min_flexion - 1e-12 || angle > o.max_flexion + 1e-12)
        throw msd::Error(a->where(side) + "lies outside knee.range_deg");
    if (s.tendons_engage_at)
      throw msd::Error(m.where("optimal_at_deg") + "sets the tendons' natural lengths, as tendons.engage_at does: give "
                       "one of them");
    if ((o.front_optimal_angle != 0.0 || o.back_optimal_angle != 0.0) && !(o.tendons_direct && s.insert_at_path_end))
      throw msd::Error(m.where("optimal_at_deg") + "needs tendons.route: direct and tendons.insertions: path (only a "
                       "strand straight to its insertion turns with the knee when its natural length is taken)");
  }
  o.hill.enabled = tbio::read_choice(m, leg_scene_parameter("muscles.law")) == "hill";
  if (const auto h = m.optional_section("hill")) {
    if (!o.hill.enabled) throw msd::Error(m.where("hill") + "only meaningful with 'law: hill'");
    h->only({"rest_fibre_stretch", "active_width", "passive_strain", "passive_shape", "force_velocity", "max_velocity",
             "curvature", "eccentric_max"});
    o.hill.rest_fibre_stretch = number(*h, "muscles.hill.rest_fibre_stretch");
    o.hill.active_width = number(*h, "muscles.hill.active_width");
    o.hill.passive_strain = number(*h, "muscles.hill.passive_strain");
    o.hill.passive_shape = number(*h, "muscles.hill.passive_shape");
    o.hill.force_velocity = tbio::read_flag(*h, leg_scene_parameter("muscles.hill.force_velocity"));
    o.hill.max_velocity = number(*h, "muscles.hill.max_velocity");
    o.hill.curvature = number(*h, "muscles.hill.curvature");
    o.hill.eccentric_max = number(*h, "muscles.hill.eccentric_max");
  }
  if (o.hill.enabled) {
    if (m.has("force_length_zero"))
      throw msd::Error(m.where("force_length_zero") + "belongs to the thesis law; with 'law: hill' the curve is muscles.hill.active_width");
    if (o.hill.force_velocity && !msd::is_implicit(s.integrator))
      throw msd::Error(m.where("law") + "the Hill law's force-velocity relation damps each unit far more than the "
                       "tissue's dampers (about 0.5 s x a unit's share of F_max / its optimal length, in N s/m); it needs 'integrator: backward_euler' "
                       "or 'bdf2', or 'hill: {force_velocity: false}'");
  }
  o.activation_time = number(m, "muscles.activation_time");
  o.deactivation_time = number(m, "muscles.deactivation_time");
  if (m.has("force_length_zero")) {
    if (m.text("force_length_zero") == "none") {
      o.force_length.enabled = false;
    } else {
      o.force_length.zero_at = m.number("force_length_zero");
      if (!(o.force_length.zero_at >= 0.0 && o.force_length.zero_at < 1.0))
        throw msd::Error(m.where("force_length_zero") + "must lie in [0, 1), or be none");
    }
  }
  o.unit_angle_deg = number(m, "muscles.unit_angle_deg");
  o.front_line = vector3(m, "muscles.front_line");
  o.back_line = vector3(m, "muscles.back_line");
  if (m.has("script") && m.has("activation"))
    throw msd::Error(m.where("activation") + "give either a script or constant activations, not both");
  if (m.has("script")) {
    const fs::path sp = relative_to(path, m.text("script"));
    require_file(sp, m.where("script"));
    s.script_path = sp.string();
    s.script = msd::read_activation_script(s.script_path, {"FRONT_MUSCLE", "BACK_MUSCLE"});
  }
  if (const auto a = m.optional_section("activation")) activation_pair(*a, s.front_activation, s.back_activation);
}

msd::LegModelOptions::Obstacle read_obstacle(const Fields& ob, size_t i, msd::Keyframes<msd::Vec3>& motion) {
  ob.only({"name", "shape", "point", "axis", "radius", "normal", "response", "box", "motion"});
  msd::LegModelOptions::Obstacle spec;
  spec.object.name = ob.text_or("name", "obstacle" + std::to_string(i));
  const std::string shape = ob.choice("shape", {"cylinder", "plane"});
  if (shape == "cylinder") {
    spec.object.shape = msd::ObstacleShape::Cylinder;
    spec.object.cylinder.point = ob.vec3("point");
    spec.object.cylinder.axis = ob.vec3_or("axis", msd::Vec3::UnitY());
    if (spec.object.cylinder.axis.norm() > 0.0) spec.object.cylinder.axis.normalize();
    spec.object.cylinder.radius = number(ob, "contact.obstacles[].radius");
  } else {
    spec.object.shape = msd::ObstacleShape::Plane;
    spec.object.plane.point = ob.vec3("point");
    spec.object.plane.normal = ob.vec3("normal");
    if (spec.object.plane.normal.norm() > 0.0) spec.object.plane.normal.normalize();
  }
  try {
    spec.object.response = msd::parse_contact_response(ob.text_or("response", "stick"));
    msd::check_obstacle(spec.object, spec.object.name);
  } catch (const msd::Error& e) {
    throw msd::Error(ob.where() + e.what());
  }
  if (const auto b = ob.optional_section("box")) {
    const LegBox bb = box(*b, spec.object.name);
    spec.box = std::make_pair(bb.lo, bb.hi);
  }
  motion = ob.has("motion") ? vector_keyframes(ob, "motion") : msd::Keyframes<msd::Vec3>{};
  return spec;
}

void read_contact(const Fields& c, const std::string& path, LegScene& s) {
  c.only({"knee", "obstacles"});
  if (const auto k = c.optional_section("knee")) {
    const LegBox b = box(*k, "knee");
    s.model.knee_contact_box = std::make_pair(b.lo, b.hi);
  }
  if (!c.has("obstacles")) return;
  const YAML::Node list = c.node()["obstacles"];
  if (!list.IsSequence()) throw msd::Error(c.where("obstacles") + "must be a list of objects");
  for (size_t i = 0; i < list.size(); ++i) {
    msd::Keyframes<msd::Vec3> motion;
    s.model.obstacles.push_back(
        read_obstacle(Fields(list[i], "contact.obstacles[" + std::to_string(i) + "]", path), i, motion));
    s.obstacle_motion.push_back(motion);
  }
}

void read_analysis(const Fields& a, const std::string& path, LegScene& s) {
  a.only({"from", "bulge", "drop", "wobble"});
  s.analysis_from = number(a, "analysis.from");
  if (a.has("bulge")) {
    const YAML::Node list = a.node()["bulge"];
    if (!list.IsSequence()) throw msd::Error(a.where("bulge") + "must be a list of areas {name, lo, hi}");
    for (size_t i = 0; i < list.size(); ++i)
      s.bulge_areas.push_back(
          box(Fields(list[i], "analysis.bulge[" + std::to_string(i) + "]", path), "area" + std::to_string(i)));
  }
  if (const auto d = a.optional_section("drop")) {
    d->only({"release"});
    s.drop_release = number(*d, "analysis.drop.release");
  }
  if (const auto w = a.optional_section("wobble")) {
    w->only({"probe", "after"});
    s.wobble_probe = box(w->section("probe"), "probe");
    s.wobble_after = number(*w, "analysis.wobble.after");
  }
}

void read_variants(const Fields& f, const std::string& path, LegScene& s) {
  const YAML::Node list = f.node()["variants"];
  if (!list.IsSequence() || list.size() == 0) throw msd::Error(f.where("variants") + "must be a list of {name, activation}");
  for (size_t i = 0; i < list.size(); ++i) {
    const Fields v(list[i], "variants[" + std::to_string(i) + "]", path);
    v.only({"name", "activation"});
    LegVariant lv;
    lv.name = v.text("name");
    if (lv.name.empty() || lv.name.find_first_of("/\\ ") != std::string::npos)
      throw msd::Error(v.where("name") + "must be a plain folder name");
    activation_pair(v.section("activation"), lv.front, lv.back);
    s.variants.push_back(lv);
  }
  if (s.script) throw msd::Error(f.where("variants") + "variants set constant activations; the scene also has a script");
}

// A copy of `n` made of new nodes, which carry no position: a message about
// a value set on the command line then names no line of the scene file.
YAML::Node unmarked(const YAML::Node& n) {
  if (n.IsScalar()) return YAML::Node(n.Scalar());
  if (n.IsSequence()) {
    YAML::Node out(YAML::NodeType::Sequence);
    for (const YAML::Node& child : n) out.push_back(unmarked(child));
    return out;
  }
  if (n.IsMap()) {
    YAML::Node out(YAML::NodeType::Map);
    for (const auto& kv : n) out[kv.first.Scalar()] = unmarked(kv.second);
    return out;
  }
  return YAML::Node();
}

// One --set KEY=VALUE applied to the parsed scene: KEY a dotted path of
// mapping keys (sections are made when missing), VALUE parsed as YAML.
void apply_override(YAML::Node& root, const std::string& path, const std::string& assignment) {
  const std::string where = "--set " + assignment + ": ";
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) throw msd::Error(where + "give KEY=VALUE, KEY a dotted field of the scene (knee.damping=0.1)");
  const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  std::vector<std::string> parts;
  for (size_t from = 0;;) {
    const size_t dot = key.find('.', from);
    parts.push_back(key.substr(from, dot == std::string::npos ? std::string::npos : dot - from));
    if (parts.back().empty()) throw msd::Error(where + "'" + key + "' has an empty field name");
    if (dot == std::string::npos) break;
    from = dot + 1;
  }
  YAML::Node parsed;
  try {
    parsed = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw msd::Error(where + "the value is not YAML (" + e.msg + ")");
  }
  const YAML::Node value = unmarked(parsed);
  if (text.empty() || value.IsNull()) throw msd::Error(where + "no value (an empty or null value would remove the field)");
  YAML::Node node;
  node.reset(root);
  std::string walked;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    walked += (i ? "." : "") + parts[i];
    YAML::Node next = node[parts[i]];
    if (next.IsDefined() && !next.IsNull() && !next.IsMap())
      throw msd::Error(where + path + ": '" + walked + "' is not a section (a mapping) that '" + key + "' could be in");
    if (!next.IsDefined() || next.IsNull()) node[parts[i]] = YAML::Node(YAML::NodeType::Map);
    YAML::Node child = node[parts[i]];
    node.reset(child);
  }
  node[parts.back()] = value;
}

LegScene scene_from(const YAML::Node& root, const std::string& path, const std::string& text) {
  const Fields f(root, "", path);
  f.only({"name", "description", "geometry", "mesh_pull", "duration", "dt", "integrator", "newton", "output_interval", "gravity", "terms",
          "nonlinear_threshold", "threads", "forces", "materials", "knee", "hip", "tendons", "muscles", "contact", "analysis", "variants",
          "outputs"});
  LegScene s;
  s.file = path;
  s.text = text;
  read_run(f, path, s);
  const Fields mats = f.section("materials");
  mats.only({"passive", "muscle", "skin"});
  s.model.passive = material(mats.section("passive"));
  s.model.muscle = material(mats.section("muscle"));
  if (s.model.terms & msd::kNeoHookean)
    for (const auto& [name, m] : {std::pair{"passive", &s.model.passive}, std::pair{"muscle", &s.model.muscle}})
      if (!m->poisson_ratio)
        throw msd::Error(f.where("terms") + "neo_hookean needs a Poisson's ratio: give materials." + name +
                         ".poisson_ratio");
  if (const auto skin = mats.optional_section("skin")) {
    skin->only({"youngs_modulus", "thickness"});
    s.model.skin = msd::LegModelOptions::Skin{number(*skin, "materials.skin.youngs_modulus"),
                                              number(*skin, "materials.skin.thickness")};
  }
  read_knee(f.section("knee"), s);
  if (const auto h = f.optional_section("hip")) read_hip(*h, s);
  if (const auto t = f.optional_section("tendons")) read_tendons(*t, s);
  if (const auto m = f.optional_section("muscles")) read_muscles(*m, path, s);
  if (const auto c = f.optional_section("contact")) read_contact(*c, path, s);
  if (const auto a = f.optional_section("analysis")) read_analysis(*a, path, s);
  if (f.has("variants")) read_variants(f, path, s);
  if (const auto out = f.optional_section("outputs")) {
    out->only({"obj_every"});
    s.obj_every = static_cast<int>(tbio::read_integer(*out, leg_scene_parameter("outputs.obj_every")));
  }
  return s;
}

}  // namespace

LegScene read_leg_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::string text = msd::read_input_file(path, "scene file");
  YAML::Node root = tbio::parse_yaml(text, path);
  if (!root || !root.IsMap()) throw msd::Error(path + ": the scene must be a YAML mapping");
  std::string set;
  for (const std::string& o : overrides) {
    apply_override(root, path, o);
    set += (set.empty() ? "" : " ") + ("--set " + o);
  }
  // The scene as run (the results' /meta, a checkpoint's identity): with
  // settings, what was set (one comment line each), then the changed scene
  // itself, so that a reader of the text sees the values the run used.
  if (!overrides.empty()) {
    YAML::Emitter e;
    e << root;
    text = "# " + path + " as changed by:\n";
    for (const std::string& o : overrides) text += "# --set " + o + "\n";
    text += std::string(e.c_str()) + "\n";
  }
  try {
    LegScene s = scene_from(root, path, text);
    s.overrides = overrides;
    return s;
  } catch (const msd::Error& e) {
    if (set.empty()) throw;
    // A field set on the command line has no line in the file: say so.
    throw msd::Error(std::string(e.what()) + " (the file as changed by " + set + ")");
  }
}

}  // namespace leg
