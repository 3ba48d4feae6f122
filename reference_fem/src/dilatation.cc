#include "dilatation.h"

#include <cmath>

namespace fem::internal {

using namespace dealii;

void CellDilatation::reinit(unsigned pressure_degree, const std::vector<Point<3>>& X,
                            const std::vector<double>& JxW) {
  const unsigned nq = static_cast<unsigned>(X.size());
  JxW_ = JxW;
  Point<3> centre;
  double volume = 0.0;
  for (unsigned q = 0; q < nq; ++q) {
    centre += JxW[q] * X[q];
    volume += JxW[q];
  }
  centre /= volume;
  const double h = std::cbrt(volume);
  // Monomials of total degree <= pressure_degree in (X - centre) / h.
  std::vector<std::array<unsigned, 3>> powers;
  for (unsigned d = 0; d <= pressure_degree; ++d)
    for (unsigned i = 0; i <= d; ++i)
      for (unsigned j = 0; i + j <= d; ++j) powers.push_back({{i, j, d - i - j}});
  np_ = static_cast<unsigned>(powers.size());
  phi_.reinit(nq, np_);
  for (unsigned q = 0; q < nq; ++q) {
    const Tensor<1, 3> y = (X[q] - centre) / h;
    for (unsigned l = 0; l < np_; ++l)
      phi_(q, l) = std::pow(y[0], powers[l][0]) * std::pow(y[1], powers[l][1]) * std::pow(y[2], powers[l][2]);
  }
  FullMatrix<double> M(np_, np_);
  for (unsigned q = 0; q < nq; ++q)
    for (unsigned k = 0; k < np_; ++k)
      for (unsigned l = 0; l < np_; ++l) M(k, l) += phi_(q, k) * phi_(q, l) * JxW[q];
  Minv_.reinit(np_, np_);
  Minv_.invert(M);
  Jt_.assign(nq, 1.0);
  p_.assign(nq, 0.0);
  G_.reinit(np_, np_);
}

bool CellDilatation::compute(const std::vector<double>& J, double kappa) {
  const unsigned nq = static_cast<unsigned>(J.size());
  std::vector<double> m(np_, 0.0), c(np_, 0.0), qv(np_, 0.0), ph(np_, 0.0);
  for (unsigned q = 0; q < nq; ++q)
    for (unsigned l = 0; l < np_; ++l) m[l] += phi_(q, l) * J[q] * JxW_[q];
  for (unsigned k = 0; k < np_; ++k)
    for (unsigned l = 0; l < np_; ++l) c[k] += Minv_(k, l) * m[l];
  bool valid = true;
  energy_ = 0.0;
  FullMatrix<double> D(np_, np_);
  for (unsigned q = 0; q < nq; ++q) {
    double jt = 0.0;
    for (unsigned l = 0; l < np_; ++l) jt += phi_(q, l) * c[l];
    Jt_[q] = jt;
    if (!(jt > 0.0)) {
      valid = false;
      continue;
    }
    energy_ += U(kappa, jt) * JxW_[q];
    const double d1 = dU(kappa, jt), d2 = ddU(kappa, jt);
    for (unsigned k = 0; k < np_; ++k) {
      qv[k] += phi_(q, k) * d1 * JxW_[q];
      for (unsigned l = 0; l < np_; ++l) D(k, l) += d2 * phi_(q, k) * phi_(q, l) * JxW_[q];
    }
  }
  for (unsigned k = 0; k < np_; ++k)
    for (unsigned l = 0; l < np_; ++l) ph[k] += Minv_(k, l) * qv[l];
  for (unsigned q = 0; q < nq; ++q) {
    double p = 0.0;
    for (unsigned l = 0; l < np_; ++l) p += phi_(q, l) * ph[l];
    p_[q] = p;
  }
  FullMatrix<double> tmp(np_, np_);
  Minv_.mmult(tmp, D);
  tmp.mmult(G_, Minv_);
  return valid;
}

}  // namespace fem::internal
