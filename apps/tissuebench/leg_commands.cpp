#include "leg_commands.hpp"

#include "cli_checks.hpp"
#include "progress.hpp"

#include "leg/limb_input.hpp"
#include "leg/run.hpp"
#include "leg/scene.hpp"
#include "leg/viewer.hpp"
#include "tbio/series_tools.hpp"

#include "msd/geometry/leg_generator.hpp"
#include "msd/io/atomic_file.hpp"
#include "msd/io/interrupt.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <utility>

namespace app {

namespace {

constexpr double kDefaultLegSpacing = 0.0245;

}  // namespace

int cmd_mesh(const MeshArgs& args) {
  msd::install_interrupt_handlers();  // SIGINT/SIGTERM: the VTU being written is removed, exit 128+N
  const std::string scene = args.scene.empty() ? std::string(TISSUEBENCH_DATA_DIR) + "/leg/leg.yaml" : args.scene;
  const leg::LegMeshSummary s = leg::mesh_leg_scene(scene, args.out);
  std::printf("%s", leg::format_leg_mesh_summary(s).c_str());
  std::printf("written: %s/mesh.vtu, bone_points.vtu, surfaces/*.vtu, summary.json\n", args.out.c_str());
  return 0;
}

int cmd_leg(const LegArgs& args) {
  const std::string file =
      args.scene.empty() ? std::string(TISSUEBENCH_DATA_DIR) + "/scenes/hamstrings.yaml" : args.scene;
  leg::LegScene scene = leg::read_leg_scene(file, args.set);
  if (args.duration > 0.0) {
    if (args.duration < 10.0 * scene.dt)
      throw msd::Error("--duration: " + tbio::json_number(args.duration) + " s is fewer than ten steps of the scene's dt (" +
                       tbio::json_number(scene.dt) + " s, " + file + ")");
    scene.duration = args.duration;
  }
  if (args.obj_every >= 0) scene.obj_every = args.obj_every;
  msd::install_interrupt_handlers();  // SIGINT/SIGTERM: stop at the next step, leg.h5 marked failed
  ProgressLine progress(scene.name + " (leg)", !args.quiet);
  leg::LegCheckpointing cp;
  cp.every = args.checkpoint_every;
  cp.resume = args.resume;
  const auto runs =
      leg::run_leg_scene(scene, args.out, [&](double t, double end) { progress.update(t, end); }, cp);
  progress.done();
  int rc = 0;
  for (const auto& r : runs) {
    std::printf("%s", leg::format_leg_summary(r).c_str());
    if (r.status != "complete") {
      std::fprintf(stderr, "error: %s%s%s: %s\n", scene.name.c_str(), r.variant.empty() ? "" : " / ",
                   r.variant.c_str(), r.failure.c_str());
      if (!r.kept) std::fprintf(stderr, "  no leg.h5 could be written (nothing was left in its place)\n");
      if (rc == 0) rc = 1;
      if (r.interrupted) rc = msd::interrupted_exit_code(r.interrupted);
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
  p.muscles = args.muscles == "anatomical" ? msd::MuscleShape::Anatomical : msd::MuscleShape::Thesis;
  if (p.muscles == msd::MuscleShape::Anatomical && args.out.empty()) {
    std::fprintf(stderr, "tissuebench: error: --muscles anatomical needs --out: the default folder, msd/data/leg, "
                         "holds the shipped leg with the thesis' muscles\n");
    return 2;
  }
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
  std::printf("  muscles: %s; the published quadriceps %.0f cm3 and hamstrings %.0f cm3 for this body (Handsfield et "
              "al. 2014), PCSA %.0f and %.0f cm2 (Ward et al. 2009 fibre lengths)\n",
              args.muscles.c_str(), 1e6 * leg.front_target_volume, 1e6 * leg.back_target_volume, 1e4 * leg.front_pcsa,
              1e4 * leg.back_pcsa);
  std::printf("  tendons: %zu paths; grid spacing in the scene %.4f m; %.2f s\n", leg.tendons.size(), spacing, seconds);
  std::printf("written: %s/{skin,upper_bone,lower_bone,front_muscle,back_muscle}.obj, leg.yaml\n", out.c_str());
  return 0;
}

tbio::Json run_leg_for_suite(const std::string& scene_file, const std::string& out_dir,
                             const std::function<void(double, double)>& progress) {
  namespace fs = std::filesystem;
  const leg::LegScene scene = leg::read_leg_scene(scene_file);
  const auto runs = leg::run_leg_scene(scene, out_dir, progress);
  const std::string dir = "leg/" + fs::path(out_dir).filename().string();
  tbio::Json entry;
  entry["scene"] = scene.name;
  entry["scene_file"] = scene_file;
  entry["dir"] = dir;
  entry["status"] = "complete";
  entry["runs"] = tbio::Json::array();
  for (const auto& r : runs) {
    if (r.status != "complete") entry["status"] = "failed";
    entry["runs"].push_back({{"variant", r.variant},
                             {"dir", r.variant.empty() ? dir : dir + "/" + r.variant},
                             {"status", r.status},
                             {"failure", r.failure},
                             {"wall_per_simulated_second", r.wall_per_simulated()}});
  }
  return entry;
}

int cmd_view(const ViewArgs& args) {
  namespace fs = std::filesystem;
  const std::string out = args.out.empty() ? (fs::path(args.run_dir) / "view.html").string() : args.out;
  leg::ViewOptions options;
  options.max_frames = args.max_frames;
  tbio::Json config;
  config["mode"] = "run";
  config["run"] = leg::view_run_data(args.run_dir, options);
  const std::string page = leg::viewer_page(config);
  msd::write_file_atomically(out, [&](std::ostream& o) { o << page; });
  const auto& run = config["run"];
  std::printf("view: %s (%s, %zu frames, %.1f MB)\n", out.c_str(), run["status"].get<std::string>().c_str(),
              run["frame_times"].size(), static_cast<double>(page.size()) / 1e6);
  if (run["status"] != "complete")
    std::printf("  the run is %s: the page shows what was written%s%s\n", run["status"].get<std::string>().c_str(),
                run["failure"].get<std::string>().empty() ? "" : " and where it failed: ",
                run["failure"].get<std::string>().c_str());
  if (args.open) {
    const std::string command = "xdg-open '" + out + "' >/dev/null 2>&1 &";
    if (std::system(command.c_str()) != 0) std::printf("  could not start xdg-open; open the file in a browser\n");
  }
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
  c.mesh_cmd->footer("Files are written whole (a temporary, then a rename); a second mesh run into DIR is refused "
                     "(exit 2) while the first holds DIR.lock; SIGINT/SIGTERM remove the file being written and "
                     "exit 128+N (130, 143).");
  c.leg_cmd = cli.add_subcommand(
      "leg", "Run a leg scene (thesis 6): knee, tendons, muscles, collisions, scripted control; writes leg.h5, "
             "leg.xdmf (ParaView), skin OBJ frames and summary.json");
  c.leg_cmd->add_option("scene", c.leg.scene,
                      "Scene file (YAML; see docs/leg-scenes.md); default: the hamstrings "
                      "scene, msd/data/scenes/hamstrings.yaml")
      ->check(CLI::ExistingFile);
  c.leg_cmd->add_option("--out", c.leg.out, "Output folder")->capture_default_str();
  c.leg_cmd->add_option("--duration", c.leg.duration, "Run only this many simulated seconds")
      ->check(app::finite_positive("simulated seconds"));
  c.leg_cmd->add_option("--obj-every", c.leg.obj_every, "Write the skin as OBJ every n-th frame (0: none)")
      ->check(app::integer_in(0, 1000000000, "frames"));
  c.leg_cmd->add_flag("--quiet", c.leg.quiet, "No progress line");
  c.leg_cmd->add_option("--set", c.leg.set,
                        "KEY=VALUE: replace (or add) one field of the scene file for this run, KEY a dotted field "
                        "(--set knee.damping=0.14 --set materials.passive.youngs_modulus=11960); checked as if the "
                        "file said so, and listed in summary.json's scene_overrides")
      ->expected(1)
      ->allow_extra_args(false)  // one KEY=VALUE per --set: `--set a=1 scene.yaml` keeps the scene
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c.leg_cmd->add_option("--checkpoint-every", c.leg.checkpoint_every,
                        "Write a checkpoint (DIR/leg.checkpoint) every this many simulated seconds; removed when "
                        "the run completes (DIR/VARIANT/leg.checkpoint for each variant of a scene with variants)")
      ->check(app::finite_positive("simulated seconds"));
  c.leg_cmd->add_option("--resume", c.leg.resume,
                        "Continue from a checkpoint of the same scene and options (results bit-identical to an "
                        "uninterrupted run; with variants, those before the checkpoint's are run again)")
      ->check(CLI::ExistingFile);
  c.leg_cmd->footer(
      "Files: leg.h5 and leg.csv are written under temporary names and renamed into place when the run ends "
      "(complete or failed); a second run into DIR is refused (exit 2) while the first holds DIR.lock. "
      "SIGINT/SIGTERM stop the run at its next step: leg.h5 is kept marked failed (\"interrupted by signal N at "
      "t = ...\"), exit 128+N (130, 143).");
  c.geometry_cmd = cli.add_subcommand(
      "leg-geometry", "Generate the parametric leg (skin, femur, lower bone, two muscles, tendon paths) from "
                      "anthropometry scaled by stature and mass: OBJ surfaces and the mesh scene leg.yaml");
  c.geometry_cmd->add_option("--stature", c.geometry.stature, "Stature (m), 1.2-2.3")
      ->check(app::finite_in(1.2, 2.3, "m"))
      ->capture_default_str();
  c.geometry_cmd->add_option("--mass", c.geometry.mass, "Body mass (kg), 30-200")
      ->check(app::finite_in(30.0, 200.0, "kg"))
      ->capture_default_str();
  c.geometry_cmd->add_option("--spacing", c.geometry.spacing,
                               "Grid spacing written into leg.yaml (m); default 0.0245 m scaled by stature")
      ->check(app::finite_positive("m"));
  c.geometry_cmd->add_option("--skin-cell", c.geometry.skin_cell,
                               "Skin resolution: marching-tetrahedra cell (m); inner surfaces use half")
      ->check(app::finite_positive("m"))
      ->capture_default_str();
  c.geometry_cmd
      ->add_option("--muscles", c.geometry.muscles,
                   "Muscle shapes: thesis (the thesis' spindles) or anatomical (the thigh's muscle compartment "
                   "split into quadriceps and hamstrings sized to Handsfield et al. 2014's volumes for this "
                   "stature and mass)")
      ->check(CLI::IsMember({"thesis", "anatomical"}))
      ->capture_default_str();
  c.geometry_cmd->add_option("--out", c.geometry.out, "Output folder; default: msd/data/leg (the shipped files)");
  c.view_cmd = cli.add_subcommand(
      "view", "Write a self-contained web page that plays a leg run in 3D (skin and bones; orbit, zoom, play, "
              "scrub, speed) with its time series plotted in sync; opens from a local file, no server");
  c.view_cmd->add_option("run_dir", c.view.run_dir, "A leg run's folder (tissuebench leg ... --out RUN_DIR)")
      ->required();
  c.view_cmd->add_option("--out", c.view.out, "The page (HTML); default: RUN_DIR/view.html");
  c.view_cmd->add_option("--max-frames", c.view.max_frames, "At most this many frames (every k-th and the last)")
      ->check(app::integer_in(2, 100000, "frames"))
      ->capture_default_str();
  c.view_cmd->add_flag("--open", c.view.open, "Open the page with xdg-open");
  c.serve_cmd = cli.add_subcommand(
      "serve", "Run a leg scene live in the browser: serves the viewer page on localhost and streams frames over a "
               "WebSocket; sliders set the muscles' activations, knobs the knee torque and the obstacles, a button "
               "resets");
  c.serve_cmd->add_option("scene", c.serve.scene,
                          "Scene file (YAML; see docs/leg-scenes.md); default: msd/data/scenes/hamstrings.yaml")
      ->check(CLI::ExistingFile);
  c.serve_cmd->add_option("--port", c.serve.port, "TCP port (0: any free port)")
      ->check(app::integer_in(0, 65535, "a TCP port"))
      ->capture_default_str();
  c.serve_cmd->add_option("--bind", c.serve.bind, "Address to listen on (only this machine unless you say otherwise)")
      ->capture_default_str();
  c.serve_cmd->add_option("--seconds", c.serve.seconds, "Stop after this many wall seconds (0: until Ctrl-C)")
      ->check(app::finite_in(0.0, 1e9, "wall seconds"));
  c.serve_cmd->add_option("--threads", c.serve.threads, "Force-evaluation threads (default: the scene's)")
      ->check(app::integer_in(1, 256, "threads"));
}

std::optional<int> run_leg_command(const LegCommands& c, bool root_process) {
  if (!*c.mesh_cmd && !*c.leg_cmd && !*c.geometry_cmd && !*c.view_cmd && !*c.serve_cmd) return std::nullopt;
  if (!root_process) return 0;
  if (*c.mesh_cmd) return cmd_mesh(c.mesh);
  if (*c.leg_cmd) return cmd_leg(c.leg);
  if (*c.view_cmd) return cmd_view(c.view);
  if (*c.serve_cmd) return cmd_serve(c.serve);
  return cmd_leg_geometry(c.geometry);
}

}  // namespace app
