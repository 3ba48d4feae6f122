#include "tbio/surface_check.hpp"

#include "msd/core/types.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <iterator>
#include <set>

namespace tbio {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Face = Mesh::Face_index;

// Where triangle t of surface s is, for messages: "NAME:LINE: triangle T+1".
std::string where(const NamedSurface& s, int t) {
  const auto& lines = s.mesh->triangle_line;
  const int line = static_cast<size_t>(t) < lines.size() ? lines[static_cast<size_t>(t)] : 0;
  return s.name + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": triangle " + std::to_string(t + 1);
}

}  // namespace

void refuse_intersections(const std::vector<NamedSurface>& surfaces,
                          const std::vector<std::pair<int, int>>& must_not_cross) {
  // All surfaces in one mesh, each with its own vertices; face f of the
  // combined mesh is (surface owner[f], triangle local[f]).
  Mesh all;
  std::vector<int> owner, local;
  for (size_t s = 0; s < surfaces.size(); ++s) {
    const msd::TriangleMesh& m = *surfaces[s].mesh;
    std::vector<Mesh::Vertex_index> v(static_cast<size_t>(m.num_vertices()));
    for (int i = 0; i < m.num_vertices(); ++i)
      v[static_cast<size_t>(i)] = all.add_vertex(Kernel::Point_3(m.vertices(0, i), m.vertices(1, i), m.vertices(2, i)));
    for (int t = 0; t < m.num_triangles(); ++t) {
      const msd::Tri& tri = m.triangles[static_cast<size_t>(t)];
      const Face f = all.add_face(v[static_cast<size_t>(tri[0])], v[static_cast<size_t>(tri[1])],
                                  v[static_cast<size_t>(tri[2])]);
      if (f == Mesh::null_face())
        throw msd::Error(where(surfaces[s], t) + ": not a manifold surface (the face cannot be added)");
      if (static_cast<size_t>(f.idx()) != owner.size()) throw msd::Error("surface check: unexpected face numbering");
      owner.push_back(static_cast<int>(s));
      local.push_back(t);
    }
  }
  std::vector<std::pair<Face, Face>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(CGAL::faces(all), all, std::back_inserter(pairs));
  const std::set<std::pair<int, int>> checked(must_not_cross.begin(), must_not_cross.end());
  // The first pair in a fixed order (by the faces' numbers), so the message
  // does not depend on CGAL's traversal.
  const std::pair<Face, Face>* first = nullptr;
  auto key = [](const std::pair<Face, Face>& p) {
    const std::size_t a = p.first.idx(), b = p.second.idx();  // by value: minmax of temporaries would dangle
    return std::pair<std::size_t, std::size_t>(std::min(a, b), std::max(a, b));
  };
  for (const auto& p : pairs) {
    const int a = owner[p.first.idx()], b = owner[p.second.idx()];
    if (a != b && !checked.count({a, b}) && !checked.count({b, a})) continue;
    if (!first || key(p) < key(*first)) first = &p;
  }
  if (!first) return;
  const auto [fa, fb] = key(*first);
  const int a = owner[fa], b = owner[fb];
  const std::string wa = where(surfaces[static_cast<size_t>(a)], local[fa]);
  const std::string wb = where(surfaces[static_cast<size_t>(b)], local[fb]);
  if (a == b) throw msd::Error(wa + " and " + wb + " intersect: the surface crosses itself");
  throw msd::Error(wa + " and " + wb + " intersect: the surfaces " + surfaces[static_cast<size_t>(a)].name + " and " +
                   surfaces[static_cast<size_t>(b)].name + " cross each other");
}

}  // namespace tbio
