// Closed-form solutions of the neo-Hookean strain energy used by the FEM
// reference (fem/fem.hpp):
//   Psi = mu/2 (J^(-2/3) I1 - 3) + kappa/4 (J^2 - 1 - 2 ln J),
// for the homogeneous verification cases, and the first axial frequency of a
// fixed-free bar. Used by the verification tests and the reports.
#pragma once

#include <array>

namespace bench {

struct UniaxialClosedForm {
  double nominal_stress = 0.0;   ///< P_zz, Pa (force / reference area)
  double lateral_stretch = 1.0;  ///< lambda_x = lambda_y
  double volume_ratio = 1.0;     ///< J
};

/// Homogeneous uni-axial stress between frictionless platens: stretch
/// lambda = 1 + strain along z, lateral stretch from sigma_xx = 0 (Newton).
UniaxialClosedForm neo_hookean_uniaxial(double mu, double kappa, double strain);

/// Simple shear F = I + gamma e_x (x) e_z (J = 1): Cauchy stresses
/// {sigma_xz, sigma_xx, sigma_yy, sigma_zz} = {mu g, 2/3 mu g^2, -1/3 mu g^2, -1/3 mu g^2}.
std::array<double, 4> neo_hookean_simple_shear(double mu, double gamma);

/// First axial frequency (Hz) of a fixed-free bar of length L with Poisson's
/// ratio 0: sqrt(E / rho) / (4 L).
double bar_first_frequency(double youngs_modulus, double density, double length);

}  // namespace bench
