// Embedded surfaces: the visible layer that follows the physical one (thesis
// 5.5, eq. 5.6). Every vertex P of a geometric surface is stored with a tet
// ABCD of the physical mesh and its coordinates in the frame of the tet's edges,
//
//     P = A + u (B - A) + v (C - A) + w (D - A),      (u, v, w) = M^-1 (P - A),
//
// where the columns of M are B - A, C - A, D - A at rest. At any later time the
// same (tet, u, v, w) with the deformed A..D gives the vertex: the space inside
// each tet deforms linearly, with C0 continuity between neighbours. Because the
// map is affine in the node positions, any affine motion of the tet mesh moves
// every embedded vertex by exactly that motion.
//
// The thesis found each vertex's tet "by iterating through the list of
// tetrahedrons"; here a uniform grid of the tets' bounding boxes (TetLocator)
// answers each query from the few tets near the point. A vertex that lies in no
// tet (the cubic physical surface cuts inside the smooth skin in places) takes
// its nearest tet, with coordinates that extrapolate that tet's linear field;
// such vertices are counted and their distances reported.
#pragma once

#include "msd/mesh/tet_mesh.hpp"

#include <utility>
#include <vector>

namespace msd {

/// One embedded vertex: its tet and its edge-frame coordinates (eq. 5.6).
/// `distance` is 0 when the vertex lies in the tet, else its distance (m) to
/// the tet at rest (the coordinates then extrapolate).
struct EmbeddedVertex {
  int tet = -1;
  double u = 0.0, v = 0.0, w = 0.0;
  double distance = 0.0;
};

/// The embedding of one vertex set (3 x V at rest) in a tet mesh.
struct Embedding {
  std::vector<EmbeddedVertex> vertices;
  int outside = 0;                   ///< vertices in no tet (nearest tet, extrapolated)
  double max_outside_distance = 0.0; ///< m; 0 when none is outside
};

/// Uniform-grid search structure over the tets of a mesh at rest: each tet is
/// listed in every cell its bounding box overlaps; cells are about the size of
/// a tet. Holds a reference to nothing: it copies what it needs.
class TetLocator {
 public:
  /// `nodes` 3 x N, `tets` positively oriented. Throws msd::Error for an empty
  /// mesh or non-finite coordinates.
  TetLocator(const Points& nodes, const std::vector<Tet>& tets);

  /// The tet containing p: all four barycentric coordinates >= -tolerance;
  /// among several (p on a shared face), the one whose smallest coordinate is
  /// largest. -1 when p lies in no tet.
  int containing(const Vec3& p, double tolerance = 1e-10) const;

  /// The tet nearest to p and the distance (0 when p lies in it). Rings of
  /// cells are searched outward until no unvisited tet can be nearer.
  std::pair<int, double> nearest(const Vec3& p) const;

  /// Edge-frame coordinates (u, v, w) of p in tet e (eq. 5.6), at rest.
  Vec3 local_coordinates(int e, const Vec3& p) const;

  double cell_size() const { return h_; }
  long cells() const { return static_cast<long>(n_[0]) * n_[1] * n_[2]; }

 private:
  double distance_to_tet(int e, const Vec3& p) const;
  long cell_index(const Vec3& p, int c[3]) const;

  Points nodes_;
  std::vector<Tet> tets_;
  std::vector<Mat3> inverse_;  ///< M^-1 per tet
  Vec3 lo_;
  double h_ = 1.0;
  int n_[3] = {1, 1, 1};
  std::vector<int> start_, items_;  ///< cell c lists items_[start_[c] .. start_[c + 1])
  mutable std::vector<unsigned> stamp_;
  mutable unsigned epoch_ = 0;
};

/// Embeds every column of `vertices` (3 x V, rest positions, m) in `mesh`.
/// Throws msd::Error for a non-finite vertex (naming its index).
Embedding embed_vertices(const TetMesh& mesh, const Points& vertices);

/// Positions of the embedded vertices (3 x V) for node positions `x` (3 x N)
/// of the same mesh: eq. 5.6 with the current A..D.
void embedded_positions(const Points& x, const std::vector<Tet>& tets, const Embedding& embedding, Points& out);

}  // namespace msd
