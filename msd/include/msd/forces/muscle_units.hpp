// Contractile units of muscle tissue (thesis 5.2.7, figure 5.17): force units
// on the muscle's tet edges that lie along the line of action, each pulling its
// two nodes towards each other with equal and opposite forces, so a muscle's
// units never add net force or torque. The force is proportional to the
// muscle's activation a (the thesis' model), optionally times the ascending
// limb of the active force-length relation (Gordon, Huxley & Julian 1966;
// Zajac 1989, the Hill-type models the thesis cites in 5.2.7):
//
//   F_unit = a * sigma_max * V / Lambda * f_L(lambda),
//   f_L = 1 for lambda >= 1,  1 - ((1 - lambda) / (1 - lambda_0))^2 for
//         lambda_0 < lambda < 1,  0 below,
//
// with lambda = l / l_rest the unit's stretch and lambda_0 the stretch at
// which a fibre can no longer pull (about 0.5 of optimal length). Without it
// (the thesis) a unit pulls with the same force however short it is, and an
// activated muscle whose pull exceeds what its passive tissue can bear
// collapses; with it the muscle shortens until its pull balances its load.
// (No descending limb: the units start at their optimal length.)
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
  double rest_length = 0.0;  ///< m
};

/// The ascending limb of the force-length relation, f_L(lambda) above.
/// `zero_at` = lambda_0 in [0, 1); the thesis' constant force is `zero_at` < 0
/// (f_L = 1 everywhere), see ForceLength.
double force_length_factor(double stretch, double zero_at);

/// Whether the units follow the force-length relation, and its lambda_0.
struct ForceLength {
  bool enabled = false;  ///< false: the thesis' constant force
  double zero_at = 0.5;  ///< lambda_0
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

/// Adds each unit's pull (`force` N along the current edge, times f_L of its
/// stretch when `fl` is enabled) to f (3 x N).
void add_muscle_forces(const Points& x, const std::vector<ContractileUnit>& units, double force, Points& f,
                       const ForceLength& fl = {});

}  // namespace msd
