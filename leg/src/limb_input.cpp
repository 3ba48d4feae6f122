#include "leg/limb_input.hpp"

#include "tbio/json.hpp"
#include "tbio/surface_check.hpp"
#include "tbio/yaml_fields.hpp"

#include "msd/io/vtu.hpp"
#include "msd/mesh/limb_mesher.hpp"
#include "msd/mesh/tendon_paths.hpp"

#include <chrono>
#include "msd/io/output_lock.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace leg {

namespace {

using tbio::Fields;

const std::map<std::string, int> kRegions{{"upper_bone", msd::kUpperBone},
                                          {"lower_bone", msd::kLowerBone},
                                          {"front_muscle", msd::kFrontMuscle},
                                          {"back_muscle", msd::kBackMuscle}};

// Surfaces that cross themselves, an inner surface that crosses the skin, and
// two bones or two muscles that cross each other are refused with the two
// triangles named (a bone against a muscle is allowed: erosion decides, as in
// msd::validate_limb).
void refuse_crossing_surfaces(const msd::LimbSurfaces& s) {
  std::vector<tbio::NamedSurface> list{{&s.skin, s.source.at(msd::kPassiveTissue)}};
  std::vector<int> region{msd::kPassiveTissue};
  msd::validate_closed_surface(s.skin, list[0].name);
  for (const auto& [r, m] : s.inner) {
    list.push_back({&m, s.source.at(r)});
    region.push_back(r);
    msd::validate_closed_surface(m, list.back().name);
  }
  std::vector<std::pair<int, int>> pairs;
  for (int a = 0; a < static_cast<int>(list.size()); ++a)
    for (int b = a + 1; b < static_cast<int>(list.size()); ++b)
      if (a == 0 || msd::is_bone(region[static_cast<size_t>(a)]) == msd::is_bone(region[static_cast<size_t>(b)]))
        pairs.emplace_back(a, b);
  tbio::refuse_intersections(list, pairs);
}

msd::VtuGrid surface_grid(const msd::TriangleMesh& m, const msd::Embedding& e) {
  msd::VtuGrid g;
  g.points = m.vertices;
  for (const auto& t : m.triangles) {
    g.cells.push_back({t[0], t[1], t[2]});
    g.types.push_back(msd::kVtkTriangle);
  }
  auto& tet = g.point_data["tet"];
  auto& dist = g.point_data["outside_distance"];
  for (const auto& v : e.vertices) {
    tet.push_back(v.tet);
    dist.push_back(v.distance);
  }
  return g;
}

}  // namespace

