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
//
// The Hill-type law (HillMuscle below) replaces the constant force: each unit
// is a contractile element with the dimensionless curves of Zajac 1989 in
// parallel with a passive element, and the muscle's activation follows its
// excitation with first-order dynamics (activation_step).
#pragma once

#include "msd/mesh/tet_mesh.hpp"

#include <string>
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

/// The Hill-type muscle (Zajac 1989, "Muscle and tendon: properties, models,
/// scaling, and application to biomechanics and motor control", Crit. Rev.
/// Biomed. Eng. 17; the passive curve of Thelen 2003, J. Biomech. Eng. 125).
/// A unit of rest length l_r has the optimal length l_o = l_r / s0 (s0 =
/// `rest_fibre_stretch`, the fibres' stretch in the mesh's posture); at length
/// l and lengthening rate r = dl/dt, with l~ = l / l_o and v~ = r / (l_o v_max),
/// it pulls with
///
///   T = F_u [ a f_A(l~) f_V(v~) + f_P(l~) ],   F_u = the unit's share of
///       F_max = specific tension x cross-section (unit_force at activation 1),
///   f_A = 1 - ((l~ - 1) / w)^2 on |l~ - 1| < w, else 0     (w = `active_width`;
///         w = 0.5: zero at 0.5 and 1.5, Zajac's fig. 3, Gordon et al. 1966),
///   f_P = (exp(k (l~ - 1) / e0) - 1) / (exp(k) - 1) for l~ > 1, else 0
///         (k = `passive_shape` 4, e0 = `passive_strain` 0.6: F_max at 60 %
///         strain; Thelen 2003),
///   f_V = (1 + v~) / (1 - v~ / A) for -1 < v~ < 0 (shortening; Hill 1938,
///         A = `curvature` 0.25, Zajac), 0 for v~ <= -1,
///         f_e - (f_e - 1) / (1 + c v~) for v~ >= 0 (lengthening: to the
///         plateau f_e = `eccentric_max` 1.8, with c set so that the slope at
///         v~ = 0 is `eccentric_slope_ratio` (2) times the shortening one,
///         Katz 1939: c = ratio (1 + 1/A) / (f_e - 1)).
///
/// With `force_velocity` false, f_V = 1. The force-velocity term damps each
/// unit with c = F_u a f_A f_V' / (l_o v_max): at full activation and optimal
/// length, (1 + 1/A) / v_max = 0.5 s shortening and 1.0 s lengthening times
/// F_u / l_o (N s/m) - far more than the tissue's dampers - so it needs an
/// implicit integrator at the leg's time steps (the leg scene refuses it with
/// an explicit one).
struct HillMuscle {
  bool enabled = false;            ///< false: the thesis' constant force (ForceLength applies)
  double rest_fibre_stretch = 1.0; ///< s0 = l_r / l_o
  double active_width = 0.5;       ///< w, in (0, 1)
  double passive_strain = 0.6;     ///< e0 > 0
  double passive_shape = 4.0;      ///< k > 0
  bool force_velocity = true;
  double max_velocity = 10.0;      ///< v_max, optimal lengths per second (Zajac 1989)
  double curvature = 0.25;         ///< A > 0
  double eccentric_max = 1.8;      ///< f_e > 1
  double eccentric_slope_ratio = 2.0;  ///< > 0
};

/// Throws msd::Error naming `where` and the field when a Hill parameter is out
/// of its range (a force-length curve that is not a curve: w outside (0, 1),
/// e0 or k not positive; s0, v_max, A not positive; f_e <= 1).
void check_hill_muscle(const HillMuscle& hill, const std::string& where);

/// The curves and their slopes (d/dl~, d/dv~) at one point.
double hill_active_force_length(double lt, double width, double* slope = nullptr);
double hill_passive_force_length(double lt, double strain, double shape, double* slope = nullptr);
double hill_force_velocity(double vt, const HillMuscle& hill, double* slope = nullptr);

/// A unit's tension and its partial derivatives.
struct UnitTension {
  double T = 0.0;          ///< N, >= 0
  double dT_dlength = 0.0; ///< N/m
  double dT_drate = 0.0;   ///< N s/m
};

