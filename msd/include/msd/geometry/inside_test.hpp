// Robust inside/outside test for closed triangle surfaces by ray parity
// (thesis 4.5 and 5.6.1: "count the intersections with a ray to infinity; take
// care with hits on vertices and edges").
//
// The rule. Rays run in the +x direction. A triangle is crossed when the ray's
// (y, z) lies inside the triangle's projection onto the yz plane. Hits exactly on
// a projected edge or vertex are decided by simulation of simplicity: the query
// is treated as if it were moved to (y + e, z + e^2) for an infinitesimal e > 0.
// Each edge function is evaluated from its lower-numbered vertex, so the two
// triangles sharing an edge get exactly opposite values and exactly one of them
// claims the ray. Triangles whose projection has zero area are parallel to the
// ray and never crossed. On a closed, consistently oriented surface the number of
// crossings beyond the point is therefore well defined, and the point is inside
// when it is odd. A point within `surface_tolerance` of the surface counts as
// inside (the solid is a closed set).
#pragma once

#include "msd/geometry/triangle_mesh.hpp"

#include <vector>

namespace msd {

/// Answers inside/outside queries for one closed surface. Triangles are binned
/// on a uniform grid in the yz plane, so a query inspects only the triangles
/// whose projection can contain it. Holds its own copy of the surface.
class InsideTest {
 public:
  explicit InsideTest(const TriangleMesh& surface);

  /// Sorted x coordinates where the +x ray through (y, z) crosses the surface.
  std::vector<double> crossings(double y, double z) const;

  /// Parity test for one point; points closer than `surface_tolerance` to the
  /// surface count as inside.
  bool inside(const Vec3& p, double surface_tolerance = 0.0) const;

  /// Classifies many points on the line (y, z) at once: one ray, then parity
  /// by position. `xs` need not be sorted.
  std::vector<char> inside_on_line(double y, double z,
                                   const std::vector<double>& xs) const;

  /// Unsigned distance from `p` to the nearest triangle (brute force over the
  /// triangles whose bounding box is within `max_distance`; returns
  /// max_distance when none is closer).
  double distance(const Vec3& p, double max_distance) const;

  const TriangleMesh& surface() const { return surface_; }

 private:
  const std::vector<int>& cell(double y, double z) const;

  TriangleMesh surface_;
  double y0_ = 0, z0_ = 0, cell_size_ = 1;
  int ny_ = 1, nz_ = 1;
  std::vector<std::vector<int>> bins_;
  std::vector<int> empty_;
};

/// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision
/// Detection, 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                               const Vec3& c);

/// Whether the closed axis-aligned box [lo, hi] and triangle (a, b, c) overlap:
/// separating-axis test with the 13 axes of Akenine-Moeller (2001).
bool triangle_box_overlap(const Vec3& lo, const Vec3& hi, const Vec3& a,
                          const Vec3& b, const Vec3& c);

}  // namespace msd