LimbInput read_limb_input(const std::string& scene_file) {
  const YAML::Node root = tbio::load_yaml_file(scene_file, "scene file");
  if (!root || !root.IsMap()) throw msd::Error(scene_file + ": the scene must be a YAML mapping");
  const Fields f(root, "", scene_file);
  f.only({"name", "description", "leg", "mesh", "tendons"});
  const Fields leg = f.section("leg");
  leg.only({"skin", "upper_bone", "lower_bone", "front_muscle", "back_muscle"});
  const fs::path folder = fs::path(scene_file).parent_path();
  auto file_of = [&](const std::string& key) {
    const fs::path p(leg.text(key));
    const fs::path full = p.is_absolute() ? p : folder / p;
    std::error_code ec;  // a name that cannot be looked up (too long, ...) is refused too, never thrown as fs's error
    if (!fs::exists(full, ec))
      throw msd::Error(leg.where(key) + (ec ? "cannot look up " + full.string() + ": " + ec.message()
                                            : "no such file: " + full.string()));
    return full.string();
  };
  LimbInput in;
  in.name = f.text_or("name", fs::path(scene_file).stem().string());
  msd::LimbSurfaces& surfaces = in.surfaces;
  surfaces.source[msd::kPassiveTissue] = file_of("skin");
  surfaces.skin = msd::read_surface(surfaces.source[msd::kPassiveTissue]);
  for (const auto& [key, region] : kRegions)
    if (leg.has(key)) {
      surfaces.source[region] = file_of(key);
      surfaces.inner[region] = msd::read_surface(surfaces.source[region]);
    }
  refuse_crossing_surfaces(surfaces);
  const Fields mesh = f.section("mesh");
  mesh.only({"spacing", "rotation", "rule", "origin", "pull", "pull_min_quality", "max_cubes", "memory_limit_gb"});
  msd::LimbMeshOptions& o = in.options;
  o.spacing = mesh.number("spacing");
  if (!(o.spacing > 0.0)) throw msd::Error(mesh.where("spacing") + "must be a positive length (m)");
  o.max_cubes = mesh.integer_or("max_cubes", o.max_cubes);
  if (o.max_cubes < 1) throw msd::Error(mesh.where("max_cubes") + "must be a positive number of cubes");
  if (mesh.has("memory_limit_gb")) o.memory.bytes = 1e9 * mesh.positive("memory_limit_gb");
  o.memory.how_to_raise = "mesh.memory_limit_gb in " + scene_file;
  o.memory.context = mesh.where("spacing");
  if (mesh.has("rotation")) {
    const auto r = mesh.number_list("rotation");
    if (r.size() != 3) throw msd::Error(mesh.where("rotation") + "needs three angles in degrees [x, y, z]");
    o.rotation_deg = msd::Vec3(r[0], r[1], r[2]);
  }
  if (mesh.has("origin")) {
    const auto r = mesh.number_list("origin");
    if (r.size() != 3) throw msd::Error(mesh.where("origin") + "needs three coordinates (m)");
    o.origin = msd::Vec3(r[0], r[1], r[2]);
  }
  if (mesh.has("pull")) {  // thesis 4.6: [{name, lo: [x, y, z], hi: [x, y, z]}]
    const YAML::Node list = root["mesh"]["pull"];
    if (!list.IsSequence()) throw msd::Error(mesh.where("pull") + "must be a list of areas {name, lo, hi}");
    for (size_t i = 0; i < list.size(); ++i) {
      const Fields a(list[i], "mesh.pull[" + std::to_string(i) + "]", scene_file);
      a.only({"name", "lo", "hi"});
      const auto lo = a.number_list("lo"), hi = a.number_list("hi");
      if (lo.size() != 3 || hi.size() != 3) throw msd::Error(a.where() + "lo and hi need three coordinates (m)");
      o.pull_areas.push_back({a.text("name"), msd::Vec3(lo[0], lo[1], lo[2]), msd::Vec3(hi[0], hi[1], hi[2])});
    }
  }
  o.pull_min_quality = mesh.number_or("pull_min_quality", o.pull_min_quality);
  try {
    o.rule = msd::parse_cube_rule(mesh.text_or("rule", "centre"));
  } catch (const msd::Error& e) {
    throw msd::Error(mesh.where("rule") + e.what());
  }

  // Tendons: [{name, muscle, bone, strands, path: [[x, y, z], ...]}].
  std::vector<msd::TendonPathSpec>& tendon_specs = in.tendons;
  if (f.has("tendons")) {
    const YAML::Node list = root["tendons"];
    if (!list.IsSequence()) throw msd::Error(f.where("tendons") + "must be a list of tendons");
    for (size_t i = 0; i < list.size(); ++i) {
      const Fields t(list[i], "tendons[" + std::to_string(i) + "]", scene_file);
      t.only({"name", "muscle", "bone", "strands", "path"});
      msd::TendonPathSpec spec;
      spec.name = t.text("name");
      const std::string muscle = t.text("muscle"), bone = t.text("bone");
      if (muscle != "front_muscle" && muscle != "back_muscle")
        throw msd::Error(t.where("muscle") + "'" + muscle + "' is not one of: front_muscle, back_muscle");
      if (bone != "upper_bone" && bone != "lower_bone")
        throw msd::Error(t.where("bone") + "'" + bone + "' is not one of: upper_bone, lower_bone");
      spec.muscle = kRegions.at(muscle);
      spec.bone = kRegions.at(bone);
      if (!surfaces.inner.count(spec.muscle)) throw msd::Error(t.where("muscle") + "the leg has no " + muscle);
      if (!surfaces.inner.count(spec.bone)) throw msd::Error(t.where("bone") + "the leg has no " + bone);
      spec.strands = static_cast<int>(t.integer_or("strands", 6));
      if (spec.strands < 1 || spec.strands > 64) throw msd::Error(t.where("strands") + "must be between 1 and 64");
      const YAML::Node path = list[i]["path"];
      if (!path || !path.IsSequence() || path.size() < 2)
        throw msd::Error(t.where("path") + "needs at least two points [x, y, z] (m)");
      for (size_t k = 0; k < path.size(); ++k) {
        if (!path[k].IsSequence() || path[k].size() != 3)
          throw msd::Error(t.where("path") + "point " + std::to_string(k) + " needs three coordinates");
        try {
          spec.path.emplace_back(path[k][0].as<double>(), path[k][1].as<double>(), path[k][2].as<double>());
        } catch (const YAML::Exception&) {
          throw msd::Error(t.where("path") + "point " + std::to_string(k) + " is not three numbers");
        }
      }
      tendon_specs.push_back(spec);
    }
  }

  for (size_t i = 0; i < tendon_specs.size(); ++i) {
    try {
      msd::validate_tendon_ends(surfaces, tendon_specs[i], o.spacing);
    } catch (const msd::Error& e) {
      throw msd::Error(scene_file + ": tendons[" + std::to_string(i) + "]: " + e.what());
    }
  }
  return in;
}

