// Reference meshes: boxes, the thesis cylinder and Cook's membrane, all made
// serially as coarse meshes and copied into the distributed triangulation.
#include "mesh.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>

#include <algorithm>
#include <cmath>

namespace fem::internal {

using namespace dealii;

namespace {

constexpr types::manifold_id kHullManifold = 0;
constexpr types::manifold_id kTransfiniteManifold = 1;

void check_positive(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw fem::Error(std::string("fem mesh: ") + what + " must be positive (got " + std::to_string(v) + ")");
}

// Boundary ids by the reference position of each boundary face's centre.
void number_faces(Triangulation<3>& tria, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                  bool hull) {
  const double tol = 1e-9 * std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary()) continue;
      const Point<3> c = face->center();
      types::boundary_id id = 6;
      if (std::abs(c[2] - lo[2]) < tol) id = 4;
      else if (std::abs(c[2] - hi[2]) < tol) id = 5;
      else if (!hull) {
        if (std::abs(c[0] - lo[0]) < tol) id = 0;
        else if (std::abs(c[0] - hi[0]) < tol) id = 1;
        else if (std::abs(c[1] - lo[1]) < tol) id = 2;
        else if (std::abs(c[1] - hi[1]) < tol) id = 3;
      }
      face->set_boundary_id(id);
    }
}

}  // namespace

double characteristic_length(const MeshSpec& spec) {
  switch (spec.shape) {
    case MeshSpec::Shape::Box: return std::max({spec.size[0], spec.size[1], spec.size[2]});
    case MeshSpec::Shape::Cylinder: return std::max(2 * spec.radius, spec.height);
    case MeshSpec::Shape::CooksMembrane: return 0.060;
  }
  return 1.0;
}

void make_mesh(parallel::distributed::Triangulation<3>& tria, const MeshSpec& spec) {
  for (unsigned c : spec.cells)
    if (c == 0 || c > 4096) throw fem::Error("fem mesh: coarse cell counts must be between 1 and 4096");
  if (spec.refinement > 8) throw fem::Error("fem mesh: more than 8 global refinements requested");
  Triangulation<3> coarse;
  bool cylinder = false;
  switch (spec.shape) {
    case MeshSpec::Shape::Box: {
      for (int a = 0; a < 3; ++a) check_positive(spec.size[a], "box size");
      GridGenerator::subdivided_hyper_rectangle(
          coarse, {spec.cells[0], spec.cells[1], spec.cells[2]}, Point<3>(0, 0, 0),
          Point<3>(spec.size[0], spec.size[1], spec.size[2]), false);
      number_faces(coarse, {0, 0, 0}, spec.size, false);
      break;
    }
    case MeshSpec::Shape::CooksMembrane: {
      // Unit block (xi, eta, z) mapped onto the membrane: left edge x = 0 from
      // y = 0 to 44 mm, right edge x = 48 mm from y = 44 to 60 mm, 1 mm thick.
      GridGenerator::subdivided_hyper_rectangle(coarse, {spec.cells[0], spec.cells[1], spec.cells[2]},
                                                Point<3>(0, 0, 0), Point<3>(1, 1, 0.001), false);
      number_faces(coarse, {0, 0, 0}, {1, 1, 0.001}, false);
      GridTools::transform(
          [](const Point<3>& p) {
            const double xi = p[0], eta = p[1];
            return Point<3>(0.048 * xi, (1 - eta) * 0.044 * xi + eta * (0.044 + 0.016 * xi), p[2]);
          },
          coarse);
      break;
    }
    case MeshSpec::Shape::Cylinder: {
      check_positive(spec.radius, "cylinder radius");
      check_positive(spec.height, "cylinder height");
      Triangulation<2> disk;
      GridGenerator::hyper_ball(disk, Point<2>(0, 0), spec.radius);
      GridGenerator::extrude_triangulation(disk, spec.cells[2] + 1, spec.height, coarse);
      number_faces(coarse, {-spec.radius, -spec.radius, 0}, {spec.radius, spec.radius, spec.height}, true);
      cylinder = true;
      break;
    }
  }
  tria.copy_triangulation(coarse);
  if (cylinder) {
    tria.set_all_manifold_ids(kTransfiniteManifold);
    tria.set_all_manifold_ids_on_boundary(6, kHullManifold);
    tria.set_manifold(kHullManifold, CylindricalManifold<3>(Tensor<1, 3>({0.0, 0.0, 1.0}), Point<3>(0, 0, 0)));
    TransfiniteInterpolationManifold<3> tfi;
    tfi.initialize(tria);
    tria.set_manifold(kTransfiniteManifold, tfi);
  }
  tria.refine_global(spec.refinement);
}

}  // namespace fem::internal
