// Mass properties of a bone from its tets, and the force and torque that the
// tissue's nodal forces put on it (thesis 5.4). The thesis lumped each cube's
// mass at its centre (I = sum m r_i^2); here the integrals over the tets are
// exact. With x = sum_i lambda_i v_i over a tet of volume V and the simplex
// moments  integral lambda_i lambda_j dV = V (1 + delta_ij) / 20,
//
//   integral x x^T dV = V / 20 (sum_i v_i v_i^T + s s^T),   s = sum_i v_i,
//
// so the second moment C = rho * sum over tets, the inertia tensor about the
// origin is I = tr(C) E - C, and about the centre of mass c,
// I_c = I - m (|c|^2 E - c c^T).
#pragma once

#include "msd/mesh/tet_mesh.hpp"

#include <utility>
#include <vector>

namespace msd {

/// Bone tissue density (thesis 2.8.5, dry bone: 2.0 g/cm^3), kg/m^3.
inline constexpr double kBoneDensity = 2000.0;

struct MassProperties {
  double mass = 0.0;               ///< kg
  Vec3 centre{Vec3::Zero()};       ///< centre of mass, m
  Mat3 inertia{Mat3::Zero()};      ///< about the centre, in the mesh's axes, kg m^2
};

/// Mass properties of the tets of `region` at `density`. Throws msd::Error for
/// a non-positive density or a region with no tets.
MassProperties region_mass_properties(const TetMesh& mesh, int region, double density);

/// Moment of inertia about the line through `point` along `axis` (parallel axes).
double moment_about_axis(const MassProperties& body, const Vec3& point, const Vec3& axis);

/// The resultant force and its torque about `centre` of the forces f (3 x N)
/// acting on `nodes` at positions x (3 x N): what the tissue does to a bone
/// through the nodes attached to it.
std::pair<Vec3, Vec3> force_and_torque(const Points& x, const Points& f, const std::vector<int>& nodes,
                                       const Vec3& centre);

}  // namespace msd
