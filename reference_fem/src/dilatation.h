// Static condensation of the three-field (u - p - J~) formulation with p and J~
// discontinuous polynomials of degree k - 1 on each cell (Q_k - P_{k-1} -
// P_{k-1}; Simo, Taylor & Pister 1985; the element family of deal.II step-44).
// Eliminating p and J~ cell by cell leaves the displacement-only functional
//     Pi(u) = int Psi_iso(F) dV + int U(J~) dV,   J~ = Pi_{k-1}(J)
// (the L2 projection of J onto P_{k-1} on the cell) with pressure
// p = Pi_{k-1}(U'(J~)). For k = 1 this is the mean-dilatation method.
#pragma once

#include "neo_hookean.h"

#include <deal.II/base/point.h>
#include <deal.II/lac/full_matrix.h>

#include <vector>

namespace fem::internal {

/// Per-cell condensed state. With the P_{k-1} basis phi_l (monomials in the
/// reference coordinates about the cell centre, scaled by the cell size):
///   M = int phi phi^T dV,  c = M^-1 int phi J dV,  J~(x) = phi(x) . c,
///   p^ = M^-1 int phi U'(J~) dV,  p(x) = phi(x) . p^,
///   G = M^-1 (int U''(J~) phi phi^T dV) M^-1,
/// and with B_la = int phi_l J (F^-T:G_a) dV the volumetric tangent is
/// B^T G B + int p G_a : d(J F^-T)/dF : G_b dV.
class CellDilatation {
 public:
  /// Basis values for the quadrature points X (reference positions).
  void reinit(unsigned pressure_degree, const std::vector<dealii::Point<3>>& X, const std::vector<double>& JxW);
  /// Given J at the quadrature points, computes J~, p and G. Returns false if
  /// some J~ <= 0.
  bool compute(const std::vector<double>& J, double kappa);

  unsigned size() const { return np_; }
  double phi(unsigned q, unsigned l) const { return phi_(q, l); }
  double J_tilde(unsigned q) const { return Jt_[q]; }
  double pressure(unsigned q) const { return p_[q]; }
  double energy() const { return energy_; }
  const dealii::FullMatrix<double>& G() const { return G_; }

 private:
  unsigned np_ = 1;
  dealii::FullMatrix<double> phi_, Minv_, G_;
  std::vector<double> JxW_, Jt_, p_;
  double energy_ = 0.0;
};

}  // namespace fem::internal
