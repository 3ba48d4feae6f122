// Reference meshes for the FEM solver (see fem::MeshSpec for the geometry and
// the boundary numbering).
#pragma once

#include "fem/fem.hpp"

#include <deal.II/distributed/tria.h>

namespace fem::internal {

/// Builds the coarse mesh of `spec` in `tria` (which must be empty), numbers its
/// boundary faces, attaches the cylinder's manifolds and refines globally.
void make_mesh(dealii::parallel::distributed::Triangulation<3>& tria, const MeshSpec& spec);

/// A length scale of the geometry (largest bounding-box side), m.
double characteristic_length(const MeshSpec& spec);

}  // namespace fem::internal
