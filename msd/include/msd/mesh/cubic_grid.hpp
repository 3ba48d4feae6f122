// The cubic-grid mesher (thesis 4.5, 4.5.1): lay a grid of cubes of edge h over
// a closed surface, decide which cubes belong to the solid, and split every cube
// into five tetrahedra (a central regular tet and four corner tets) with the
// split mirrored on alternate cubes so neighbouring faces conform.
#pragma once

#include "msd/core/memory.hpp"

#include "msd/geometry/inside_test.hpp"
#include "msd/geometry/triangle_mesh.hpp"
#include "msd/mesh/tet_mesh.hpp"

#include <optional>
#include <string>
#include <vector>

namespace msd {

/// Which cubes belong to a solid:
///  - Centre: the cube's centre is inside (volume-unbiased; the default);
///  - WhollyInside: the centre and all eight corners are inside (for convex
///    solids, the cube lies inside; reproduces the thesis' 120-tet cylinder);
///  - Overlap: the open cube meets the solid, i.e. a corner or the centre is
///    inside or a surface triangle passes through the cube ("remove the cubes
///    that lie wholly outside", thesis 4.5).
/// "Inside" is the closed-set ray-parity test of inside_test.hpp with a surface
/// tolerance of 1e-6 h.
enum class CubeRule { Centre, WhollyInside, Overlap };

/// Parses "centre" / "center", "inside", "overlap"; throws msd::Error otherwise.
CubeRule parse_cube_rule(const std::string& text);
std::string to_string(CubeRule rule);

/// A regular grid of nx x ny x nz cubes of edge `spacing` whose lowest corner
/// is `origin`. Grid node (i, j, k) sits at origin + h (i, j, k), 0 <= i <= nx.
struct CubicGrid {
  Vec3 origin{Vec3::Zero()};
  double spacing = 0.0;
  int nx = 0, ny = 0, nz = 0;

  long num_cubes() const { return static_cast<long>(nx) * ny * nz; }
  long cube_id(int i, int j, int k) const { return i + static_cast<long>(nx) * (j + static_cast<long>(ny) * k); }
  long node_id(int i, int j, int k) const {
    return i + static_cast<long>(nx + 1) * (j + static_cast<long>(ny + 1) * k);
  }
  Vec3 node_position(int i, int j, int k) const { return origin + spacing * Vec3(i, j, k); }
};

/// Default limit on the number of cubes in a grid's bounding box (memory guard).
inline constexpr long kDefaultMaxCubes = 20'000'000;

/// The grid covering `box` with spacing h. The origin defaults to box.lo.
/// Throws msd::Error when h <= 0 or not finite, when the origin lies above
/// box.lo, or when the grid would hold more than max_cubes cubes.
CubicGrid make_grid(const Aabb& box, double h, std::optional<Vec3> origin = std::nullopt,
                    long max_cubes = kDefaultMaxCubes);

/// For every cube of `grid` (indexed by cube_id), whether it belongs to the solid
/// bounded by `surface` under `rule`.
std::vector<char> classify_cubes(const CubicGrid& grid, const InsideTest& surface, CubeRule rule);

/// Bookkeeping from the split: the grid node of each mesh node and the cube of
/// each tet.
struct GridMeshInfo {
  std::vector<long> node_grid_id;
  std::vector<long> tet_cube_id;
};

/// Splits the cubes with cube_region[cube_id] >= 0 into five tets each, labelled
/// with that region. Tets are positively oriented; nodes are numbered in grid
/// order and only nodes used by some tet are kept.
TetMesh split_cubes(const CubicGrid& grid, const std::vector<int>& cube_region,
                    GridMeshInfo* info = nullptr);

/// Everything needed to mesh one closed surface as one region.
struct SampleMeshOptions {
  double spacing = 0.0;
  CubeRule rule = CubeRule::Centre;
  std::optional<Vec3> origin;
  long max_cubes = kDefaultMaxCubes;
  int region = kPassiveTissue;
  /// Memory estimated before allocating (msd/core/memory.hpp): the grid, then
  /// the solid cubes at solid_bytes_per_cube (a run's, or meshing's).
  MemoryLimit memory;
  double solid_bytes_per_cube = kRunBytesPerCube;
};

struct SampleMesh {
  TetMesh mesh;
  CubicGrid grid;
  GridMeshInfo info;
  long cubes = 0;
};

/// Validates the surface, lays the grid, classifies and splits. Throws
/// msd::Error (naming `name`) for a bad surface or options, or when no cube is
/// selected.
SampleMesh mesh_closed_surface(const TriangleMesh& surface, const SampleMeshOptions& options,
                               const std::string& name);

}  // namespace msd
