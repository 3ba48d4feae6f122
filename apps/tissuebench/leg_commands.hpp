// The leg's subcommands (mesh, leg, leg-geometry, view, serve): the part of the command
// line that needs only the leg layer, shared by the full program and the
// leg-only build (-DTISSUEBENCH_WITH_FEM=OFF). Exit codes as commands.hpp.
#pragma once

#include "tbio/json.hpp"

#include <CLI/CLI.hpp>

#include <functional>

#include <optional>
#include <string>
#include <vector>

namespace app {

struct MeshArgs {
  std::string scene, out = "mesh";  ///< scene "" = the shipped leg (msd/data/leg/leg.yaml)
};
/// Meshes a limb scene's surfaces (tissuebench mesh SCENE.yaml --out DIR).
int cmd_mesh(const MeshArgs& args);

struct LegArgs {
  std::string scene, out = "leg";  ///< scene "" = msd/data/scenes/hamstrings.yaml
  double duration = 0.0;           ///< > 0: run only this long (s)
  int obj_every = -1;              ///< >= 0: overrides the scene's outputs.obj_every
  bool quiet = false;
  double checkpoint_every = 0.0;   ///< simulated seconds between checkpoints (DIR/leg.checkpoint); 0: none
  std::string resume;              ///< a checkpoint to continue from
  std::vector<std::string> set;    ///< KEY=VALUE fields replacing the scene file's (leg::read_leg_scene)
};
/// Runs a leg scene (tissuebench leg SCENE.yaml --out DIR). Exit 1 when the
/// simulation blew up (its files keep what was written, marked failed).
int cmd_leg(const LegArgs& args);

struct LegGeometryArgs {
  double stature = 1.756, mass = 85.5;  ///< m, kg (the ANSUR II male mean)
  double spacing = 0.0;                ///< the scene's grid spacing (m); 0: the default scaled by stature
  double skin_cell = 0.016;            ///< the skin's marching-tetrahedra cell (m)
  std::string muscles = "thesis";      ///< thesis | anatomical (msd::MuscleShape)
  std::string out;                     ///< "" = msd/data/leg (regenerates the shipped files)
};
/// Writes the parametric leg's surfaces and its mesh scene (tissuebench leg-geometry).
int cmd_leg_geometry(const LegGeometryArgs& args);

struct ViewArgs {
  std::string run_dir, out;  ///< out "" = RUN_DIR/view.html
  int max_frames = 240;
  bool open = false;
};
/// Writes the self-contained viewer page of a leg run (tissuebench view RUN_DIR).
int cmd_view(const ViewArgs& args);

struct ServeArgs {
  std::string scene;              ///< "" = msd/data/scenes/hamstrings.yaml
  int port = 8765;                ///< 0: any free port
  std::string bind = "127.0.0.1";
  double seconds = 0.0;           ///< > 0: stop after this many wall seconds (tests)
  int threads = 0;                ///< > 0: force-evaluation threads (else the scene's)
};
/// Runs a scene live and serves the viewer page and its WebSocket (tissuebench serve).
int cmd_serve(const ServeArgs& args);

/// A leg scene run whole for the suite into out_dir: its manifest entry
/// ({scene, scene_file, dir (the folder's name under the suite's leg/), status,
/// runs: [{variant, dir, status, failure, wall_per_simulated_second}]}).
tbio::Json run_leg_for_suite(const std::string& scene_file, const std::string& out_dir,
                             const std::function<void(double, double)>& progress);

/// The leg's subcommands as registered on a CLI::App, with their arguments.
struct LegCommands {
  MeshArgs mesh;
  LegArgs leg;
  LegGeometryArgs geometry;
  ViewArgs view;
  ServeArgs serve;
  CLI::App* mesh_cmd = nullptr;
  CLI::App* leg_cmd = nullptr;
  CLI::App* geometry_cmd = nullptr;
  CLI::App* view_cmd = nullptr;
  CLI::App* serve_cmd = nullptr;
};
void add_leg_commands(CLI::App& cli, LegCommands& c);

/// Runs the leg subcommand that was given (nothing, exit 0, on a process other
/// than the first under mpirun); nullopt when none of them was.
std::optional<int> run_leg_command(const LegCommands& c, bool root_process);

}  // namespace app
