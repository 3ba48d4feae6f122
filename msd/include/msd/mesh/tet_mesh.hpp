// Tetrahedral meshes: the physical layer of the thesis (4.5). Nodes, tets with a
// region label each, and the geometric measures every other module uses.
#pragma once

#include "msd/core/types.hpp"

#include <string>
#include <vector>

namespace msd {

/// Region labels used across the project (thesis 4.5: passive tissue, front
/// muscle, back muscle, upper bone, lower bone). A sample has one region.
enum Region : int {
  kPassiveTissue = 0,
  kFrontMuscle = 1,
  kBackMuscle = 2,
  kUpperBone = 3,
  kLowerBone = 4,
};

/// `nodes` is 3 x N (rest positions, m). `tets[e]` lists four node indices with
/// positive signed volume (see tet_signed_volume). `region[e]` labels tet e.
struct TetMesh {
  Points nodes;
  std::vector<Tet> tets;
  std::vector<int> region;

  int num_nodes() const { return static_cast<int>(nodes.cols()); }
  int num_tets() const { return static_cast<int>(tets.size()); }
};

/// Signed volume (b - a) . ((c - a) x (d - a)) / 6: positive for a positively
/// oriented tet.
inline double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

/// Signed volume of tet e at positions x (3 x N).
double tet_signed_volume(const Points& x, const Tet& t);

/// Sum of signed tet volumes at positions x.
double total_volume(const Points& x, const std::vector<Tet>& tets);

/// Number of tets with signed volume <= 0 at positions x.
int count_inverted(const Points& x, const std::vector<Tet>& tets);

/// Mean-ratio quality 12 (3|V|)^(2/3) / sum of squared edge lengths: 1 for a
/// regular tet, 0 for a flat one (Liu & Joe 1994).
double tet_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Smallest tet_quality over the mesh (0 for an empty mesh).
double min_quality(const TetMesh& mesh);

/// Triangles that belong to exactly one tet, oriented with outward normals.
std::vector<Tri> boundary_faces(const std::vector<Tet>& tets);

/// How many tets share each distinct triangle: counts[k] = number of triangles
/// shared by exactly k tets (index 0 unused).
std::vector<int> face_sharing_histogram(const std::vector<Tet>& tets);

/// Throws msd::Error naming the first tet with an invalid node index, a repeated
/// node, or a non-positive volume, and a region vector of the wrong length.
void check_tet_mesh(const TetMesh& mesh, const std::string& name);

/// The six edges of a tet as local vertex pairs, in the order used by every
/// per-edge array in the library: (0,1) (0,2) (0,3) (1,2) (1,3) (2,3).
inline constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

}  // namespace msd
