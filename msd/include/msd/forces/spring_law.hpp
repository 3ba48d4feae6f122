// Edge classes of the five-tet cubic lattice and a non-linear spring law per
// class (issue 17: more freedom where the cubic lattice needs it).
//
// Why classes. The five-tet split of a cube (thesis 4.5) has two kinds of
// edge: the cube's own edges, along a grid axis (length h), and one diagonal
// of every cube face (length h sqrt 2); it has no body diagonal. With one
// stiffness per class - axis factor a, face-diagonal factor d on the element's
// k_s = s E V / L^2 (tissue_material.hpp) - the springs' Cauchy-Born
// elasticity is (docs/msd-model.md section 4, edge classes)
//     C11 = 2 (a + d) E / 3,   C12 = C44 = d E / 3,
// so with a = d (the thesis) the lattice is cubic-anisotropic,
// 2 C44 / (C11 - C12) = 2/3, and a = d / 2 makes it isotropic (the Cauchy
// relation C12 = C44 of central springs stays; the volume term adds the rest
// of lambda). Stiffness per edge class: Lloyd, Szekely & Harders 2007 (IEEE
// TVCG 13(5)), Baudet et al. 2009 (VRIPHYS).
//
// The law. A spring of rest length r, stretch lambda = |l| / r, pulls with
//     T = k r phi(lambda),  phi(lambda) = (lambda^m - lambda^-n) / (m + n),
// m (tension exponent) >= 0, n (compression exponent) >= 0, m + n > 0: a
// Seth-Hill-type blend of the generalised strains (Hill 1968, J. Mech. Phys.
// Solids 16: 229-242), with unit slope at rest, so k keeps its meaning as the
// small-strain stiffness. (m, n) = (1, 0) is the thesis' linear spring,
// phi = lambda - 1, computed by the linear code path bit for bit; (1, 2) is the
// neo-Hookean bar's uni-axial curve (lambda - lambda^-2) / 3; n > 0 makes the
// spring's force grow without bound as it is crushed (lambda -> 0), n >= 1
// its energy too. Fitting a spring law to tensile and compressibility curves:
// San-Vicente, Aguinaga & Celigueta 2012 (Comput. Methods Biomech. Biomed.
// Eng. 15(12)). The law's slope
//     phi'(lambda) = (m lambda^(m-1) + n lambda^(-n-1)) / (m + n) > 0
// for every lambda > 0, so a law with non-negative exponents is monotonic with
// positive stiffness; negative exponents (which would break that) are refused.
// Energy: k r^2 Psi(lambda), Psi(lambda) = integral_1^lambda phi
//     = (P_(m+1)(lambda) - P_(1-n)(lambda)) / (m + n),
// P_p(lambda) = (lambda^p - 1) / p, and ln lambda for p = 0.
#pragma once

#include "msd/core/types.hpp"

#include <array>
#include <string>

namespace msd {

/// The edge classes; kEdgeClasses of them. `other`: any edge that is neither
/// (a mesh not from the axis-aligned grid, e.g. one whose boundary was moved).
enum class EdgeClass : unsigned char { axis = 0, face_diagonal = 1, other = 2 };
inline constexpr int kEdgeClasses = 3;

/// "axis", "face_diagonal", "other".
const char* to_string(EdgeClass c);

/// The class of an edge from its rest vector d: axis when one component is
/// non-zero, face_diagonal when two are, of equal size; else other
/// ("zero" and "equal" to 1e-6 |d|).
EdgeClass classify_edge(const Vec3& d);

/// One class's spring: a factor on k_s (and on k_d = damping_time k_s) and
/// the law's exponents. The default is the thesis' linear spring.
struct SpringLaw {
  double stiffness = 1.0;
  double tension_exponent = 1.0;      ///< m
  double compression_exponent = 0.0;  ///< n
  /// phi(lambda) = lambda - 1 exactly: the linear code path.
  bool linear() const { return tension_exponent == 1.0 && compression_exponent == 0.0; }
};

/// Throws msd::Error "<where>.<field> must be ..." when the factor is not
/// positive and finite, an exponent is negative or not finite, or both are 0.
void check_spring_law(const SpringLaw& law, const std::string& where);

/// phi(lambda), phi'(lambda), Psi(lambda) of the law with exponents m, n
/// (lambda > 0).
double spring_law_tension(double m, double n, double stretch);
double spring_law_slope(double m, double n, double stretch);
double spring_law_energy(double m, double n, double stretch);

/// The force on vertex a as a multiple of l (as edge_spring_factor):
/// k_s r phi(|l| / r) / |l|.
inline double spring_law_factor(double ks, double length, double inv_length, double rest, double m, double n) {
  return ks * rest * spring_law_tension(m, n, length / rest) * inv_length;
}

/// dF_a/dl (F_a the force on a, l = x_b - x_a) of a spring with this law:
/// k_s [phi'(lambda) u u^T + (r phi(lambda) / |l|) (I - u u^T)], u = l / |l|.
Mat3 spring_law_jacobian(const Vec3& l, double rest, double ks, double m, double n);

}  // namespace msd
