// Neo-Hookean kinematics and the tangent contractions the assembly needs, for
//     Psi(F) = mu/2 (J^(-2/3) I1 - 3) + U(J),   U(J) = kappa/4 (J^2 - 1 - 2 ln J).
// A shape function a of a primitive vector element has one component c_a and a
// reference gradient g_a; its displacement gradient is G_a = e_{c_a} (x) g_a.
// Everything below is written for such pairs so a tangent entry costs a few
// dozen flops instead of a rank-4 contraction.
#pragma once

#include <deal.II/base/tensor.h>

#include <cmath>

namespace fem::internal {

using dealii::Tensor;

/// Per quadrature point: F, J, F^-T, I1 and the derived scalars.
struct Kinematics {
  Tensor<2, 3> F, F_inv_T;
  double J = 1.0, I1 = 3.0, a = 1.0;  // a = J^(-2/3)

  explicit Kinematics(const Tensor<2, 3>& grad_u) {
    F = grad_u;
    for (unsigned i = 0; i < 3; ++i) F[i][i] += 1.0;
    J = dealii::determinant(F);
    F_inv_T = dealii::transpose(dealii::invert(F));
    I1 = dealii::scalar_product(F, F);
    a = std::pow(J, -2.0 / 3.0);
  }
};

inline double U(double kappa, double J) { return 0.25 * kappa * (J * J - 1.0 - 2.0 * std::log(J)); }
inline double dU(double kappa, double J) { return 0.5 * kappa * (J - 1.0 / J); }
inline double ddU(double kappa, double J) { return 0.5 * kappa * (1.0 + 1.0 / (J * J)); }

/// Isochoric energy density mu/2 (J^(-2/3) I1 - 3).
inline double psi_iso(double mu, const Kinematics& k) { return 0.5 * mu * (k.a * k.I1 - 3.0); }

/// First Piola-Kirchhoff stress of the isochoric part: mu J^(-2/3) (F - I1/3 F^-T).
inline Tensor<2, 3> P_iso(double mu, const Kinematics& k) {
  return mu * k.a * (k.F - (k.I1 / 3.0) * k.F_inv_T);
}

/// For one shape function: FG = F g (so F:G_a = FG[c]) and h = F^-T g (the
/// spatial gradient; F^-T:G_a = h[c]).
struct ShapeTerms {
  dealii::Tensor<1, 3> Fg, h, g;
  unsigned c = 0;
};

inline ShapeTerms shape_terms(const Kinematics& k, const dealii::Tensor<1, 3>& g, unsigned c) {
  return {k.F * g, k.F_inv_T * g, g, c};
}

/// G_a : dP_iso/dF : G_b  (derivation in docs/fem-reference.md).
inline double iso_tangent(double mu, const Kinematics& k, const ShapeTerms& A, const ShapeTerms& B) {
  const double d = (A.c == B.c) ? A.g * B.g : 0.0;
  return mu * k.a *
         (d - (2.0 / 3.0) * A.Fg[A.c] * B.h[B.c] - (2.0 / 3.0) * A.h[A.c] * B.Fg[B.c] +
          (2.0 / 9.0) * k.I1 * A.h[A.c] * B.h[B.c] + (k.I1 / 3.0) * B.h[A.c] * A.h[B.c]);
}

/// G_a : d(J F^-T)/dF : G_b = J (h_a[c_a] h_b[c_b] - h_b[c_a] h_a[c_b]).
inline double dJFinvT(const Kinematics& k, const ShapeTerms& A, const ShapeTerms& B) {
  return k.J * (A.h[A.c] * B.h[B.c] - B.h[A.c] * A.h[B.c]);
}

/// Cauchy stress of the whole energy with volumetric pressure p:
/// sigma = (P_iso F^T)/J + p I.
inline Tensor<2, 3> cauchy(double mu, double p, const Kinematics& k) {
  Tensor<2, 3> s = (1.0 / k.J) * P_iso(mu, k) * dealii::transpose(k.F);
  for (unsigned i = 0; i < 3; ++i) s[i][i] += p;
  return s;
}

}  // namespace fem::internal