/// T of a Hill unit of rest length `rest_length` at `length` and lengthening
/// `rate` (formula above).
UnitTension hill_unit_tension(double length, double rate, double rest_length, double activation, double unit_force,
                              const HillMuscle& hill);

/// The passive element's stored energy in one unit at `length` (J): the work
/// of its tension from the optimal length l_o = rest_length / s0,
/// F_u l_o integral_1^l~ f_P = F_u l_o [(e0/k) expm1(k (l~ - 1)/e0) - (l~ - 1)] / expm1(k)
/// for l~ > 1, else 0. Its derivative in length is the passive tension F_u f_P.
double hill_passive_energy(double length, double rest_length, double unit_force, const HillMuscle& hill);

/// The sum of hill_passive_energy over a muscle's units at positions x (3 x N).
double hill_muscle_passive_energy(const Points& x, const std::vector<ContractileUnit>& units, double unit_force,
                                  const HillMuscle& hill);

/// Adds each Hill unit's pull T u (u from a to b; a pulled towards b) to f
/// (3 x N), with x, v the positions and velocities (3 x N). The passive
/// element pulls at activation 0 too.
void add_hill_muscle_forces(const Points& x, const Points& v, const std::vector<ContractileUnit>& units,
                            double unit_force, double activation, const HillMuscle& hill, Points& f);

/// First-order activation dynamics with Zajac 1989's time constants
/// (activation 10 ms, deactivation 40 ms) in the linear form of Winters 1995
/// ("An improved muscle-reflex actuator for use in large-scale
/// neuromusculoskeletal models", Ann. Biomed. Eng. 23), so that a held
/// excitation u is reached as the activation a (Zajac's eq. 3 settles at
/// u / (beta + (1 - beta) u) instead, which would change what a script's
/// levels mean):
///   da/dt = (u - a) / tau,  tau = tau_a when u > a, else tau_d,
/// solved exactly for u held over the step (a never crosses u, so tau is
/// fixed): a(t + dt) = u + (a - u) exp(-dt / tau). Unconditionally stable;
/// tau = 0: a = u at once. Throws msd::Error for u outside [0, 1] or
/// negative times.
double activation_step(double activation, double excitation, double dt, double tau_activation,
                       double tau_deactivation);

/// The muscle's units: every distinct edge of a tet of `region` whose
/// direction is within `max_angle_deg` of +-`direction`. Throws msd::Error for
/// a zero direction or an angle outside (0, 90).
std::vector<ContractileUnit> contractile_units(const TetMesh& mesh, int region, const Vec3& direction,
                                               double max_angle_deg);

/// The ends of the muscle's fibres on one side (an aponeurosis attaches
/// there): the nodes of `units` that no unit continues beyond along
/// side * direction - every unit at such a node runs from it against
/// side * d. side = +1: the ends furthest along d; -1: the other ends. On a
/// grid the units along d form chains (the fibres), and each chain has one
/// end on each side. x: 3 x N positions (the rest positions). Sorted,
/// distinct. Throws msd::Error for a zero direction or side not +-1.
std::vector<int> fibre_end_nodes(const Points& x, const std::vector<ContractileUnit>& units, const Vec3& direction,
                                 int side);

/// Force of each unit (N): activation * max_stress * volume / (sum over units of
/// |(x_b - x_a) . d| at rest). 0 for no units.
double unit_force(const TetMesh& mesh, int region, const std::vector<ContractileUnit>& units, const Vec3& direction,
                  double activation, double max_stress);

/// Force of each unit (N) when the muscle's force comes from a given
/// cross-section `area` (m^2; e.g. the published PCSA) instead of the mesh's:
/// a section crosses on average Lambda / L units (L the region's extent along
/// d, Lambda as above), so each unit carries activation * max_stress * area *
/// L / Lambda. For a prism along d (V = A L) with area = A it is unit_force.
/// 0 for no units; throws msd::Error for an area that is not positive.
double unit_force_for_area(const TetMesh& mesh, int region, const std::vector<ContractileUnit>& units,
                           const Vec3& direction, double activation, double max_stress, double area);

/// Adds each unit's pull (`force` N along the current edge, times f_L of its
/// stretch when `fl` is enabled) to f (3 x N).
void add_muscle_forces(const Points& x, const std::vector<ContractileUnit>& units, double force, Points& f,
                       const ForceLength& fl = {});

}  // namespace msd
