#include "leg_commands.hpp"

#include "progress.hpp"

#include "leg/limb_input.hpp"
#include "leg/run.hpp"
#include "leg/scene.hpp"

#include "msd/geometry/leg_generator.hpp"

#include <chrono>
#include <cstdio>
#include <utility>

namespace app {

namespace {

constexpr double kDefaultLegSpacing = 0.0245;

}  // namespace

int cmd_mesh(const MeshArgs& args) {
  const std::string scene = args.scene.empty() ? std::string(TISSUEBENCH_DATA_DIR) + "/leg/leg.yaml" : args.scene;
  const leg::LegMeshSummary s = leg::mesh_leg_scene(scene, args.out);
  std::printf("%s", leg::format_leg_mesh_summary(s).c_str());
  std::printf("written: %s/mesh.vtu, bone_points.vtu, surfaces/*.vtu, summary.json\n", args.out.c_str());
  return 0;
}

int cmd_leg(const LegArgs& args) {
  const std::string file =
      args.scene.empty() ? std::string(TISSUEBENCH_DATA_DIR) + "/scenes/hamstrings.yaml" : args.scene;
  leg::LegScene scene = leg::read_leg_scene(file);
  if (args.duration > 0.0) scene.duration = args.duration;
  if (args.obj_every >= 0) scene.obj_every = args.obj_every;
  ProgressLine progress(scene.name + " (leg)", !args.quiet);
  const auto runs = leg::run_leg_scene(scene, args.out, [&](double t, double end) { progress.update(t, end); });
  progress.done();
  int rc = 0;
  for (const auto& r : runs) {
    std::printf("%s", leg::format_leg_summary(r).c_str());
    if (r.status != "complete") {
      std::fprintf(stderr, "error: %s%s%s: %s\n", scene.name.c_str(), r.variant.empty() ? "" : " / ",
                   r.variant.c_str(), r.failure.c_str());
      rc = 3;
    }
  }
  std::printf("written: %s/ (leg.h5, leg.csv, leg.xdmf, skin/frame_*.obj, summary.json)\n", args.out.c_str());
  return rc;
}

int cmd_leg_geometry(const LegGeometryArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  msd::LegParameters p;
  p.stature = args.stature;
  p.mass = args.mass;
  p.skin_cell = args.skin_cell;
  const msd::LegGeometry leg = msd::make_leg(p);
  const double spacing = args.spacing > 0.0 ? args.spacing : kDefaultLegSpacing * p.stature / p.dims.reference_stature;
  const std::string out = args.out.empty() ? std::string(TISSUEBENCH_DATA_DIR) + "/leg" : args.out;
  msd::write_leg(leg, p, spacing, out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("leg: stature %.3f m, mass %.1f kg (girth scale %.3f); hip %.3f m, knee %.3f m, ankle %.3f m, foot %.3f m\n",
              p.stature, p.mass, leg.girth_scale, leg.hip_height, leg.knee_height, leg.ankle_height, leg.foot_length);
  const std::pair<const char*, const msd::TriangleMesh*> surfaces[] = {{"skin", &leg.skin},
                                                                        {"upper_bone", &leg.upper_bone},
                                                                        {"lower_bone", &leg.lower_bone},
                                                                        {"front_muscle", &leg.front_muscle},
                                                                        {"back_muscle", &leg.back_muscle}};
  for (const auto& [name, m] : surfaces)
    std::printf("  %-13s %6d triangles %6d vertices  %7.3f L\n", name, m->num_triangles(), m->num_vertices(),
                1e3 * msd::enclosed_volume(*m));
  std::printf("  tendons: %zu paths; grid spacing in the scene %.4f m; %.2f s\n", leg.tendons.size(), spacing, seconds);
  std::printf("written: %s/{skin,upper_bone,lower_bone,front_muscle,back_muscle}.obj, leg.yaml\n", out.c_str());
  return 0;
}

void add_leg_commands(CLI::App& cli, LegCommands& c) {

  c.mesh_cmd = cli.add_subcommand(
      "mesh", "Mesh a limb from its surfaces (skin, bones, muscles as OBJ/STL/PLY): regions, erosion, bone points, "
              "embedded surfaces; writes VTU files for ParaView and summary.json");
  c.mesh_cmd->add_option("scene", c.mesh.scene,
                       "Scene file (YAML; see leg/include/leg/limb_input.hpp); default: the shipped leg, "
                       "msd/data/leg/leg.yaml")
      ->check(CLI::ExistingFile);
  c.mesh_cmd->add_option("--out", c.mesh.out, "Output folder")->capture_default_str();
  c.leg_cmd = cli.add_subcommand(
      "leg", "Run a leg scene (thesis 6): knee, tendons, muscles, collisions, scripted control; writes leg.h5, "
             "leg.xdmf (ParaView), skin OBJ frames and summary.json");
  c.leg_cmd->add_option("scene", c.leg.scene,
                      "Scene file (YAML; see docs/leg-scenes.md); default: the hamstrings "
                      "scene, msd/data/scenes/hamstrings.yaml")
      ->check(CLI::ExistingFile);
  c.leg_cmd->add_option("--out", c.leg.out, "Output folder")->capture_default_str();
  c.leg_cmd->add_option("--duration", c.leg.duration, "Run only this many simulated seconds");
  c.leg_cmd->add_option("--obj-every", c.leg.obj_every, "Write the skin as OBJ every n-th frame (0: none)");
  c.leg_cmd->add_flag("--quiet", c.leg.quiet, "No progress line");
  c.geometry_cmd = cli.add_subcommand(
      "leg-geometry", "Generate the parametric leg (skin, femur, lower bone, two muscles, tendon paths) from "
                      "anthropometry scaled by stature and mass: OBJ surfaces and the mesh scene leg.yaml");
  c.geometry_cmd->add_option("--stature", c.geometry.stature, "Stature (m), 1.2-2.3")->capture_default_str();
  c.geometry_cmd->add_option("--mass", c.geometry.mass, "Body mass (kg), 30-200")->capture_default_str();
  c.geometry_cmd->add_option("--spacing", c.geometry.spacing,
                               "Grid spacing written into leg.yaml (m); default 0.0245 m scaled by stature");
  c.geometry_cmd->add_option("--skin-cell", c.geometry.skin_cell,
                               "Skin resolution: marching-tetrahedra cell (m); inner surfaces use half")
      ->capture_default_str();
  c.geometry_cmd->add_option("--out", c.geometry.out, "Output folder; default: msd/data/leg (the shipped files)");
}

std::optional<int> run_leg_command(const LegCommands& c, bool root_process) {
  if (!*c.mesh_cmd && !*c.leg_cmd && !*c.geometry_cmd) return std::nullopt;
  if (!root_process) return 0;
  if (*c.mesh_cmd) return cmd_mesh(c.mesh);
  if (*c.leg_cmd) return cmd_leg(c.leg);
  return cmd_leg_geometry(c.geometry);
}

}  // namespace app
