// Material constants of one tissue region and how they become per-element
// constants (thesis 5.1.2, 5.2.3-5.2.6). Two ways to give them:
//
//  - Raw: the thesis' element constants used as they are, the same for every
//    element: k_s and k_r, k_v in N/m, k_d in N s/m (the thesis' uni-axial
//    sample used k_s = 10.75, k_d = 0.2).
//
//  - Physical: Young's modulus E (Pa) and dimensionless factors. Each element e
//    with rest volume V_e contributes to its edge c of rest length L_c
//        k_s = s_lattice * scale * E V_e / L_c^2
//    - the form of Van Gelder (1998, "Approximate simulation of elastic
//    membranes by triangulated spring meshes", J. Graphics Tools 3(2):21-42):
//    stiffness proportional to the element measure over the squared edge length,
//    summed over the elements sharing the edge - so the small-strain modulus of a
//    sample does not depend on the mesh spacing h. s_lattice = 5/6 calibrates the
//    form to the five-tetrahedron cubic lattice: its Cauchy-Born (homogenised)
//    elasticity with s_lattice = 1 is C11 = 4E/3, C12 = C44 = E/3, i.e. a modulus
//    along the grid axes of (C11 - C12)(C11 + 2 C12)/(C11 + C12) = 6E/5
//    (derivation in docs/msd-model.md), so 5/6 makes it E. `scale` (default 1)
//    is the calibration knob.
//    Dampers: k_d = damping_time * k_s (stiffness-proportional Rayleigh damping,
//    time constant in s). Repulsion and volume terms are dimensionless factors
//    of the element's reference stiffness for vertex i at rest height x0_i:
//        k_r,i = repulsion_factor * s_lattice * scale * E V_e / x0_i^2,
//        k_v,i = volume_factor    * s_lattice * scale * E V_e / x0_i^2.
//    Linearised at rest, face repulsion adds stiffness 2 k_r against a change of
//    height and volume preservation adds k_v.
#pragma once

#include "msd/core/types.hpp"
#include "msd/forces/bulk_volume.hpp"
#include "msd/forces/spring_law.hpp"

#include <array>

#include <optional>
#include <string>

namespace msd {

enum class ConstantsMode { Raw, Physical };

/// How a region's mass is spread over its nodes:
///  - PerTet: every tet gives a quarter of its mass to each vertex (the lumped
///    mass of linear finite elements: surface and edge nodes carry less, the
///    centre of mass and inertia of the sample are right; the default);
///  - EqualPerNode: the region's mass divided equally over all its nodes (what
///    the thesis did, 5.2.6; use it to reproduce the thesis).
enum class MassLumping { PerTet, EqualPerNode };

struct TissueMaterial {
  double density = 0.0;  ///< kg/m^3 (thesis 2.8: non-muscular tissue 920)
  ConstantsMode mode = ConstantsMode::Raw;
  MassLumping lumping = MassLumping::PerTet;
  // Raw constants.
  double k_s = 0.0, k_d = 0.0, k_r = 0.0, k_v = 0.0;
  // Physical constants.
  double youngs_modulus = 0.0;     ///< Pa
  double damping_time = 0.0;       ///< s, k_d = damping_time * k_s
  double stiffness_scale = 1.0;    ///< calibration factor on k_s, k_r, k_v
  double repulsion_factor = 0.0;   ///< k_r relative to the reference stiffness
  double volume_factor = 0.0;      ///< k_v relative to the reference stiffness
  /// Poisson's ratio, in (-1, 0.5): read only by the continuum element (the
  /// neo_hookean term, whose mu and lambda are E's, nu's and stiffness_scale's);
  /// the lattice's own ratio is set by its geometry.
  std::optional<double> poisson_ratio;
  // Both modes.
  double repulsion_floor = 0.01;   ///< tangent continuation below floor * x0
  /// Per edge class (EdgeClass order: axis, face_diagonal, other): a factor on
  /// the edge's k_s and k_d and its spring law (msd/forces/spring_law.hpp).
  /// The default, factor 1 and the linear law on every class, is the thesis'.
  std::array<SpringLaw, kEdgeClasses> edge_laws{};
  /// A factor on the lattice's bulk term's modulus (lattice_bulk_law;
  /// read only with the bulk term, msd/forces/bulk_volume.hpp).
  double bulk_factor = 1.0;
  /// The springs have rest length 0 and the cotangent weights of
  /// msd/forces/zero_length_springs.hpp (k = stiffness_scale mu w; the
  /// dampers keep the physical rule's k_d), and the bulk term has the neo-Hookean law: the
  /// lattice whose energy is the compressible neo-Hookean one. Physical
  /// constants with a Poisson's ratio, the bulk term, no edge classes.
  bool zero_length_springs = false;
  /// Whether every class is the thesis' linear spring of factor 1.
  bool thesis_springs() const;
};

/// Cauchy-Born factor of the five-tetrahedron cubic lattice (see above).
inline constexpr double kLatticeStiffnessFactor = 5.0 / 6.0;

/// The volume law of the lattice's per-cube bulk term
/// (msd/forces/bulk_volume.hpp), lambda and mu of E and nu:
///  - springs with a rest length: quadratic, K = bulk_factor *
///    stiffness_scale * (lambda - mu) - what isotropic springs
///    (lambda_s = mu_s = mu) lack of the continuum's small-strain
///    elasticity; needs nu above 1/4 (at or below it lambda <= mu: springs
///    alone are already as compressible or less);
///  - zero-length springs: neo-Hookean, modulus bulk_factor *
///    stiffness_scale * lambda, rest_modulus stiffness_scale * mu (the
///    springs' own mu); needs nu > 0.
/// Throws msd::Error naming `where` unless the constants are physical with a
/// Poisson's ratio in that range.
BulkLaw lattice_bulk_law(const TissueMaterial& m, const std::string& where);

/// The shear modulus mu = E / (2 (1 + nu)) times stiffness_scale (Pa) of
/// physical constants with a Poisson's ratio; throws msd::Error naming
/// `where` and `what` (the term that needs it) otherwise.
double scaled_shear_modulus(const TissueMaterial& m, const std::string& where, const std::string& what);

/// Throws msd::Error naming `where` and the field if a constant is unphysical
/// (density <= 0, negative constants, E <= 0 in physical mode, floor not in
/// (0, 1), a Poisson's ratio given outside (-1, 0.5), non-finite values, an
/// edge class's law refused by check_spring_law: "<where>: edge_classes.axis.stiffness ...").
void check_material(const TissueMaterial& m, const std::string& where);

/// Per-element constants of one tet from its rest geometry.
struct ElementConstants {
  double k_s[6], k_d[6], k_r[4], k_v[4];
};

/// edge_class (kTetEdges order; null: every edge `axis`, i.e. no class
/// factor - which is factor 1 unless the material sets one) picks each edge's
/// factor from m.edge_laws.
ElementConstants element_constants(const TissueMaterial& m, double rest_volume,
                                   const double rest_length[6], const double rest_height[4],
                                   const EdgeClass* edge_class = nullptr);

}  // namespace msd
