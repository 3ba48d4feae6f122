// Closed triangle surfaces: the geometric layer of the thesis (4.5) and the input
// of the cubic-grid mesher. Built-in shapes, OBJ input/output, and validation.
#pragma once

#include "msd/core/types.hpp"

#include <string>
#include <vector>

namespace msd {

/// A triangle surface. `vertices` is 3 x V; each triangle lists three vertex
/// indices counter-clockwise when seen from outside (outward normals).
struct TriangleMesh {
  Points vertices;
  std::vector<Tri> triangles;
  /// Per triangle, the 1-based line of the file that defined it (OBJ, ASCII
  /// STL and PLY); empty or 0 where unknown (binary files, generated meshes).
  std::vector<int> triangle_line;

  int num_vertices() const { return static_cast<int>(vertices.cols()); }
  int num_triangles() const { return static_cast<int>(triangles.size()); }
};

struct Aabb {
  Vec3 lo{Vec3::Constant(0.0)};
  Vec3 hi{Vec3::Constant(0.0)};
};

/// Axis-aligned bounding box of the vertices (the mesh must not be empty).
Aabb bounding_box(const TriangleMesh& mesh);

/// Volume enclosed by a closed surface (divergence theorem); positive when the
/// triangles face outwards.
double enclosed_volume(const TriangleMesh& mesh);

/// Cylinder along +z: base centred at the origin, top at z = height. The side
/// is a prism over a regular polygon with `segments` vertices inscribed in the
/// circle of `radius` (first vertex on +x); caps are fans around a centre vertex.
TriangleMesh make_cylinder(double radius, double height, int segments);

/// Axis-aligned box [lo, hi], two triangles per face.
TriangleMesh make_box(const Vec3& lo, const Vec3& hi);

/// Reads a Wavefront OBJ file: `v x y z` and `f a b c ...` records (polygons
/// are fan-triangulated; `a/b/c` forms and negative indices accepted; other
/// records ignored). Errors name the file and line.
TriangleMesh read_obj(const std::string& path);

/// Reads an STL file, ASCII (`solid` ... `facet` ... `vertex x y z`) or binary
/// (80-byte header, triangle count, 50 bytes per triangle; recognised by its
/// size). STL stores each triangle's corners separately: corners with exactly
/// equal coordinates are merged into one vertex so the surface can be checked
/// for closure. Errors name the file and the line (ASCII) or triangle (binary).
TriangleMesh read_stl(const std::string& path);

/// Reads a PLY file (`ascii`, `binary_little_endian` or `binary_big_endian`
/// 1.0): the `vertex` element's x, y, z properties (any numeric type; other
/// properties skipped) and the `face` element's vertex index list
/// (`vertex_indices` or `vertex_index`; polygons fan-triangulated). Errors name
/// the file and the header line, or the element and its index.
TriangleMesh read_ply(const std::string& path);

/// Reads a surface by its extension: .obj, .stl or .ply (case-insensitive).
TriangleMesh read_surface(const std::string& path);

/// Writes `mesh` as OBJ (vertices with 17 significant digits), whole or not at all.
void write_obj(const std::string& path, const TriangleMesh& mesh);

/// Writes `triangles` over the vertices `positions` (3 x V, e.g. a deformed
/// frame of a mesh) as OBJ, each coordinate with `decimals` digits after the
/// point (6: micrometres), whole or not at all (msd/io/atomic_file.hpp).
void write_obj(const std::string& path, const Points& positions, const std::vector<Tri>& triangles, int decimals);

/// Area-weighted vertex normals (3 x V, unit length; zero for a vertex in no
/// triangle): outward on a closed, outward-oriented surface.
Points vertex_normals(const TriangleMesh& mesh);

/// Checks that `mesh` bounds a solid: finite coordinates, valid indices, no
/// degenerate triangle, every edge shared by exactly two triangles (closed and
/// edge-manifold), every vertex fan a single disc (vertex-manifold), neighbouring
/// triangles consistently oriented, and outward orientation (positive enclosed
/// volume). Throws msd::Error whose message starts with `name` and states the
/// first fault found, with the triangle, edge or vertex indices involved.
void validate_closed_surface(const TriangleMesh& mesh, const std::string& name);

/// "NAME:LINE: triangle T" for messages: T counted from 1 in reading order,
/// the line where the file has one (TriangleMesh::triangle_line).
std::string triangle_where(const TriangleMesh& mesh, const std::string& name, int t);

}  // namespace msd
