// Surfaces that cross themselves or each other are refused before meshing: a
// self-intersecting skin would be meshed with a hidden void, and two regions'
// surfaces that cross leave cubes claimed by both. The face-pair tests are
// CGAL's (Polygon_mesh_processing::self_intersections, exact predicates),
// run once on all the surfaces together.
#pragma once

#include "msd/geometry/triangle_mesh.hpp"

#include <string>
#include <utility>
#include <vector>

namespace tbio {

/// A surface to check, with the name its messages use (its file).
struct NamedSurface {
  const msd::TriangleMesh* mesh = nullptr;
  std::string name;
};

/// Throws msd::Error when a surface crosses itself ("NAME:LINE: triangle 12
/// and NAME:LINE: triangle 40 intersect: the surface crosses itself") or when
/// two surfaces of a pair listed in `must_not_cross` (indices into `surfaces`)
/// cross each other ("A:LINE: triangle 3 of A and B:LINE: triangle 7 of B
/// intersect: the surfaces cross"). Triangles are numbered from 1 in reading
/// order, and carry the line of the file that defined them where the format
/// has lines. Each surface must already be closed and manifold
/// (msd::validate_closed_surface).
/// Every crossing counts, a fold between neighbouring triangles too (the leg
/// generator's relaxation no longer turns triangles inwards, which is how it
/// made the folds the shipped lower bone had: msd/geometry/implicit_surface.hpp).
void refuse_intersections(const std::vector<NamedSurface>& surfaces,
                          const std::vector<std::pair<int, int>>& must_not_cross);

}  // namespace tbio
