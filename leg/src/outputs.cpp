#include "leg/outputs.hpp"

#include "tbio/series_tools.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/io/atomic_file.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace fs = std::filesystem;

namespace leg {

namespace {

std::vector<std::array<double, 3>> rows_of(const msd::Points& p) {
  std::vector<std::array<double, 3>> r(static_cast<size_t>(p.cols()));
  for (int i = 0; i < p.cols(); ++i) r[static_cast<size_t>(i)] = {p(0, i), p(1, i), p(2, i)};
  return r;
}

std::vector<std::array<double, 3>> displacement(const msd::Points& x, const msd::Points& rest) {
  std::vector<std::array<double, 3>> d(static_cast<size_t>(x.cols()));
  for (int i = 0; i < x.cols(); ++i)
    d[static_cast<size_t>(i)] = {x(0, i) - rest(0, i), x(1, i) - rest(1, i), x(2, i) - rest(2, i)};
  return d;
}

}  // namespace

tbio::RunMeta run_meta(const LegScene& scene, const LegVariant& variant, const msd::LegModel& model) {
  tbio::RunMeta meta;
  meta.solver = "msd-leg";
  meta.spec_text = scene.text;
  meta.spec_path = scene.file;
  meta.spec_name = scene.name;
  const msd::LegModelOptions& o = scene.model;
  meta.material = {{"passive_youngs_modulus", o.passive.youngs_modulus},
                   {"passive_density", o.passive.density},
                   {"passive_damping_time", o.passive.damping_time},
                   {"muscle_youngs_modulus", o.muscle.youngs_modulus},
                   {"muscle_density", o.muscle.density},
                   {"tendon_modulus", o.tendon_modulus},
                   {"strand_area", o.strand_area},
                   {"max_muscle_stress", o.max_muscle_stress}};
  if (o.front_pcsa) meta.material.push_back({"front_pcsa", *o.front_pcsa});
  if (o.back_pcsa) meta.material.push_back({"back_pcsa", *o.back_pcsa});
  if (o.skin) {
    meta.material.push_back({"skin_youngs_modulus", o.skin->youngs_modulus});
    meta.material.push_back({"skin_thickness", o.skin->thickness});
  }
  const std::string knee_control =
      scene.knee_angle.empty() ? "dynamic"
      : scene.knee_release     ? "scripted until " + tbio::json_number(*scene.knee_release) + " s, then dynamic"
                               : "scripted";
  meta.text = {{"terms", msd::force_terms_to_string(model.tissue.terms)},
               {"variant", variant.name},
               {"knee_control", knee_control},
               {"geometry", scene.geometry}};
  return meta;
}

void add_rest_geometry(tbio::ResultsWriter& writer, const msd::LegModel& model, const msd::TriangleMesh& skin,
                       const msd::TriangleMesh& bones, const msd::TriangleMesh& obstacles) {
  std::vector<std::vector<int>> cells;
  for (const msd::Tet& t : model.tets) cells.push_back({t[0], t[1], t[2], t[3]});
  writer.add_point_set("nodes", rows_of(model.tissue.rest_positions), cells);
  std::vector<std::vector<int>> tris;
  for (const msd::Tri& t : skin.triangles) tris.push_back({t[0], t[1], t[2]});
  writer.add_point_set("skin", rows_of(skin.vertices), tris);
  for (const auto& [name, mesh] : {std::pair<const char*, const msd::TriangleMesh*>{"bones", &bones}, {"obstacles", &obstacles}}) {
    if (mesh->num_vertices() == 0) continue;
    tris.clear();
    for (const msd::Tri& t : mesh->triangles) tris.push_back({t[0], t[1], t[2]});
    writer.add_point_set(name, rows_of(mesh->vertices), tris);
  }
}

void append_frame_fields(tbio::ResultsWriter& writer, const Frame& frame, const Instruments& in) {
  const double t = frame.state->tissue.t;
  writer.append_frame("nodes", t, displacement(frame.state->tissue.x, in.leg->tissue.rest_positions));
  writer.append_frame("skin", t, displacement(frame.skin_x, in.skin->vertices));
  if (in.bones.num_vertices() > 0) writer.append_frame("bones", t, displacement(frame.bones_x, in.bones.vertices));
  if (in.obstacles.num_vertices() > 0)
    writer.append_frame("obstacles", t, displacement(frame.obstacles_x, in.obstacles.vertices));
}

void write_skin_obj(const std::string& dir, long index, const msd::Points& skin_x, const msd::TriangleMesh& skin) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04ld.obj", index);
  msd::write_obj((fs::path(dir) / "skin" / name).string(), skin_x, skin.triangles, 6);
}

