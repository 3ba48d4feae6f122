// Skin against skin (thesis 5.6: "prevent the parts of the skin surface above
// and below the back of the knee joint from interpenetrating when the knee is
// bent"): only a named collision region is tested, split into two sides by a
// plane; each side's surface nodes are tested against the other side's tets.
//
// Detection: the thesis' inside-outside test of a node against the other
// side's solid, here as "inside one of its tets" (all four barycentric
// coordinates >= 0) and behind its closest boundary face (a node resting on
// the surface touches, it does not penetrate), the tets found through a bounding-volume hierarchy of
// their current boxes (AabbTree), rebuilt every call because the tets move.
// Response (5.6.2): the node moves to the closest boundary face of the other
// side along that face's outward normal, x += ((p0 - x) . n) n, and its
// velocity is set to zero. The report counts contacts, the deepest
// penetration, and the contact area (a third of the area of the faces around
// each contacting node).
#pragma once

#include "msd/mesh/tet_mesh.hpp"

#include <limits>
#include <string>
#include <vector>

namespace msd {

/// A bounding-volume hierarchy of axis-aligned boxes (median split along the
/// longest axis, leaves of up to 4 boxes).
class AabbTree {
 public:
  AabbTree() = default;
  /// lo, hi: 3 x B, box b = [lo.col(b), hi.col(b)].
  AabbTree(const Points& lo, const Points& hi);
  /// Rebuilds over new boxes, reusing the storage (no allocation once it has
  /// held as many boxes).
  void rebuild(const Points& lo, const Points& hi);
  /// Indices of the boxes containing p (closed boxes), in no particular order.
  void query(const Vec3& p, std::vector<int>& out) const;

 private:
  struct Node {
    Vec3 lo, hi;
    int left = -1, right = -1;  ///< children, or -1 at a leaf
    int begin = 0, end = 0;     ///< leaf: range in order_
  };
  int build(int begin, int end);
  std::vector<Node> nodes_;
  std::vector<int> order_;
  Points lo_, hi_, centre_;
};

struct SelfContactRegion {
  std::string name;
  std::vector<int> nodes[2];  ///< surface nodes of each side
  std::vector<int> tets[2];   ///< tets of each side (mesh indices)
  std::vector<Tri> faces[2];  ///< boundary faces of each side, outward
  /// A node found deeper than this (m) is not moved: so deep a "contact" is a
  /// node caught inside a neighbouring tet across the split, not skin that
  /// came through skin in one step (infinity: every contact is resolved).
  double max_correction = std::numeric_limits<double>::infinity();
  /// Per side, per surface node: the nodes sharing a tet with it. A node is
  /// not tested against tets touching these (at a fold - the crease's apex -
  /// a node lies "inside" its neighbours' tets without any skin having
  /// passed through skin, and putting it on a face next to it flattens them).
  std::vector<std::vector<int>> ring[2];
};

/// The region: boundary faces of the mesh (at rest) whose centroid lies in
/// the box [lo, hi], and tets whose centroid does, each given to side 0 where
/// (centroid - split_point) . split_normal >= 0, else side 1. `surface`, when
/// given, replaces the mesh's boundary faces: the faces that count as skin
/// (a mesh with holes - the leg's joint space - has boundary faces inside it
/// that no skin can touch). Throws msd::Error naming the region if either
/// side has no face.
SelfContactRegion make_self_contact_region(const TetMesh& mesh, const std::string& name, const Vec3& lo,
                                           const Vec3& hi, const Vec3& split_point, const Vec3& split_normal,
                                           const std::vector<Tri>& surface = {});

struct SelfContactReport {
  int contacts = 0;
  int too_deep = 0;        ///< found inside but deeper than max_correction: left alone
  double max_depth = 0.0;  ///< m
  double area = 0.0;       ///< m^2
};

/// Detects and resolves the region's contacts at positions x (velocities v),
/// leaving alone nodes with held[node] != 0 (held by a bone; an empty `held`:
/// every node may move).
SelfContactReport resolve_self_contact(const SelfContactRegion& region, const std::vector<Tet>& tets, Points& x,
                                       Points& v, const std::vector<char>& held = {});

/// Buffers of resolve_self_contact, reused between calls.
struct SelfContactWorkspace {
  Points lo[2], hi[2];  ///< per side: the other side's tets' boxes
  AabbTree tree[2];
  std::vector<int> candidates;
};

/// The same with its buffers in `w` (no allocation once they are sized).
SelfContactReport resolve_self_contact(const SelfContactRegion& region, const std::vector<Tet>& tets, Points& x,
                                       Points& v, const std::vector<char>& held, SelfContactWorkspace& w);

}  // namespace msd
