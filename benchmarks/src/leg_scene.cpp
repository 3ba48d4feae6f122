#include "bench/leg_scene.hpp"

#include "bench/leg_mesh.hpp"
#include "bench/results_file.hpp"
#include "bench/series_tools.hpp"
#include "bench/signal_analysis.hpp"
#include "bench/yaml_fields.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/forces/tendon.hpp"
#include "msd/mesh/embedding.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace fs = std::filesystem;

namespace bench {

template <class T>
T Keyframes<T>::at(double t) const {
  if (time.empty()) return T{};
  if (t <= time.front()) return value.front();
  if (t >= time.back()) return value.back();
  const size_t k = static_cast<size_t>(std::upper_bound(time.begin(), time.end(), t) - time.begin());
  const double s = (t - time[k - 1]) / (time[k] - time[k - 1]);
  return T(value[k - 1] + s * (value[k] - value[k - 1]));
}

template <class T>
T Keyframes<T>::rate(double t) const {
  if (time.size() < 2 || t < time.front() || t >= time.back()) return T(0.0 * value.front());
  const size_t k = static_cast<size_t>(std::upper_bound(time.begin(), time.end(), t) - time.begin());
  return T((value[k] - value[k - 1]) / (time[k] - time[k - 1]));
}

template struct Keyframes<double>;
template struct Keyframes<msd::Vec3>;

namespace {

constexpr double kDeg = M_PI / 180.0;

msd::Vec3 vec3(const Fields& f, const std::string& key) {
  const auto v = f.number_list(key);
  if (v.size() != 3) throw msd::Error(f.where(key) + "needs three numbers [x, y, z]");
  for (double c : v)
    if (!std::isfinite(c)) throw msd::Error(f.where(key) + "must be finite");
  return msd::Vec3(v[0], v[1], v[2]);
}

msd::Vec3 vec3_or(const Fields& f, const std::string& key, const msd::Vec3& fallback) {
  return f.has(key) ? vec3(f, key) : fallback;
}

LegBox box(const Fields& f, const std::string& name) {
  f.only({"name", "lo", "hi"});
  LegBox b;
  b.name = f.text_or("name", name);
  b.lo = vec3(f, "lo");
  b.hi = vec3(f, "hi");
  if ((b.lo.array() >= b.hi.array()).any()) throw msd::Error(f.where("hi") + "must exceed lo on every axis");
  return b;
}

double positive(const Fields& f, const std::string& key) {
  const double v = f.number(key);
  if (!(v > 0.0) || !std::isfinite(v)) throw msd::Error(f.where(key) + "must be a positive number");
  return v;
}

double non_negative_or(const Fields& f, const std::string& key, double fallback) {
  const double v = f.number_or(key, fallback);
  if (!(v >= 0.0) || !std::isfinite(v)) throw msd::Error(f.where(key) + "must be a number >= 0");
  return v;
}

// [[t, v], ...] with increasing t.
Keyframes<double> scalar_keyframes(const Fields& f, const std::string& key, double scale) {
  Keyframes<double> k;
  for (const auto& [t, v] : f.pair_list(key)) {
    if (!k.time.empty() && !(t > k.time.back())) throw msd::Error(f.where(key) + "times must increase");
    k.time.push_back(t);
    k.value.push_back(scale * v);
  }
  if (k.time.empty()) throw msd::Error(f.where(key) + "needs at least one [time, value] pair");
  return k;
}

Keyframes<msd::Vec3> vector_keyframes(const Fields& f, const std::string& key) {
  Keyframes<msd::Vec3> k;
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
    if (!k.time.empty() && !(v[0] > k.time.back())) throw msd::Error(f.where(key) + "times must increase");
    k.time.push_back(v[0]);
    k.value.emplace_back(v[1], v[2], v[3]);
  }
  return k;
}

msd::TissueMaterial material(const Fields& f) {
  f.only({"density", "youngs_modulus", "damping_time", "stiffness_scale", "repulsion_factor", "volume_factor",
          "repulsion_floor"});
  msd::TissueMaterial m;
  m.mode = msd::ConstantsMode::Physical;
  m.density = positive(f, "density");
  m.youngs_modulus = positive(f, "youngs_modulus");
  m.damping_time = non_negative_or(f, "damping_time", 0.0);
  m.stiffness_scale = f.number_or("stiffness_scale", 1.0);
  m.repulsion_factor = non_negative_or(f, "repulsion_factor", 0.5);
  m.volume_factor = non_negative_or(f, "volume_factor", 1.6);
  m.repulsion_floor = f.number_or("repulsion_floor", m.repulsion_floor);
  try {
    msd::check_material(m, f.where());
  } catch (const msd::Error& e) {
    throw msd::Error(std::string(e.what()));
  }
  return m;
}

void activation_pair(const Fields& f, double& front, double& back) {
  f.only({"front", "back"});
  front = f.number_or("front", 0.0);
  back = f.number_or("back", 0.0);
  if (!(front >= 0.0 && front <= 1.0)) throw msd::Error(f.where("front") + "an activation lies in [0, 1]");
  if (!(back >= 0.0 && back <= 1.0)) throw msd::Error(f.where("back") + "an activation lies in [0, 1]");
}

fs::path relative_to(const std::string& scene_file, const std::string& p) {
  const fs::path q(p);
  return q.is_absolute() ? q : fs::path(scene_file).parent_path() / q;
}

}  // namespace

