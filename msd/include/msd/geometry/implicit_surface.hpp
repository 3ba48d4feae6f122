// Closed triangle surfaces from implicit solids (the leg generator's surfaces):
// marching tetrahedra on the Kuhn (Freudenthal) split of a cubic grid, then a
// few passes of tangential relaxation with projection back onto the surface.
//
// A solid is { x : f(x) < 0 } for a field f that behaves like a distance near
// its zero set (|grad f| of order one). Kuhn's split cuts every cube into the six
// tets along its main diagonal, so neighbouring cubes' faces are split the same
// way and the zero set's pieces meet edge to edge: the result is closed and
// manifold wherever no grid node lies exactly on the surface (such values are
// nudged outside). Triangles face outwards: each is oriented towards the tet's
// outside nodes. Relaxation moves every vertex towards the mean of its
// neighbours within the tangent plane (grad f), then back onto f = 0 by Newton
// steps along grad f (central differences), which evens out the slivers
// marching tetrahedra leaves without moving the surface. A pass never turns a
// triangle to face against grad f (at its centroid): the vertices of a
// triangle that would turn keep their positions. Such turned triangles are
// how relaxation folded the surface over itself (a self-intersection, which
// the limb mesher refuses: tbio/surface_check.hpp).
//
// Building blocks for fields (each an exact or approximate signed distance):
// ellipsoids, capsules, elliptic sections, and Quilez's polynomial smooth
// minimum for blended unions.
#pragma once

#include "msd/geometry/triangle_mesh.hpp"

#include <functional>

namespace msd {

using ScalarField = std::function<double(const Vec3&)>;

struct ImplicitMeshOptions {
  Vec3 lo{Vec3::Zero()}, hi{Vec3::Zero()};  ///< the box sampled; f must be > 0 on its boundary (m)
  double cell = 0.0;                        ///< grid cube edge (m)
  int relax_iterations = 4;                 ///< tangential relaxation passes (0: raw marching tetrahedra)
};

/// Meshes { f < 0 } inside the box. Throws msd::Error for an empty or
/// inverted box, a cell that is not positive or would need more than 2e7 grid
/// nodes, a solid that reaches the box's boundary (the surface would be open),
/// or no surface at all.
TriangleMesh mesh_implicit_surface(const ScalarField& f, const ImplicitMeshOptions& options);

/// Central-difference gradient of f at x with step h.
Vec3 field_gradient(const ScalarField& f, const Vec3& x, double h);

/// Polynomial smooth minimum with blend width k >= 0 (k = 0: min):
/// min(a, b) - k s^2 / 4 with s = max(k - |a - b|, 0) / k (Quilez 2013).
double smooth_min(double a, double b, double k);
/// The smooth maximum, -smooth_min(-a, -b, k): a blended intersection.
double smooth_max(double a, double b, double k);

/// Approximate signed distance to the ellipsoid with centre c and semi-axes s
/// (along x, y, z): (|(x - c) / s| - 1) min(s). Exact for a sphere.
double ellipsoid_field(const Vec3& x, const Vec3& c, const Vec3& s);

/// Exact signed distance to the capsule of radius r around segment [a, b].
double capsule_field(const Vec3& x, const Vec3& a, const Vec3& b, double r);

}  // namespace msd
