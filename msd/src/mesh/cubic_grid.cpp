#include "msd/mesh/cubic_grid.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace msd {

CubeRule parse_cube_rule(const std::string& text) {
  if (text == "centre" || text == "center") return CubeRule::Centre;
  if (text == "inside") return CubeRule::WhollyInside;
  if (text == "overlap") return CubeRule::Overlap;
  throw Error("unknown cube rule '" + text + "' (expected centre, inside or overlap)");
}

std::string to_string(CubeRule rule) {
  switch (rule) {
    case CubeRule::Centre: return "centre";
    case CubeRule::WhollyInside: return "inside";
    case CubeRule::Overlap: return "overlap";
  }
  return "?";
}

CubicGrid make_grid(const Aabb& box, double h, std::optional<Vec3> origin, long max_cubes) {
  if (!(h > 0.0) || !std::isfinite(h))
    throw Error("mesh spacing h must be positive and finite (got " + std::to_string(h) + ")");
  CubicGrid g;
  g.spacing = h;
  g.origin = origin.value_or(box.lo);
  if (!g.origin.allFinite()) throw Error("grid origin is not finite");
  if (((g.origin - box.lo).array() > 1e-9 * h).any())
    throw Error("grid origin lies above the surface's lowest corner in some coordinate");
  double cells[3];
  for (int a = 0; a < 3; ++a) {
    cells[a] = std::ceil((box.hi[a] - g.origin[a]) / h - 1e-9);
    if (cells[a] < 1) cells[a] = 1;
  }
  const double total = cells[0] * cells[1] * cells[2];
  if (total > static_cast<double>(max_cubes))
    throw Error("a grid of " + std::to_string(static_cast<long>(cells[0])) + " x " +
                std::to_string(static_cast<long>(cells[1])) + " x " +
                std::to_string(static_cast<long>(cells[2])) + " cubes exceeds the limit of " +
                std::to_string(max_cubes) + " (raise mesh.max_cubes in the spec or mesh scene, or increase the "
                "spacing h = " + std::to_string(h) + " m)");
  g.nx = static_cast<int>(cells[0]);
  g.ny = static_cast<int>(cells[1]);
  g.nz = static_cast<int>(cells[2]);
  return g;
}

namespace {

// Inside flags for a lattice of points origin + h (i + s, j + s, k + s),
// 0 <= i < n[0] etc., by one ray per (j, k) line plus the closed-set tolerance.
std::vector<char> classify_lattice(const CubicGrid& g, const InsideTest& test, double shift,
                                   const int n[3]) {
  const double h = g.spacing;
  std::vector<char> flag(static_cast<size_t>(n[0]) * n[1] * n[2], 0);
  std::vector<double> xs(static_cast<size_t>(n[0]));
  for (int i = 0; i < n[0]; ++i) xs[static_cast<size_t>(i)] = g.origin.x() + h * (i + shift);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j) {
      const auto line = test.inside_on_line(g.origin.y() + h * (j + shift),
                                            g.origin.z() + h * (k + shift), xs);
      for (int i = 0; i < n[0]; ++i)
        flag[i + static_cast<size_t>(n[0]) * (j + static_cast<size_t>(n[1]) * k)] = line[i];
    }
  // Closed set: lattice points within tol of a triangle count as inside.
  const double tol = 1e-6 * h;
  const TriangleMesh& m = test.surface();
  for (const Tri& t : m.triangles) {
    const Vec3 a = m.vertices.col(t[0]), b = m.vertices.col(t[1]), c = m.vertices.col(t[2]);
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c).array() - tol;
    const Vec3 hi = a.cwiseMax(b).cwiseMax(c).array() + tol;
    int i0[3], i1[3];
    for (int ax = 0; ax < 3; ++ax) {
      i0[ax] = std::max(0, static_cast<int>(std::ceil((lo[ax] - g.origin[ax]) / h - shift)));
      i1[ax] = std::min(n[ax] - 1, static_cast<int>(std::floor((hi[ax] - g.origin[ax]) / h - shift)));
    }
    for (int k = i0[2]; k <= i1[2]; ++k)
      for (int j = i0[1]; j <= i1[1]; ++j)
        for (int i = i0[0]; i <= i1[0]; ++i) {
          char& f = flag[i + static_cast<size_t>(n[0]) * (j + static_cast<size_t>(n[1]) * k)];
          if (f) continue;
          const Vec3 p = g.origin + h * Vec3(i + shift, j + shift, k + shift);
          if ((closest_point_on_triangle(p, a, b, c) - p).norm() <= tol) f = 1;
        }
  }
  return flag;
}

}  // namespace