LegScene read_leg_scene(const std::string& path) {
  const YAML::Node root = load_yaml_file(path, "scene file");
  if (!root || !root.IsMap()) throw msd::Error(path + ": the scene must be a YAML mapping");
  const Fields f(root, "", path);
  f.only({"name", "description", "geometry", "mesh_pull", "duration", "dt", "output_interval", "gravity", "terms",
          "nonlinear_threshold", "materials", "knee", "tendons", "muscles", "contact", "analysis", "variants",
          "outputs"});
  LegScene s;
  s.file = path;
  {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    s.text = ss.str();
  }
  s.name = f.text_or("name", fs::path(path).stem().string());
  s.description = f.text_or("description", "");
  if (f.has("geometry")) {
    const fs::path g = relative_to(path, f.text("geometry"));
    if (!fs::exists(g)) throw msd::Error(f.where("geometry") + "no such file: " + g.string());
    s.geometry = g.string();
  } else {
    s.geometry = std::string(TISSUEBENCH_DATA_DIR) + "/leg/leg.yaml";
  }
  if (f.has("mesh_pull")) {
    try {
      s.mesh_pull = root["mesh_pull"].as<bool>();
    } catch (const YAML::Exception&) {
      throw msd::Error(f.where("mesh_pull") + "must be true or false");
    }
  }
  s.duration = positive(f, "duration");
  s.dt = positive(f, "dt");
  s.output_interval = f.number_or("output_interval", 0.04);
  const double steps_per_frame = s.output_interval / s.dt;
  if (!(s.output_interval > 0.0) || std::abs(steps_per_frame - std::round(steps_per_frame)) > 1e-6 * steps_per_frame ||
      std::round(steps_per_frame) < 1.0)
    throw msd::Error(f.where("output_interval") + "must be a positive whole number of steps dt (" +
                     json_number(s.output_interval) + " s / " + json_number(s.dt) + " s)");
  msd::LegModelOptions& o = s.model;
  o.gravity = vec3_or(f, "gravity", msd::Vec3(0, 0, -9.81));
  if (f.has("terms")) {
    o.terms = 0;
    for (const std::string& t : f.text_list("terms")) {
      try {
        o.terms |= msd::parse_force_term(t);
      } catch (const msd::Error& e) {
        throw msd::Error(f.where("terms") + e.what());
      }
    }
  }
  o.nonlinear_threshold = f.number_or("nonlinear_threshold", 0.7);
  if (!(o.nonlinear_threshold >= 0.0 && o.nonlinear_threshold <= 1.0))
    throw msd::Error(f.where("nonlinear_threshold") + "must lie in [0, 1]");

  const Fields mats = f.section("materials");
  mats.only({"passive", "muscle"});
  o.passive = material(mats.section("passive"));
  o.muscle = material(mats.section("muscle"));

  const Fields knee = f.section("knee");
  knee.only({"centre", "axis", "range_deg", "initial_angle_deg", "initial_velocity_deg", "angle_deg", "release", "torque",
             "damping", "limit_stiffness", "passive_range_deg", "joint_space_radius"});
  o.joint_space_radius = non_negative_or(knee, "joint_space_radius", 0.0);
  o.knee_centre = vec3(knee, "centre");
  o.knee_axis = vec3_or(knee, "axis", msd::Vec3::UnitY());
  if (!(o.knee_axis.norm() > 0.0)) throw msd::Error(knee.where("axis") + "must be a nonzero vector");
  o.knee_axis.normalize();
  if (knee.has("range_deg")) {
    const auto r = knee.number_list("range_deg");
    if (r.size() != 2 || !(r[0] < r[1])) throw msd::Error(knee.where("range_deg") + "needs [min, max] with min < max");
    o.min_flexion = r[0] * kDeg;
    o.max_flexion = r[1] * kDeg;
  }
  s.initial_angle = knee.number_or("initial_angle_deg", 0.0) * kDeg;
  s.initial_velocity = knee.number_or("initial_velocity_deg", 0.0) * kDeg;
  if (s.initial_angle < o.min_flexion || s.initial_angle > o.max_flexion)
    throw msd::Error(knee.where("initial_angle_deg") + "lies outside range_deg");
  if (knee.has("angle_deg")) s.knee_angle = scalar_keyframes(knee, "angle_deg", kDeg);
  if (knee.has("release")) {
    if (s.knee_angle.empty()) throw msd::Error(knee.where("release") + "releases a scripted knee: give angle_deg too");
    s.knee_release = non_negative_or(knee, "release", 0.0);
  }
  for (double a : s.knee_angle.value)
    if (a < o.min_flexion - 1e-12 || a > o.max_flexion + 1e-12)
      throw msd::Error(knee.where("angle_deg") + "an angle lies outside range_deg");
  if (knee.has("torque")) s.joint_torque = scalar_keyframes(knee, "torque", 1.0);
  o.joint_damping = non_negative_or(knee, "damping", 0.0);
  o.limit_stiffness = non_negative_or(knee, "limit_stiffness", 0.0);
  o.passive_lo = o.min_flexion;
  o.passive_hi = o.max_flexion;
  if (knee.has("passive_range_deg")) {
    const auto r = knee.number_list("passive_range_deg");
    if (r.size() != 2 || !(r[0] <= r[1])) throw msd::Error(knee.where("passive_range_deg") + "needs [lo, hi], lo <= hi");
    o.passive_lo = r[0] * kDeg;
    o.passive_hi = r[1] * kDeg;
  }

  if (const auto t = f.optional_section("tendons")) {
    t->only({"modulus", "moduli", "strand_area", "insertions", "engage_at", "pretension"});
    if (const auto m = t->optional_section("moduli")) {
      for (const auto& kv : m->node()) {
        const std::string name = kv.first.as<std::string>();
        o.tendon_moduli[name] = positive(*m, name);
      }
    }
    if (t->has("engage_at")) s.tendons_engage_at = non_negative_or(*t, "engage_at", 0.0);
    const std::string ins = t->text_or("insertions", "path");
    if (ins != "path" && ins != "nodes")
      throw msd::Error(t->where("insertions") + "'" + ins + "' is not one of: path, nodes");
    s.insert_at_path_end = ins == "path";
    o.tendon_modulus = t->has("modulus") ? positive(*t, "modulus") : o.tendon_modulus;
    o.strand_area = t->has("strand_area") ? positive(*t, "strand_area") : o.strand_area;
    if (const auto p = t->optional_section("pretension")) {
      p->only({"fraction", "start", "duration"});
      s.pretension_fraction = p->number("fraction");
      if (!(s.pretension_fraction >= 0.0 && s.pretension_fraction < 1.0))
        throw msd::Error(p->where("fraction") + "must lie in [0, 1): the natural length becomes (1 - fraction) L0");
      s.pretension_start = non_negative_or(*p, "start", 0.0);
      s.pretension_duration = non_negative_or(*p, "duration", 0.0);
    }
  }

  if (const auto m = f.optional_section("muscles")) {
    m->only({"max_stress", "force_length_zero", "unit_angle_deg", "front_line", "back_line", "script", "activation"});
    o.max_muscle_stress = m->has("max_stress") ? positive(*m, "max_stress") : o.max_muscle_stress;
    if (m->has("force_length_zero")) {
      if (m->text("force_length_zero") == "none") {
        o.force_length.enabled = false;
      } else {
        o.force_length.zero_at = m->number("force_length_zero");
        if (!(o.force_length.zero_at >= 0.0 && o.force_length.zero_at < 1.0))
          throw msd::Error(m->where("force_length_zero") + "must lie in [0, 1), or be none");
      }
    }
    o.unit_angle_deg = m->number_or("unit_angle_deg", o.unit_angle_deg);
    if (!(o.unit_angle_deg > 0.0 && o.unit_angle_deg < 90.0))
      throw msd::Error(m->where("unit_angle_deg") + "must lie between 0 and 90");
    o.front_line = vec3_or(*m, "front_line", o.front_line);
    o.back_line = vec3_or(*m, "back_line", o.back_line);
    if (m->has("script") && m->has("activation"))
      throw msd::Error(m->where("activation") + "give either a script or constant activations, not both");
    if (m->has("script")) {
      const fs::path sp = relative_to(path, m->text("script"));
      if (!fs::exists(sp)) throw msd::Error(m->where("script") + "no such file: " + sp.string());
      s.script_path = sp.string();
      s.script = msd::read_activation_script(s.script_path, {"FRONT_MUSCLE", "BACK_MUSCLE"});
    }
    if (const auto a = m->optional_section("activation")) activation_pair(*a, s.front_activation, s.back_activation);
  }

  if (const auto c = f.optional_section("contact")) {
    c->only({"knee", "obstacles"});
    if (const auto k = c->optional_section("knee")) {
      const LegBox b = box(*k, "knee");
      o.knee_contact_box = std::make_pair(b.lo, b.hi);
    }
    if (c->has("obstacles")) {
      const YAML::Node list = c->node()["obstacles"];
      if (!list.IsSequence()) throw msd::Error(c->where("obstacles") + "must be a list of objects");
      for (size_t i = 0; i < list.size(); ++i) {
        const Fields ob(list[i], "contact.obstacles[" + std::to_string(i) + "]", path);
        ob.only({"name", "shape", "point", "axis", "radius", "normal", "response", "box", "motion"});
        msd::LegModelOptions::Obstacle spec;
        spec.object.name = ob.text_or("name", "obstacle" + std::to_string(i));
        const std::string shape = ob.text("shape");
        if (shape == "cylinder") {
          spec.object.shape = msd::ObstacleShape::Cylinder;
          spec.object.cylinder.point = vec3(ob, "point");
          spec.object.cylinder.axis = vec3_or(ob, "axis", msd::Vec3::UnitY());
          if (spec.object.cylinder.axis.norm() > 0.0) spec.object.cylinder.axis.normalize();
          spec.object.cylinder.radius = positive(ob, "radius");
        } else if (shape == "plane") {
          spec.object.shape = msd::ObstacleShape::Plane;
          spec.object.plane.point = vec3(ob, "point");
          spec.object.plane.normal = vec3(ob, "normal");
          if (spec.object.plane.normal.norm() > 0.0) spec.object.plane.normal.normalize();
        } else {
          throw msd::Error(ob.where("shape") + "'" + shape + "' is not one of: cylinder, plane");
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
        s.obstacle_motion.push_back(ob.has("motion") ? vector_keyframes(ob, "motion") : Keyframes<msd::Vec3>{});
        o.obstacles.push_back(spec);
      }
    }
  }

  if (const auto a = f.optional_section("analysis")) {
    a->only({"from", "bulge", "drop", "wobble"});
    s.analysis_from = non_negative_or(*a, "from", 0.0);
    if (a->has("bulge")) {
      const YAML::Node list = a->node()["bulge"];
      if (!list.IsSequence()) throw msd::Error(a->where("bulge") + "must be a list of areas {name, lo, hi}");
      for (size_t i = 0; i < list.size(); ++i)
        s.bulge_areas.push_back(box(Fields(list[i], "analysis.bulge[" + std::to_string(i) + "]", path),
                                    "area" + std::to_string(i)));
    }
    if (const auto d = a->optional_section("drop")) {
      d->only({"release"});
      s.drop_release = non_negative_or(*d, "release", 0.0);
    }
    if (const auto w = a->optional_section("wobble")) {
      w->only({"probe", "after"});
      s.wobble_probe = box(w->section("probe"), "probe");
      s.wobble_after = non_negative_or(*w, "after", 0.0);
    }
  }

  if (f.has("variants")) {
    const YAML::Node list = root["variants"];
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
  if (const auto out = f.optional_section("outputs")) {
    out->only({"obj_every"});
    s.obj_every = static_cast<int>(out->integer_or("obj_every", 1));
    if (s.obj_every < 0) throw msd::Error(out->where("obj_every") + "must be >= 0");
  }
  return s;
}

namespace {

// ---- Measurements on one state. --------------------------------------------

struct MuscleShape {
  std::vector<int> nodes;
  msd::Vec3 line{msd::Vec3::UnitZ()};
  double rest_length = 0.0, rest_radius = 0.0;
};

void length_and_radius(const msd::Points& x, const MuscleShape& m, double& length, double& radius) {
  double lo = 1e300, hi = -1e300;
  msd::Vec3 c = msd::Vec3::Zero();
  for (int i : m.nodes) {
    const double s = m.line.dot(x.col(i));
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    c += x.col(i);
  }
  c /= static_cast<double>(m.nodes.size());
  double r2 = 0.0;
  for (int i : m.nodes) {
    const msd::Vec3 d = msd::Vec3(x.col(i)) - c;
    r2 += (d - d.dot(m.line) * m.line).squaredNorm();
  }
  length = hi - lo;
  radius = std::sqrt(r2 / static_cast<double>(m.nodes.size()));
}

double region_volume(const msd::Points& x, const std::vector<msd::Tet>& tets, const std::vector<int>& region, int r) {
  double v = 0.0;
  for (size_t e = 0; e < tets.size(); ++e)
    if (region[e] == r) v += msd::tet_signed_volume(x, tets[e]);
  return v;
}

// Area-weighted vertex normals of a closed surface (outward).
msd::Points vertex_normals(const msd::TriangleMesh& m) {
  msd::Points n = msd::Points::Zero(3, m.num_vertices());
  for (const msd::Tri& t : m.triangles) {
    const msd::Vec3 a = m.vertices.col(t[0]), b = m.vertices.col(t[1]), c = m.vertices.col(t[2]);
    const msd::Vec3 w = (b - a).cross(c - a);
    for (int v : t) n.col(v) += w;
  }
  for (int i = 0; i < n.cols(); ++i)
    if (n.col(i).norm() > 0.0) n.col(i).normalize();
  return n;
}

void write_obj(const std::string& path, const msd::Points& v, const std::vector<msd::Tri>& tris) {
  std::FILE* out = std::fopen(path.c_str(), "w");
  if (!out) throw msd::Error(path + ": cannot write");
  for (int i = 0; i < v.cols(); ++i) std::fprintf(out, "v %.6f %.6f %.6f\n", v(0, i), v(1, i), v(2, i));
  for (const msd::Tri& t : tris) std::fprintf(out, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
  const bool ok = std::ferror(out) == 0;
  std::fclose(out);
  if (!ok) throw msd::Error(path + ": write failed");
}

// XDMF for ParaView: the tets and the skin, each frame's geometry the rest
// points plus that frame's displacement (a hyperslab of /fields/NAME_displacement).
void write_xdmf(const std::string& path, const std::string& h5_name, long frames, const std::vector<double>& times,
                long nodes, long tets, long skin_vertices, long skin_triangles) {
  std::ofstream x(path + ".partial");
  x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n <Domain>\n";
  auto grid = [&](const std::string& name, const std::string& set, const std::string& topology, long cells,
                  int per_cell, const std::string& cell_set, long points) {
    x << "  <Grid Name=\"" << name << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (long k = 0; k < frames; ++k) {
      x << "   <Grid Name=\"" << name << "_" << k << "\" GridType=\"Uniform\">\n"
        << "    <Time Value=\"" << json_number(times[static_cast<size_t>(k)]) << "\"/>\n"
        << "    <Topology TopologyType=\"" << topology << "\" NumberOfElements=\"" << cells << "\">\n"
        << "     <DataItem Dimensions=\"" << cells << " " << per_cell << "\" NumberType=\"Int\" Format=\"HDF\">"
        << h5_name << ":/fields/" << cell_set << "</DataItem>\n    </Topology>\n"
        << "    <Geometry GeometryType=\"XYZ\">\n"
        << "     <DataItem ItemType=\"Function\" Function=\"$0 + $1\" Dimensions=\"" << points << " 3\">\n"
        << "      <DataItem Dimensions=\"" << points << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
        << h5_name << ":/fields/" << set << "_points</DataItem>\n"
        << "      <DataItem ItemType=\"HyperSlab\" Dimensions=\"" << points << " 3\">\n"
        << "       <DataItem Dimensions=\"3 3\" Format=\"XML\">" << k << " 0 0 1 1 1 1 " << points
        << " 3</DataItem>\n"
        << "       <DataItem Dimensions=\"" << frames << " " << points
        << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5_name << ":/fields/" << set
        << "_displacement</DataItem>\n      </DataItem>\n     </DataItem>\n    </Geometry>\n   </Grid>\n";
    }
    x << "  </Grid>\n";
  };
  grid("tissue", "nodes", "Tetrahedron", tets, 4, "nodes_tets", nodes);
  grid("skin", "skin", "Triangle", skin_triangles, 3, "skin_triangles", skin_vertices);
  x << " </Domain>\n</Xdmf>\n";
  x.close();
  if (!x) throw msd::Error(path + ": write failed");
  fs::rename(path + ".partial", path);
}

std::string json_object(const LegRunSummary& s, const LegScene& scene) {
  std::ostringstream o;
  o << "{\n  \"scene\": " << json_string(scene.name) << ",\n  \"scene_file\": " << json_string(scene.file)
    << ",\n  \"variant\": " << json_string(s.variant) << ",\n  \"status\": " << json_string(s.status);
  if (!s.failure.empty()) o << ",\n  \"failure\": " << json_string(s.failure);
  o << ",\n  \"simulated_seconds\": " << json_number(s.simulated) << ",\n  \"wall_seconds\": "
    << json_number(s.wall_seconds) << ",\n  \"wall_per_simulated_second\": " << json_number(s.wall_per_simulated())
    << ",\n  \"dt\": " << json_number(scene.dt) << ",\n  \"steps\": " << s.steps << ",\n  \"frames\": " << s.frames
    << ",\n  \"nodes\": " << s.nodes << ",\n  \"tets\": " << s.tets << ",\n  \"values\": {";
  bool first = true;
  for (const auto& [k, v] : s.values) {
    o << (first ? "\n" : ",\n") << "    " << json_string(k) << ": " << json_number(v);
    first = false;
  }
  o << "\n  },\n  \"knee_angle_trajectory_deg\": [";
  for (size_t i = 0; i < s.trajectory.size(); ++i)
    o << (i ? ", " : "") << "[" << json_number(s.trajectory[i].first, 6) << ", " << json_number(s.trajectory[i].second, 6)
      << "]";
  o << "]\n}\n";
  return o.str();
}

void write_summary(const std::string& dir, const LegRunSummary& s, const LegScene& scene) {
  const std::string path = (fs::path(dir) / "summary.json").string();
  {
    std::ofstream out(path + ".partial");
    out << json_object(s, scene);
    if (!out) throw msd::Error(path + ": write failed");
  }
  fs::rename(path + ".partial", path);
}

// Peaks of the knee angle about its final value (the pendulum test's swing).
void drop_metrics(const std::vector<double>& t, const std::vector<double>& angle_deg, double release,
                  std::map<std::string, double>& out) {
  std::vector<double> tt, aa;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= release) {
      tt.push_back(t[i]);
      aa.push_back(angle_deg[i]);
    }
  if (aa.size() < 5) return;
  // The final rest angle: the mean of the last fifth.
  const size_t tail = aa.size() - aa.size() / 5;
  double rest = 0.0;
  for (size_t i = tail; i < aa.size(); ++i) rest += aa[i];
  rest /= static_cast<double>(aa.size() - tail);
  std::vector<double> peaks, peak_t;
  for (size_t i = 1; i + 1 < aa.size(); ++i)
    if (aa[i] > aa[i - 1] && aa[i] >= aa[i + 1] && aa[i] - rest > 0.5) {
      peaks.push_back(aa[i]);
      peak_t.push_back(tt[i]);
    }
  out["drop_rest_angle_deg"] = rest;
  out["drop_start_angle_deg"] = aa.front();
  if (!peaks.empty()) {
    out["drop_first_swing_peak_deg"] = peaks[0];
    out["drop_first_swing_amplitude_deg"] = peaks[0] - aa.front();
  }
  if (peaks.size() >= 2) {
    out["drop_successive_peak_ratio"] = (peaks[1] - rest) / (peaks[0] - rest);
    out["drop_swing_period_s"] = peak_t[1] - peak_t[0];
  }
  int oscillations = 0;
  for (double p : peaks)
    if (p - rest > 0.02 * (peaks[0] - rest) && p - rest > 1.0) ++oscillations;
  out["drop_oscillations"] = oscillations;
  const RingDown r = analyse_ring_down(tt, aa);
  out["drop_frequency_hz"] = r.frequency;
  out["drop_damping_ratio"] = r.damping_ratio;
}

}  // namespace

std::vector<LegRunSummary> run_leg_scene(const LegScene& scene, const std::string& out_dir,
                                         const std::function<void(double, double)>& progress) {
  fs::create_directories(out_dir);
  std::error_code ignore;
  fs::remove(fs::path(out_dir) / "summary.json", ignore);

  LimbInput input = read_limb_input(scene.geometry);
  if (!scene.mesh_pull) input.options.pull_areas.clear();
  const MeshedLimb limb = mesh_limb_input(input);
  msd::LegModelOptions model_options = scene.model;
  if (scene.insert_at_path_end)
    for (const msd::TendonPathSpec& t : input.tendons) model_options.tendon_insertions.push_back(t.path.back());
  const msd::LegModel leg = msd::build_leg_model(limb.mesh, limb.tendons, model_options);
  const msd::TriangleMesh& skin = input.surfaces.skin;
  const msd::Embedding& skin_embedding = limb.mesh.embedded.at(msd::kPassiveTissue);
  const msd::Points skin_normals = vertex_normals(skin);
  const msd::Model& tm = leg.tissue;
  const int n = tm.num_nodes();

  // What is measured, set up once.
  std::vector<int> tet_region;
  for (const msd::Element& e : tm.elements) tet_region.push_back(e.region);
  const int regions[] = {msd::kPassiveTissue, msd::kFrontMuscle, msd::kBackMuscle};
  double rest_volume[3];
  for (int r = 0; r < 3; ++r) rest_volume[r] = region_volume(tm.rest_positions, leg.tets, tet_region, regions[r]);
  MuscleShape muscles[2];
  for (int k = 0; k < 2; ++k) {
    const int r = k == 0 ? msd::kFrontMuscle : msd::kBackMuscle;
    std::vector<char> in(static_cast<size_t>(n), 0);
    for (size_t e = 0; e < leg.tets.size(); ++e)
      if (tet_region[e] == r)
        for (int v : leg.tets[e]) in[static_cast<size_t>(v)] = 1;
    for (int i = 0; i < n; ++i)
      if (in[static_cast<size_t>(i)]) muscles[k].nodes.push_back(i);
    muscles[k].line = (k == 0 ? scene.model.front_line : scene.model.back_line).normalized();
    if (!muscles[k].nodes.empty())
      length_and_radius(tm.rest_positions, muscles[k], muscles[k].rest_length, muscles[k].rest_radius);
  }
  std::vector<std::vector<int>> bulge_vertices(scene.bulge_areas.size());
  for (size_t a = 0; a < scene.bulge_areas.size(); ++a) {
    for (int i = 0; i < skin.num_vertices(); ++i)
      if (scene.bulge_areas[a].contains(skin.vertices.col(i))) bulge_vertices[a].push_back(i);
    if (bulge_vertices[a].empty())
      throw msd::Error(scene.file + ": analysis.bulge '" + scene.bulge_areas[a].name + "' holds no skin vertex");
  }
  std::vector<char> skin_lower(static_cast<size_t>(skin.num_vertices()));
  for (int i = 0; i < skin.num_vertices(); ++i)
    skin_lower[static_cast<size_t>(i)] = (msd::Vec3(skin.vertices.col(i)) - leg.knee.centre).dot(scene.model.leg_axis) < 0.0;
  std::vector<int> probe_nodes;
  if (scene.wobble_probe) {
    for (int i = 0; i < n; ++i)
      if (!leg.attached[static_cast<size_t>(i)] && scene.wobble_probe->contains(tm.rest_positions.col(i)))
        probe_nodes.push_back(i);
    if (probe_nodes.empty()) throw msd::Error(scene.file + ": analysis.wobble.probe holds no free tissue node");
  }
  const msd::Vec3 shank_rest = (leg.lower_bone.mass > 0.0 ? leg.lower_bone.centre : msd::Vec3(tm.rest_positions.col(leg.lower_nodes.front()))) -
                               leg.knee.centre;
  std::vector<int> thigh_free;
  for (int i = 0; i < n; ++i)
    if (!leg.attached[static_cast<size_t>(i)] &&
        (msd::Vec3(tm.rest_positions.col(i)) - leg.knee.centre).dot(scene.model.leg_axis) > 0.0)
      thigh_free.push_back(i);
  const msd::Vec3 down = scene.model.gravity.norm() > 0.0 ? msd::Vec3(scene.model.gravity.normalized()) : msd::Vec3(-msd::Vec3::UnitZ());

  std::vector<LegVariant> variants = scene.variants;
  if (variants.empty()) variants.push_back({"", scene.front_activation, scene.back_activation});
  const long steps_per_frame = std::lround(scene.output_interval / scene.dt);
  const long total_steps = std::lround(scene.duration / scene.dt);
  std::vector<LegRunSummary> summaries;

  for (const LegVariant& variant : variants) {
    const std::string dir = variant.name.empty() ? out_dir : (fs::path(out_dir) / variant.name).string();
    fs::create_directories(fs::path(dir) / "skin");
    fs::remove(fs::path(dir) / "summary.json", ignore);
    LegRunSummary sum;
    sum.name = scene.name;
    sum.variant = variant.name;
    sum.dir = dir;
    sum.nodes = n;
    sum.tets = static_cast<long>(leg.tets.size());

    std::vector<SeriesColumn> cols = {{"time", "s"},
                                      {"knee_angle", "deg"},
                                      {"knee_velocity", "deg/s"},
                                      {"knee_torque", "N m"},
                                      {"passive_joint_torque", "N m"},
                                      {"joint_reaction_x", "N"},
                                      {"joint_reaction_y", "N"},
                                      {"joint_reaction_z", "N"},
                                      {"front_activation", "1"},
                                      {"back_activation", "1"}};
    for (const std::string& t : leg.tendon_names) cols.push_back({"tension_" + t, "N"});
    for (const std::string& t : leg.tendon_names) cols.push_back({"straightness_" + t, "1"});
    cols.insert(cols.end(), {{"volume_ratio_passive", "1"},
                             {"volume_ratio_front_muscle", "1"},
                             {"volume_ratio_back_muscle", "1"},
                             {"length_ratio_front_muscle", "1"},
                             {"length_ratio_back_muscle", "1"},
                             {"radius_ratio_front_muscle", "1"},
                             {"radius_ratio_back_muscle", "1"},
                             {"knee_contact_area", "m^2"},
                             {"knee_contacts", "1"}});
    for (const msd::RigidObstacle& ob : leg.obstacles) {
      cols.push_back({"obstacle_force_" + ob.name, "N"});
      cols.push_back({"obstacle_contacts_" + ob.name, "1"});
    }
    for (const LegBox& a : scene.bulge_areas) cols.push_back({"bulge_" + a.name, "m"});
    cols.insert(cols.end(), {{"lower_leg_below_horizontal", "deg"},
                             {"thigh_flesh_sag", "m"},
                             {"kinetic_energy", "J"},
                             {"elastic_energy", "J"},
                             {"max_node_speed", "m/s"}});
    if (!probe_nodes.empty()) {
      cols.push_back({"probe_x", "m"});
      cols.push_back({"probe_y", "m"});
      cols.push_back({"probe_z", "m"});
    }
    RunMeta meta;
    meta.solver = "msd-leg";
    meta.spec_text = scene.text;
    meta.spec_path = scene.file;
    meta.spec_name = scene.name;
    meta.material = {{"passive_youngs_modulus", scene.model.passive.youngs_modulus},
                     {"passive_density", scene.model.passive.density},
                     {"passive_damping_time", scene.model.passive.damping_time},
                     {"muscle_youngs_modulus", scene.model.muscle.youngs_modulus},
                     {"muscle_density", scene.model.muscle.density},
                     {"tendon_modulus", scene.model.tendon_modulus},
                     {"strand_area", scene.model.strand_area},
                     {"max_muscle_stress", scene.model.max_muscle_stress}};
    meta.text = {{"terms", msd::force_terms_to_string(tm.terms)},
                 {"variant", variant.name},
                 {"knee_control", scene.knee_angle.empty() ? "dynamic"
                                  : scene.knee_release ? "scripted until " + json_number(*scene.knee_release) + " s, then dynamic"
                                                       : "scripted"},
                 {"geometry", scene.geometry}};
    const std::string h5 = (fs::path(dir) / "leg.h5").string();
    ResultsWriter writer(h5, meta, cols);
    {
      std::vector<std::array<double, 3>> pts(static_cast<size_t>(n));
      for (int i = 0; i < n; ++i) pts[static_cast<size_t>(i)] = {tm.rest_positions(0, i), tm.rest_positions(1, i), tm.rest_positions(2, i)};
      std::vector<std::vector<int>> cells;
      for (const msd::Tet& t : leg.tets) cells.push_back({t[0], t[1], t[2], t[3]});
      writer.add_point_set("nodes", pts, cells);
      std::vector<std::array<double, 3>> sp(static_cast<size_t>(skin.num_vertices()));
      for (int i = 0; i < skin.num_vertices(); ++i) sp[static_cast<size_t>(i)] = {skin.vertices(0, i), skin.vertices(1, i), skin.vertices(2, i)};
      std::vector<std::vector<int>> tris;
      for (const msd::Tri& t : skin.triangles) tris.push_back({t[0], t[1], t[2]});
      writer.add_point_set("skin", sp, tris);
    }

    msd::LegState state = msd::leg_rest_state(leg, scene.initial_angle);
    state.knee.velocity = scene.initial_velocity;
    msd::place_attached(leg.knee, state.knee, tm.rest_positions, leg.lower_nodes, state.tissue.x, state.tissue.v);
    msd::LegScratch scratch;
    msd::LegControls controls;
    controls.tendon_length_scale.assign(leg.tendon_names.size(), 1.0);
    controls.obstacle_offset.assign(leg.obstacles.size(), msd::Vec3::Zero());
    controls.obstacle_velocity.assign(leg.obstacles.size(), msd::Vec3::Zero());
    auto set_controls = [&](double t) {  // the controls in effect over the step ending at t
      controls.front_activation = scene.script ? scene.script->activation("FRONT_MUSCLE", t) : variant.front;
      controls.back_activation = scene.script ? scene.script->activation("BACK_MUSCLE", t) : variant.back;
      double scale = 1.0;
      if (scene.pretension_fraction > 0.0) {
        const double ramp = scene.pretension_duration > 0.0
                                ? std::clamp((t - scene.pretension_start) / scene.pretension_duration, 0.0, 1.0)
                                : (t >= scene.pretension_start ? 1.0 : 0.0);
        scale = 1.0 - scene.pretension_fraction * ramp;
      }
      std::fill(controls.tendon_length_scale.begin(), controls.tendon_length_scale.end(), scale);
      controls.joint_torque = scene.joint_torque.empty() ? 0.0 : scene.joint_torque.at(t);
      if (!scene.knee_angle.empty() && (!scene.knee_release || t <= *scene.knee_release))
        controls.scripted_knee = msd::HingeState{scene.knee_angle.at(t), scene.knee_angle.rate(t - 0.5 * scene.dt)};
      else
        controls.scripted_knee.reset();
      for (size_t k = 0; k < leg.obstacles.size(); ++k)
        if (!scene.obstacle_motion[k].empty()) {
          controls.obstacle_offset[k] = scene.obstacle_motion[k].at(t);
          controls.obstacle_velocity[k] = scene.obstacle_motion[k].rate(t - 0.5 * scene.dt);
        }
    };
    // Tendons engaged later (a starting posture first): slack until then, then
    // their natural lengths are the paths' lengths at that moment.
    bool engaged = !scene.tendons_engage_at;
    if (!engaged)
      controls.strand_natural_length.assign(leg.strands.size(), std::numeric_limits<double>::infinity());
    auto engage = [&]() {
      for (size_t k = 0; k < leg.strands.size(); ++k) {
        controls.strand_natural_length[k] = msd::leg_strand_length(leg, leg.strands[k], state.tissue.x, state.knee.angle);
      }
      engaged = true;
    };
    set_controls(0.0);
    // The step-0 diagnostics (forces at rest) for the first row.
    {
      msd::LegState probe = state;
      msd::step_leg(leg, probe, controls, 0.0, scratch);
    }

    msd::Points skin_x(3, skin.num_vertices());
    std::vector<double> frame_times;
    std::map<std::string, std::vector<double>> recorded;
    msd::Points strand_points;  // reused by record()
    auto record = [&]() {
      const msd::Points& x = state.tissue.x;
      const double t = state.tissue.t;
      std::vector<double> row = {t,
                                 state.knee.angle / kDeg,
                                 state.knee.velocity / kDeg,
                                 scratch.knee_torque,
                                 scratch.passive_joint_torque,
                                 scratch.joint_reaction.x(),
                                 scratch.joint_reaction.y(),
                                 scratch.joint_reaction.z(),
                                 controls.front_activation,
                                 controls.back_activation};
      for (size_t k = 0; k < leg.tendon_names.size(); ++k)
        row.push_back(k < scratch.tendon_tension.size() ? scratch.tendon_tension[k] : 0.0);
      std::vector<double> straight(leg.tendon_names.size(), 0.0);
      std::vector<int> count(leg.tendon_names.size(), 0);
      for (const msd::LegStrand& s : leg.strands) {
        msd::leg_strand_points(leg, s, x, state.knee.angle, strand_points);
        const double chord = (strand_points.col(strand_points.cols() - 1) - strand_points.col(0)).norm();
        straight[static_cast<size_t>(s.tendon)] += chord / msd::leg_strand_length(leg, s, x, state.knee.angle);
        ++count[static_cast<size_t>(s.tendon)];
      }
      for (size_t k = 0; k < straight.size(); ++k) {
        straight[k] /= std::max(1, count[k]);
        row.push_back(straight[k]);
      }
      for (int r = 0; r < 3; ++r)
        row.push_back(rest_volume[r] > 0.0 ? region_volume(x, leg.tets, tet_region, regions[r]) / rest_volume[r] : 1.0);
      double len[2] = {1.0, 1.0}, rad[2] = {1.0, 1.0};
      for (int k = 0; k < 2; ++k)
        if (!muscles[k].nodes.empty()) {
          length_and_radius(x, muscles[k], len[k], rad[k]);
          len[k] /= muscles[k].rest_length;
          rad[k] /= muscles[k].rest_radius;
        }
      row.insert(row.end(), {len[0], len[1], rad[0], rad[1], scratch.knee_contact.area,
                             static_cast<double>(scratch.knee_contact.contacts)});
      for (size_t k = 0; k < leg.obstacles.size(); ++k) {
        const double fk = k < scratch.obstacles.size() ? scratch.obstacles[k].force.norm() : 0.0;
        row.push_back(fk);
        row.push_back(k < scratch.obstacles.size() ? scratch.obstacles[k].contacts : 0.0);
      }
      msd::embedded_positions(x, limb.mesh.mesh.tets, skin_embedding, skin_x);
      const msd::Mat3 rot = msd::hinge_rotation(leg.knee, state.knee.angle);
      for (size_t a = 0; a < scene.bulge_areas.size(); ++a) {
        double b = -1e300;
        for (int i : bulge_vertices[a]) {
          const msd::Vec3 X = skin.vertices.col(i);
          const bool lower = skin_lower[static_cast<size_t>(i)];
          const msd::Vec3 ref = lower ? msd::Vec3(leg.knee.centre + rot * (X - leg.knee.centre)) : X;
          const msd::Vec3 nn = lower ? msd::Vec3(rot * skin_normals.col(i)) : msd::Vec3(skin_normals.col(i));
          b = std::max(b, (msd::Vec3(skin_x.col(i)) - ref).dot(nn));
        }
        row.push_back(b);
      }
      const msd::Vec3 shank = rot * shank_rest;
      row.push_back(std::asin(std::clamp(shank.normalized().dot(down), -1.0, 1.0)) / kDeg);
      double sag = 0.0;
      for (int i : thigh_free) sag += (x.col(i) - tm.rest_positions.col(i)).dot(down);
      row.push_back(thigh_free.empty() ? 0.0 : sag / static_cast<double>(thigh_free.size()));
      double elastic = msd::conservative_energy(tm, x);
      for (size_t si = 0; si < leg.strands.size(); ++si) {
        const msd::LegStrand& s = leg.strands[si];
        const double l0 = si < controls.strand_natural_length.size() ? controls.strand_natural_length[si] : s.natural_length;
        if (std::isfinite(l0))
          elastic += msd::leg_strand_energy(leg, s, x, state.knee.angle,
                                            controls.tendon_length_scale[static_cast<size_t>(s.tendon)] * l0);
      }
      row.push_back(msd::leg_kinetic_energy(leg, state));
      row.push_back(elastic);
      row.push_back(state.tissue.v.colwise().norm().maxCoeff());
      if (!probe_nodes.empty()) {
        msd::Vec3 d = msd::Vec3::Zero();
        for (int i : probe_nodes) d += x.col(i) - tm.rest_positions.col(i);
        d /= static_cast<double>(probe_nodes.size());
        row.insert(row.end(), {d.x(), d.y(), d.z()});
      }
      writer.append(row);
      for (size_t c = 0; c < cols.size(); ++c) recorded[cols[c].name].push_back(row[c]);
      // Fields: node and skin displacements; an OBJ of the skin.
      std::vector<std::array<double, 3>> d(static_cast<size_t>(n));
      for (int i = 0; i < n; ++i)
        d[static_cast<size_t>(i)] = {x(0, i) - tm.rest_positions(0, i), x(1, i) - tm.rest_positions(1, i),
                                     x(2, i) - tm.rest_positions(2, i)};
      writer.append_frame("nodes", t, d);
      std::vector<std::array<double, 3>> sd(static_cast<size_t>(skin.num_vertices()));
      for (int i = 0; i < skin.num_vertices(); ++i)
        sd[static_cast<size_t>(i)] = {skin_x(0, i) - skin.vertices(0, i), skin_x(1, i) - skin.vertices(1, i),
                                      skin_x(2, i) - skin.vertices(2, i)};
      writer.append_frame("skin", t, sd);
      const long frame = static_cast<long>(frame_times.size());
      if (scene.obj_every > 0 && frame % scene.obj_every == 0) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04ld.obj", frame);
        write_obj((fs::path(dir) / "skin" / name).string(), skin_x, skin.triangles);
      }
      frame_times.push_back(t);
      if (std::fmod(t + 1e-9, 0.2) < 0.5 * scene.output_interval || frame == 0)
        sum.trajectory.emplace_back(t, state.knee.angle / kDeg);
    };

    const auto start = std::chrono::steady_clock::now();
    record();
    try {
      for (long k = 1; k <= total_steps; ++k) {
        if (!engaged && (k - 1) * scene.dt >= *scene.tendons_engage_at - 1e-12) engage();
        set_controls(k * scene.dt);
        msd::step_leg(leg, state, controls, scene.dt, scratch);
        state.tissue.t = k * scene.dt;  // no drift from summing dt
        if (k % steps_per_frame == 0) record();
        if (progress && k % 500 == 0) progress(state.tissue.t, scene.duration);
        sum.steps = k;
      }
    } catch (const msd::SimulationFailure& e) {
      sum.status = "failed";
      sum.failure = e.what();
    }
    sum.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sum.simulated = sum.steps * scene.dt;
    sum.frames = static_cast<long>(frame_times.size());
    writer.set_timing(sum.wall_seconds, sum.steps, scene.dt, 1);
    writer.set_timing_detail("wall_per_simulated_second", sum.wall_per_simulated());

    // Scalars for the summary, over the frames from analysis.from on (a
    // scripted lead-in to the starting posture is not part of the result).
    size_t first = 0;
    while (first + 1 < frame_times.size() && frame_times[first] < scene.analysis_from - 1e-9) ++first;
    for (auto& [name, series] : recorded) series.erase(series.begin(), series.begin() + static_cast<long>(first));
    std::vector<double> times(frame_times.begin() + static_cast<long>(first), frame_times.end());
    auto largest = [&](const std::string& column) {
      const auto& c = recorded.at(column);
      return *std::max_element(c.begin(), c.end());
    };
    auto& v = sum.values;
    v["analysis_from_s"] = times.front();
    v["joint_space_tets_left_out"] = static_cast<double>(leg.joint_space_tets);
    const auto& angle = recorded["knee_angle"];
    v["knee_angle_start_deg"] = angle.front();
    v["knee_angle_end_deg"] = angle.back();
    v["knee_angle_max_deg"] = *std::max_element(angle.begin(), angle.end());
    v["knee_angle_min_deg"] = *std::min_element(angle.begin(), angle.end());
    v["time_of_max_knee_angle_s"] =
        times[static_cast<size_t>(std::max_element(angle.begin(), angle.end()) - angle.begin())];
    v["time_of_min_knee_angle_s"] =
        times[static_cast<size_t>(std::min_element(angle.begin(), angle.end()) - angle.begin())];
    const auto& below = recorded["lower_leg_below_horizontal"];
    v["lower_leg_highest_below_horizontal_deg"] = *std::min_element(below.begin(), below.end());
    v["lower_leg_end_below_horizontal_deg"] = below.back();
    v["knee_contact_area_max_m2"] = largest("knee_contact_area");
    v["knee_contact_area_end_m2"] = recorded["knee_contact_area"].back();
    for (size_t i = 0; i < times.size(); ++i)
      if (recorded["knee_contacts"][i] > 0.0) {
        v["knee_contact_first_s"] = times[i];
        break;
      }
    for (size_t a = 0; a < scene.bulge_areas.size(); ++a) {
      v["bulge_" + scene.bulge_areas[a].name + "_max_m"] = largest("bulge_" + scene.bulge_areas[a].name);
      v["bulge_" + scene.bulge_areas[a].name + "_end_m"] = recorded["bulge_" + scene.bulge_areas[a].name].back();
    }
    for (const char* m : {"front_muscle", "back_muscle"}) {
      const auto& len = recorded[std::string("length_ratio_") + m];
      const auto& rad = recorded[std::string("radius_ratio_") + m];
      const auto& vol = recorded[std::string("volume_ratio_") + m];
      v[std::string(m) + "_length_ratio_min"] = *std::min_element(len.begin(), len.end());
      v[std::string(m) + "_radius_ratio_max"] = *std::max_element(rad.begin(), rad.end());
      v[std::string(m) + "_volume_ratio_min"] = *std::min_element(vol.begin(), vol.end());
      v[std::string(m) + "_volume_ratio_max"] = *std::max_element(vol.begin(), vol.end());
    }
    const auto& pv = recorded["volume_ratio_passive"];
    v["passive_volume_ratio_min"] = *std::min_element(pv.begin(), pv.end());
    for (size_t k = 0; k < leg.tendon_names.size(); ++k) {
      const auto& T = recorded["tension_" + leg.tendon_names[k]];
      v["tendon_" + leg.tendon_names[k] + "_tension_max_N"] = *std::max_element(T.begin(), T.end());
      v["tendon_" + leg.tendon_names[k] + "_straightness_start"] = recorded["straightness_" + leg.tendon_names[k]].front();
      v["tendon_" + leg.tendon_names[k] + "_straightness_max"] = largest("straightness_" + leg.tendon_names[k]);
    }
    for (size_t k = 0; k < leg.obstacles.size(); ++k)
      v["obstacle_" + leg.obstacles[k].name + "_force_max_N"] = largest("obstacle_force_" + leg.obstacles[k].name);
    const auto& sag = recorded["thigh_flesh_sag"];
    v["thigh_flesh_sag_end_m"] = sag.back();
    v["thigh_flesh_sag_max_m"] = *std::max_element(sag.begin(), sag.end());
    const auto& speed = recorded["max_node_speed"];
    v["max_node_speed_end_m_s"] = speed.back();
    const auto& ke = recorded["kinetic_energy"];
    v["kinetic_energy_end_J"] = ke.back();
    if (scene.drop_release) drop_metrics(times, angle, *scene.drop_release, v);
    if (!probe_nodes.empty()) {
      // The probe's mean displacement after `after`, on its direction of
      // largest variance, as a ring-down.
      std::vector<double> tt;
      std::vector<msd::Vec3> d;
      for (size_t i = 0; i < times.size(); ++i)
        if (times[i] >= scene.wobble_after) {
          tt.push_back(times[i]);
          d.emplace_back(recorded["probe_x"][i], recorded["probe_y"][i], recorded["probe_z"][i]);
        }
      if (d.size() >= 8) {
        msd::Vec3 mean = msd::Vec3::Zero();
        for (const auto& p : d) mean += p;
        mean /= static_cast<double>(d.size());
        msd::Mat3 cov = msd::Mat3::Zero();
        for (const auto& p : d) cov += (p - mean) * (p - mean).transpose();
        Eigen::SelfAdjointEigenSolver<msd::Mat3> es(cov);
        const msd::Vec3 axis = es.eigenvectors().col(2);
        // Less its straight-line drift (the flesh still settling under gravity).
        std::vector<double> sig;
        double st = 0.0, ss = 0.0, stt = 0.0, sts = 0.0;
        for (size_t i = 0; i < d.size(); ++i) {
          const double y = axis.dot(d[i] - mean);
          sig.push_back(y);
          st += tt[i];
          ss += y;
          stt += tt[i] * tt[i];
          sts += tt[i] * y;
        }
        const double nn = static_cast<double>(d.size());
        const double slope = (nn * sts - st * ss) / (nn * stt - st * st), icpt = (ss - slope * st) / nn;
        double amp = 0.0;
        for (size_t i = 0; i < sig.size(); ++i) {
          sig[i] -= icpt + slope * tt[i];
          amp = std::max(amp, std::abs(sig[i]));
        }
        const RingDown r = analyse_ring_down(tt, sig);
        v["wobble_frequency_hz"] = r.frequency;
        v["wobble_damping_ratio"] = r.damping_ratio;
        v["wobble_amplitude_m"] = amp;
        v["wobble_peaks"] = r.peaks;
      }
    }
    if (sum.status == "failed")
      writer.fail(sum.failure);
    else
      writer.finish();
    write_xdmf((fs::path(dir) / "leg.xdmf").string(), "leg.h5", sum.frames, frame_times, n,
               static_cast<long>(leg.tets.size()), skin.num_vertices(), skin.num_triangles());
    write_summary(dir, sum, scene);
    summaries.push_back(sum);
  }
  if (!scene.variants.empty()) {
    // One summary over the variants at the top.
    const std::string path = (fs::path(out_dir) / "summary.json").string();
    std::ofstream out(path + ".partial");
    out << "{\n  \"scene\": " << json_string(scene.name) << ",\n  \"variants\": {";
    for (size_t i = 0; i < summaries.size(); ++i) {
      std::string body = json_object(summaries[i], scene);
      // indent the nested object
      std::string ind;
      for (char c : body) {
        ind += c;
        if (c == '\n') ind += "    ";
      }
      while (!ind.empty() && (ind.back() == ' ' || ind.back() == '\n')) ind.pop_back();
      out << (i ? ",\n    " : "\n    ") << json_string(summaries[i].variant) << ": " << ind;
    }
    out << "\n  }\n}\n";
    out.close();
    if (!out) throw msd::Error(path + ": write failed");
    fs::rename(path + ".partial", path);
  }
  return summaries;
}

std::string format_leg_summary(const LegRunSummary& s) {
  std::ostringstream o;
  char line[256];
  std::snprintf(line, sizeof line, "%s%s%s: %s, %.2f s simulated in %.1f s wall (%.2f s per simulated s), %ld frames\n",
                s.name.c_str(), s.variant.empty() ? "" : " / ", s.variant.c_str(), s.status.c_str(), s.simulated,
                s.wall_seconds, s.wall_per_simulated(), s.frames);
  o << line;
  if (!s.failure.empty()) o << "  failure: " << s.failure << "\n";
  for (const auto& [k, v] : s.values) {
    std::snprintf(line, sizeof line, "  %-44s %12.5g\n", k.c_str(), v);
    o << line;
  }
  return o.str();
}

}  // namespace bench
