#include "bench/closed_form.hpp"

#include "msd/core/types.hpp"

#include <cmath>

namespace bench {

namespace {

// Cauchy stress component along a principal direction with stretch l, for the
// diagonal deformation diag(lt, lt, lz).
double sigma(double mu, double kappa, double l, double lt, double lz) {
  const double J = lt * lt * lz;
  const double I1 = 2 * lt * lt + lz * lz;
  const double p = 0.5 * kappa * (J - 1.0 / J);
  return mu * std::pow(J, -5.0 / 3.0) * (l * l - I1 / 3.0) + p;
}

}  // namespace

UniaxialClosedForm neo_hookean_uniaxial(double mu, double kappa, double strain) {
  const double lz = 1.0 + strain;
  if (!(lz > 0.0)) throw msd::Error("neo_hookean_uniaxial: strain must exceed -1");
  double lt = 1.0 / std::sqrt(lz);  // incompressible guess
  for (int it = 0; it < 100; ++it) {
    const double f = sigma(mu, kappa, lt, lt, lz);
    const double h = 1e-7 * lt;
    const double df = (sigma(mu, kappa, lt + h, lt + h, lz) - sigma(mu, kappa, lt - h, lt - h, lz)) / (2 * h);
    double step = f / df;
    while (lt - step <= 0.0) step *= 0.5;
    lt -= step;
    if (std::abs(step) < 1e-15 * lt) break;
  }
  UniaxialClosedForm r;
  r.lateral_stretch = lt;
  r.volume_ratio = lt * lt * lz;
  r.nominal_stress = sigma(mu, kappa, lz, lt, lz) * lt * lt;
  return r;
}

std::array<double, 4> neo_hookean_simple_shear(double mu, double g) {
  return {{mu * g, 2.0 / 3.0 * mu * g * g, -mu * g * g / 3.0, -mu * g * g / 3.0}};
}

double bar_first_frequency(double E, double rho, double L) { return std::sqrt(E / rho) / (4.0 * L); }

}  // namespace bench