void write_xdmf(const std::string& path, const std::string& h5_name, const std::vector<double>& times, long nodes,
                long tets, long skin_vertices, long skin_triangles, long bone_vertices, long bone_triangles) {
  const long frames = static_cast<long>(times.size());
  msd::write_file_atomically(path, [&](std::ostream& x) {
    x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n <Domain>\n";
    auto grid = [&](const std::string& name, const std::string& set, const std::string& topology, long cells,
                    int per_cell, const std::string& cell_set, long points) {
      x << "  <Grid Name=\"" << name << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
      for (long k = 0; k < frames; ++k) {
        x << "   <Grid Name=\"" << name << "_" << k << "\" GridType=\"Uniform\">\n"
          << "    <Time Value=\"" << tbio::json_number(times[static_cast<size_t>(k)]) << "\"/>\n"
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
    if (bone_vertices > 0) grid("bones", "bones", "Triangle", bone_triangles, 3, "bones_triangles", bone_vertices);
    x << " </Domain>\n</Xdmf>\n";
  });
}

tbio::Json summary_json(const LegRunSummary& s, const LegScene& scene) {
  tbio::Json j;
  j["scene"] = scene.name;
  j["scene_file"] = scene.file;
  if (!scene.overrides.empty()) j["scene_overrides"] = scene.overrides;  // the file was not run as shipped
  j["variant"] = s.variant;
  j["status"] = s.status;
  if (!s.failure.empty()) j["failure"] = s.failure;
  j["simulated_seconds"] = s.simulated;
  j["wall_seconds"] = s.wall_seconds;
  j["wall_per_simulated_second"] = s.wall_per_simulated();
  j["dt"] = scene.dt;
  j["integrator"] = msd::to_string(scene.integrator);
  if (msd::is_implicit(scene.integrator)) {
    j["newton_iterations"] = s.newton_iterations;
    j["step_cuts"] = s.step_cuts;
    j["factorizations"] = s.factorizations;
  }
  j["steps"] = s.steps;
  j["frames"] = s.frames;
  j["nodes"] = s.nodes;
  j["tets"] = s.tets;
  j["warnings"] = tbio::Json::array();
  for (const std::string& w : s.warnings) j["warnings"].push_back(w);
  j["values"] = tbio::Json::object();
  for (const auto& [k, v] : s.values) j["values"][k] = std::isfinite(v) ? tbio::Json(v) : tbio::Json(nullptr);
  j["knee_angle_trajectory_deg"] = tbio::Json::array();
  for (const auto& [t, a] : s.trajectory) j["knee_angle_trajectory_deg"].push_back({tbio::rounded(t, 6), tbio::rounded(a, 6)});
  return j;
}

void write_variants_summary(const std::string& out_dir, const LegScene& scene,
                            const std::vector<LegRunSummary>& summaries) {
  tbio::Json j;
  j["scene"] = scene.name;
  j["variants"] = tbio::Json::object();
  for (const LegRunSummary& s : summaries) j["variants"][s.variant] = summary_json(s, scene);
  tbio::write_json_file((fs::path(out_dir) / "summary.json").string(), j);
}

}  // namespace leg