std::vector<char> classify_cubes(const CubicGrid& g, const InsideTest& test, CubeRule rule) {
  const int nc[3] = {g.nx, g.ny, g.nz};
  const std::vector<char> centre = classify_lattice(g, test, 0.5, nc);
  if (rule == CubeRule::Centre) return centre;

  const int nn[3] = {g.nx + 1, g.ny + 1, g.nz + 1};
  const std::vector<char> node = classify_lattice(g, test, 0.0, nn);
  std::vector<char> keep(centre.size(), 0);
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        int corners = 0;
        for (int c = 0; c < 8; ++c)
          corners += node[g.node_id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))];
        const long id = g.cube_id(i, j, k);
        keep[id] = rule == CubeRule::WhollyInside ? (centre[id] && corners == 8)
                                                  : (centre[id] || corners > 0);
      }
  if (rule == CubeRule::Overlap) {
    // A surface triangle passing through the (slightly shrunk) open cube.
    const double h = g.spacing, tol = 1e-6 * h;
    const TriangleMesh& m = test.surface();
    for (const Tri& t : m.triangles) {
      const Vec3 a = m.vertices.col(t[0]), b = m.vertices.col(t[1]), c = m.vertices.col(t[2]);
      const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
      int i0[3], i1[3];
      for (int ax = 0; ax < 3; ++ax) {
        i0[ax] = std::max(0, static_cast<int>(std::floor((lo[ax] - g.origin[ax]) / h)) - 1);
        i1[ax] = std::min(nc[ax] - 1, static_cast<int>(std::floor((hi[ax] - g.origin[ax]) / h)) + 1);
      }
      for (int k = i0[2]; k <= i1[2]; ++k)
        for (int j = i0[1]; j <= i1[1]; ++j)
          for (int i = i0[0]; i <= i1[0]; ++i) {
            const long id = g.cube_id(i, j, k);
            if (keep[id]) continue;
            const Vec3 clo = g.node_position(i, j, k).array() + tol;
            const Vec3 chi = g.node_position(i + 1, j + 1, k + 1).array() - tol;
            if (triangle_box_overlap(clo, chi, a, b, c)) keep[id] = 1;
          }
    }
  }
  return keep;
}

TetMesh split_cubes(const CubicGrid& g, const std::vector<int>& cube_region, GridMeshInfo* info) {
  if (static_cast<long>(cube_region.size()) != g.num_cubes())
    throw Error("split_cubes: cube_region has " + std::to_string(cube_region.size()) +
                " entries for " + std::to_string(g.num_cubes()) + " cubes");
  TetMesh mesh;
  std::unordered_map<long, int> node_index;
  std::vector<long> grid_ids;
  std::vector<long> tet_cube;
  auto node = [&](int i, int j, int k) {
    const long id = g.node_id(i, j, k);
    auto [it, fresh] = node_index.emplace(id, static_cast<int>(grid_ids.size()));
    if (fresh) grid_ids.push_back(id);
    return it->second;
  };
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const long cid = g.cube_id(i, j, k);
        const int region = cube_region[cid];
        if (region < 0) continue;
        // Corner c = (a, b, d) bits; global parity decides the central tet, so
        // the face diagonals of neighbouring cubes coincide.
        int corner[8];
        for (int c = 0; c < 8; ++c) corner[c] = node(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        auto even = [&](int c) { return ((i + j + k + (c & 1) + ((c >> 1) & 1) + ((c >> 2) & 1)) & 1) == 0; };
        std::array<int, 4> central{};
        int nc = 0;
        for (int c = 0; c < 8; ++c)
          if (even(c)) central[nc++] = c;
        std::vector<std::array<int, 4>> local{central};
        for (int c = 0; c < 8; ++c)
          if (!even(c)) local.push_back({c, c ^ 1, c ^ 2, c ^ 4});
        for (const auto& l : local) {
          Tet t{corner[l[0]], corner[l[1]], corner[l[2]], corner[l[3]]};
          mesh.tets.push_back(t);
          mesh.region.push_back(region);
          tet_cube.push_back(cid);
        }
      }
  mesh.nodes.resize(3, static_cast<Eigen::Index>(grid_ids.size()));
  for (size_t n = 0; n < grid_ids.size(); ++n) {
    long id = grid_ids[n];
    const int i = static_cast<int>(id % (g.nx + 1));
    id /= (g.nx + 1);
    const int j = static_cast<int>(id % (g.ny + 1));
    const int k = static_cast<int>(id / (g.ny + 1));
    mesh.nodes.col(static_cast<Eigen::Index>(n)) = g.node_position(i, j, k);
  }
  for (Tet& t : mesh.tets)
    if (tet_signed_volume(mesh.nodes, t) < 0.0) std::swap(t[2], t[3]);
  if (info) {
    info->node_grid_id = std::move(grid_ids);
    info->tet_cube_id = std::move(tet_cube);
  }
  return mesh;
}

SampleMesh mesh_closed_surface(const TriangleMesh& surface, const SampleMeshOptions& options,
                               const std::string& name) {
  validate_closed_surface(surface, name);
  SampleMesh out;
  try {
    out.grid = make_grid(bounding_box(surface), options.spacing, options.origin, options.max_cubes);
  } catch (const Error& e) {
    throw Error((options.memory.context.empty() ? name + ": " : options.memory.context) + e.what());
  }
  const std::string where = name + ": grid spacing " + std::to_string(options.spacing) + " m: ";
  check_memory(static_cast<double>(out.grid.nx) * out.grid.ny * out.grid.nz, kGridBytesPerCube, "a grid",
               options.memory, where);
  const InsideTest test(surface);
  const std::vector<char> keep = classify_cubes(out.grid, test, options.rule);
  std::vector<int> region(keep.size(), -1);
  for (size_t c = 0; c < keep.size(); ++c)
    if (keep[c]) {
      region[c] = options.region;
      ++out.cubes;
    }
  if (out.cubes == 0)
    throw Error(name + ": no cube of the grid (h = " + std::to_string(options.spacing) +
                ", rule " + to_string(options.rule) + ") belongs to the solid; reduce h");
  check_memory(static_cast<double>(out.cubes), options.solid_bytes_per_cube, "a solid", options.memory, where);
  out.mesh = split_cubes(out.grid, region, &out.info);
  check_tet_mesh(out.mesh, name);
  return out;
}

}  // namespace msd