MeshedLimb mesh_limb_input(const LimbInput& in) {
  MeshedLimb out{msd::mesh_limb(in.surfaces, in.options), {}};
  for (const auto& spec : in.tendons) out.tendons.push_back(msd::route_tendon(out.mesh, spec));
  return out;
}

LegMeshSummary mesh_leg_scene(const std::string& scene_file, const std::string& out_dir) {
  const auto start = std::chrono::steady_clock::now();
  const LimbInput in = read_limb_input(scene_file);
  const msd::LimbSurfaces& surfaces = in.surfaces;
  const msd::LimbMeshOptions& o = in.options;
  std::vector<std::string> inputs{scene_file}, outputs;
  for (const auto& [region, file] : surfaces.source) inputs.push_back(file);
  for (const char* f : {"mesh.vtu", "bone_points.vtu", "tendons.vtu", "summary.json"})
    outputs.push_back((fs::path(out_dir) / f).string());
  for (const char* f : {"skin", "upper_bone", "lower_bone", "front_muscle", "back_muscle"})
    outputs.push_back((fs::path(out_dir) / "surfaces" / (std::string(f) + ".vtu")).string());
  msd::refuse_output_over_inputs("--out", outputs, inputs);
  fs::path folder = fs::path(out_dir).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();
  if (!folder.parent_path().empty()) fs::create_directories(folder.parent_path());
  const msd::OutputLock lock(folder.string(), msd::this_command_line());  // one mesh run per folder
  const MeshedLimb limb = mesh_limb_input(in);
  // A summary from an earlier run must not outlive a failed one.
  std::error_code ignore;
  fs::remove(fs::path(out_dir) / "summary.json", ignore);
  const msd::LimbMesh& m = limb.mesh;
  const std::vector<msd::TendonStrands>& tendons = limb.tendons;

  // Outputs: everything else first, summary.json last.
  fs::create_directories(fs::path(out_dir) / "surfaces");
  msd::VtuGrid tets;
  tets.points = m.mesh.nodes;
  for (size_t e = 0; e < m.mesh.tets.size(); ++e) {
    const auto& t = m.mesh.tets[e];
    tets.cells.push_back({t[0], t[1], t[2], t[3]});
    tets.types.push_back(msd::kVtkTetra);
    tets.cell_data["region"].push_back(m.mesh.region[e]);
  }
  auto& bp = tets.point_data["bone_point"];
  bp.assign(static_cast<size_t>(m.mesh.num_nodes()), -1.0);
  msd::VtuGrid points;
  points.points.resize(3, static_cast<Eigen::Index>(m.bone_points.size()));
  for (size_t i = 0; i < m.bone_points.size(); ++i) {
    bp[static_cast<size_t>(m.bone_points[i].first)] = m.bone_points[i].second;
    points.points.col(static_cast<Eigen::Index>(i)) = m.mesh.nodes.col(m.bone_points[i].first);
    points.cells.push_back({static_cast<int>(i)});
    points.types.push_back(msd::kVtkVertex);
    points.cell_data["region"].push_back(m.bone_points[i].second);
  }
  msd::write_vtu((fs::path(out_dir) / "mesh.vtu").string(), tets);
  msd::write_vtu((fs::path(out_dir) / "bone_points.vtu").string(), points);
  msd::VtuGrid strands;
  strands.points = m.mesh.nodes;
  for (size_t t = 0; t < tendons.size(); ++t)
    for (size_t k = 0; k < tendons[t].strands.size(); ++k) {
      strands.cells.push_back(tendons[t].strands[k]);
      strands.types.push_back(msd::kVtkPolyLine);
      strands.cell_data["tendon"].push_back(static_cast<double>(t));
      strands.cell_data["strand"].push_back(static_cast<double>(k));
    }
  msd::write_vtu((fs::path(out_dir) / "tendons.vtu").string(), strands);

  LegMeshSummary s;
  for (const auto& [r, e] : m.embedded) {
    const msd::TriangleMesh& surface = r == msd::kPassiveTissue ? surfaces.skin : surfaces.inner.at(r);
    const std::string name = r == msd::kPassiveTissue ? "skin" : msd::region_name(r);
    msd::write_vtu((fs::path(out_dir) / "surfaces" / (name + ".vtu")).string(), surface_grid(surface, e));
    s.embedded_vertices += static_cast<long>(e.vertices.size());
    s.embedded_outside += e.outside;
    s.max_outside_distance = std::max(s.max_outside_distance, e.max_outside_distance);
  }
  s.cubes = m.cubes;
  s.tets = m.mesh.num_tets();
  s.nodes = m.mesh.num_nodes();
  s.bone_points = static_cast<long>(m.bone_points.size());
  for (const auto& t : tendons) s.tendon_strands += static_cast<long>(t.strands.size());
  for (int r : {msd::kPassiveTissue, msd::kFrontMuscle, msd::kBackMuscle, msd::kUpperBone, msd::kLowerBone})
    s.tets_by_region[msd::region_name(r)] = m.tets_by_region.count(r) ? m.tets_by_region.at(r) : 0;
  s.min_quality = msd::min_quality(m.mesh);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  tbio::Json j;
  j["scene"] = scene_file;
  j["spacing"] = o.spacing;
  j["cubes"] = s.cubes;
  j["tets"] = s.tets;
  j["nodes"] = s.nodes;
  j["tets_by_region"] = s.tets_by_region;
  j["bone_points"] = s.bone_points;
  j["tendon_strands"] = s.tendon_strands;
  j["embedded_vertices"] = s.embedded_vertices;
  j["embedded_outside"] = s.embedded_outside;
  j["max_outside_distance"] = s.max_outside_distance;
  j["pulled_nodes"] = m.pull.moved;
  j["pull_gap_before"] = m.pull.gap_before;
  j["pull_gap_after"] = m.pull.gap_after;
  j["min_quality"] = s.min_quality;
  j["seconds"] = s.seconds;
  tbio::write_json_file((fs::path(out_dir) / "summary.json").string(), j);
  return s;
}

std::string format_leg_mesh_summary(const LegMeshSummary& s) {
  std::ostringstream o;
  o << "cubes              " << s.cubes << "\ntets               " << s.tets << " (";
  bool first = true;
  for (const auto& [k, v] : s.tets_by_region) {
    o << (first ? "" : ", ") << k << " " << v;
    first = false;
  }
  o << ")\nnodes              " << s.nodes << "\nbone points        " << s.bone_points << "\ntendon strands     "
    << s.tendon_strands << "\nembedded vertices  " << s.embedded_vertices << " (" << s.embedded_outside
    << " outside the tets, at most " << s.max_outside_distance * 1e3 << " mm away)\nmin quality        "
    << s.min_quality << "\nseconds            " << s.seconds << "\n";
  return o.str();
}

}  // namespace leg
