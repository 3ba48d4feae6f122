// The element force loop: for every element, gather its four vertices once, add
// the enabled terms (edge springs, edge dampers, face repulsion, volume
// preservation - thesis eq. 5.4 plus eq. 5.5) and scatter into one force buffer.
// Each term is its own function (edge_springs.hpp, ...); this loop only composes
// them so a model pays for the terms it uses and nothing else.
#pragma once

#include "msd/model/model.hpp"

namespace msd {

/// Internal forces of all elements at positions x and velocities v (3 x N) into
/// f (resized and overwritten). Returns the number of elements whose non-linear
/// terms were evaluated (all of them when the threshold is off).
long compute_internal_forces(const Model& model, const Points& x, const Points& v, Points& f);

/// Forces of element e alone, for diagnostics and tests: f[i] is the force on
/// its local vertex i.
void element_forces(const Model& model, int e, const Points& x, const Points& v, Vec3 f[4]);

/// Elastic energy of the conservative terms (springs, face repulsion) at x.
double conservative_energy(const Model& model, const Points& x);

/// Kinetic energy sum m |v|^2 / 2.
double kinetic_energy(const Model& model, const Points& v);

}  // namespace msd
