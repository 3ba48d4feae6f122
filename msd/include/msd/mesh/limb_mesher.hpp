// The physical and visible layers of a limb from its surfaces (thesis 4.5, 5.5):
// validate the skin and the internal surfaces (closed, manifold, oriented,
// nested), lay a cubic grid of chosen spacing and orientation, label the cubes
// by region with erosion and bone points (regions.hpp), split them into five
// tets each, and embed every vertex of every surface in the tets.
#pragma once

#include "msd/geometry/triangle_mesh.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "msd/mesh/embedding.hpp"
#include "msd/mesh/regions.hpp"

#include <map>
#include <optional>
#include <string>

namespace msd {

/// Human-readable region names used in messages and outputs:
/// passive_tissue, front_muscle, back_muscle, upper_bone, lower_bone.
std::string region_name(int region);

/// The limb's surfaces: the skin and any of the four internal regions.
struct LimbSurfaces {
  TriangleMesh skin;
  std::map<int, TriangleMesh> inner;  ///< region -> closed surface
  std::map<int, std::string> source;  ///< region (kPassiveTissue = skin) -> file, for messages
};

/// An area where surface nodes are pulled towards the skin (thesis 4.6, "behind
/// the knee"): an axis-aligned box in the surfaces' frame.
struct PullArea {
  std::string name;
  Vec3 lo{Vec3::Zero()}, hi{Vec3::Zero()};
};

struct LimbMeshOptions {
  double spacing = 0.0;                    ///< cube edge h, m
  Vec3 rotation_deg{Vec3::Zero()};         ///< grid orientation: rotations about x, then y, then z (degrees)
  std::optional<Vec3> origin;              ///< grid origin in the rotated frame (default: the skin's lowest corner)
  CubeRule rule = CubeRule::Centre;
  long max_cubes = kDefaultMaxCubes;
  /// Memory estimated before allocating (msd/core/memory.hpp): the grid, then
  /// the solid cubes at solid_bytes_per_cube (meshing's, or a run's).
  MemoryLimit memory;
  double solid_bytes_per_cube = kMeshBytesPerCube;
  /// Thesis 4.6: boundary nodes of the tet mesh inside these areas move towards
  /// the closest point of the skin, as far as every tet around them keeps a
  /// quality of at least pull_min_quality (the move is halved up to 6 times,
  /// then skipped). Before the surfaces are embedded.
  std::vector<PullArea> pull_areas;
  double pull_min_quality = 0.3;
};

/// What the pull did: nodes moved, and their mean distance to the skin before
/// and after (m).
struct PullReport {
  long candidates = 0, moved = 0;
  double gap_before = 0.0, gap_after = 0.0;
};

struct LimbMesh {
  TetMesh mesh;                              ///< nodes in the surfaces' frame, tets labelled by region
  std::vector<long> tet_cube;                ///< per tet of `mesh`: its grid cube (GridMeshInfo::tet_cube_id)
  CubicGrid grid;                            ///< in the rotated frame
  Mat3 rotation{Mat3::Identity()};           ///< rotated frame = rotation * surfaces' frame
  RegionLabelling labels;
  std::vector<std::pair<int, int>> bone_points;  ///< (mesh node, bone region)
  long cubes = 0;
  std::map<int, long> tets_by_region;
  std::map<int, Embedding> embedded;         ///< region (kPassiveTissue = skin) -> its surface's vertices
  PullReport pull;
};

/// Throws msd::Error naming the region (and its file) and the fault: a surface
/// that is not closed, manifold and outward-oriented; an internal surface with
/// a vertex outside the skin; two muscles or two bones that overlap (one's
/// vertex inside the other). A bone overlapping a muscle is allowed: erosion
/// resolves it (thesis figure 4.7).
void validate_limb(const LimbSurfaces& surfaces);

/// Validates, meshes and embeds. Throws msd::Error for bad options or when no
/// cube lies in the skin.
LimbMesh mesh_limb(const LimbSurfaces& surfaces, const LimbMeshOptions& options);

}  // namespace msd
