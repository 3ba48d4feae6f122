// `tissuebench mesh SCENE.yaml --out DIR`: a limb's surfaces (the user's OBJ,
// STL or PLY files) meshed into the physical layer and embedded, written for
// ParaView with a summary. The scene's geometry part:
//
//   name: my_leg
//   leg:                          # files relative to the scene's folder
//     skin: skin.obj              # required
//     upper_bone: femur.stl       # optional, each of the four
//     lower_bone: tibia.ply
//     front_muscle: quadriceps.obj
//     back_muscle: hamstrings.obj
//   mesh:
//     spacing: 0.025              # m, required
//     rotation: [0, 0, 0]         # grid orientation, degrees about x, y, z
//     rule: centre                # centre | inside | overlap
//     pull:                       # optional (thesis 4.6): surface nodes towards the skin
//       - {name: behind_knee, lo: [x, y, z], hi: [x, y, z]}   # box, m
//     pull_min_quality: 0.3       # no tet around a pulled node below this quality
//   tendons:                      # optional
//     - {name: hamstrings_lower, muscle: back_muscle, bone: lower_bone, strands: 6,
//        path: [[0, -0.03, 0.17], [0, -0.012, 0.13]]}   # muscle end first (m)
//
// Output (DIR): mesh.vtu (tets; cell data region; point data bone_point = the
// bone's region or -1), bone_points.vtu, tendons.vtu (one polyline per strand,
// cell data tendon and strand), surfaces/NAME.vtu (each surface at
// rest with its embedding: tet and distance per vertex), summary.json.
#pragma once

#include "msd/mesh/limb_mesher.hpp"
#include "msd/mesh/tendon_paths.hpp"

#include <map>
#include <string>
#include <vector>

namespace leg {

/// A mesh scene read and checked, not yet meshed: the surfaces, the mesher's
/// options and the tendons' routing input (ends validated against their regions).
struct LimbInput {
  std::string name;
  msd::LimbSurfaces surfaces;
  msd::LimbMeshOptions options;
  std::vector<msd::TendonPathSpec> tendons;
};
/// Reads a mesh scene (the format above). Throws msd::Error naming the file and field.
LimbInput read_limb_input(const std::string& scene_file);

/// The limb meshed and its tendons routed.
struct MeshedLimb {
  msd::LimbMesh mesh;
  std::vector<msd::TendonStrands> tendons;
};
MeshedLimb mesh_limb_input(const LimbInput& input);

struct LegMeshSummary {
  long cubes = 0, tets = 0, nodes = 0, bone_points = 0, tendon_strands = 0;
  std::map<std::string, long> tets_by_region;
  long embedded_vertices = 0, embedded_outside = 0;
  double max_outside_distance = 0.0, min_quality = 0.0, seconds = 0.0;
};

/// Reads the scene, meshes and writes DIR. Throws msd::Error naming the scene
/// file and field, or the surface file and fault; nothing is left in DIR that
/// looks complete when it fails (summary.json is written last).
LegMeshSummary mesh_leg_scene(const std::string& scene_file, const std::string& out_dir);

/// The summary as printed by the command.
std::string format_leg_mesh_summary(const LegMeshSummary& s);

}  // namespace leg
