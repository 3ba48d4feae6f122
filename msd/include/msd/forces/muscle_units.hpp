// Contractile units of muscle tissue (thesis 5.2.7, figure 5.17): force units
// on the muscle's tet edges that lie along the line of action, each pulling its
// two nodes towards each other with equal and opposite forces, so a muscle's
// units never add net force or torque. The force is proportional to the
// muscle's activation a (the thesis' model; no force-length or force-velocity
// dependence):
//
//   F_unit = a * sigma_max * V / Lambda,
//
// where V is the muscle's rest volume and Lambda the summed rest length of its
// units projected on the line of action. V / Lambda is each unit's share of the
// muscle's cross-section: a section of area A = V / L crosses on average
// Lambda / L units, so the section carries a * sigma_max * A in total.
#pragma once

#include "msd/mesh/tet_mesh.hpp"

#include <vector>

namespace msd {

/// One contractile unit: the tet edge (a, b) of a muscle.
struct ContractileUnit {
  int a = 0, b = 0;
};

/// The muscle's units: every distinct edge of a tet of `region` whose
/// direction is within `max_angle_deg` of +-`direction`. Throws msd::Error for
/// a zero direction or an angle outside (0, 90).
std::vector<ContractileUnit> contractile_units(const TetMesh& mesh, int region, const Vec3& direction,
                                               double max_angle_deg);

/// Force of each unit (N): activation * max_stress * volume / (sum over units of
/// |(x_b - x_a) . d| at rest). 0 for no units.
double unit_force(const TetMesh& mesh, int region, const std::vector<ContractileUnit>& units, const Vec3& direction,
                  double activation, double max_stress);

/// Adds each unit's pull (`force` N along the current edge) to f (3 x N).
void add_muscle_forces(const Points& x, const std::vector<ContractileUnit>& units, double force, Points& f);

}  // namespace msd
