// Tendon strands (thesis 5.3): a tension-only cable along a polyline of nodes
// p_0 (muscle end) ... p_n (bone end) of length L = sum |p_{i+1} - p_i|,
//
//   T = k_t (L - L0)  for L > L0,  0 otherwise  (a slack tendon pushes nothing),
//   k_t = E A / L0     (modulus E, cross-section A, natural length L0),
//
// with energy k_t (L - L0)^2 / 2 for L > L0. With u_i the unit vector of
// segment i, the forces are minus the energy's gradient:
//
//   F_0 = T u_0,   F_n = -T u_{n-1},   F_i = T (u_i - u_{i-1})  (inner nodes).
//
// An inner node receives only the resultant of the two segment pulls, which is
// transverse to the strand where it runs straight: the tendon slides through
// the tissue instead of dragging it along. Pre-tensioning (5.3; the thesis
// reduced the natural length by 20-30 %) is a scale on L0 from the scene.
//
// Real tendon is not linear from zero: its collagen crimp straightens first
// (the toe region, to about 2-3 % strain), then it stretches linearly at
// about 1.2 GPa (Maganaris & Paul 1999, J. Physiol. 521; Butler et al. 1978,
// Exerc. Sport Sci. Rev. 6). With the toe strain e_t > 0 and e = (L - L0)/L0:
//
//   T = k_t L0 e^2 / (2 e_t)        for 0 < e < e_t   (stiffness rising linearly),
//   T = k_t L0 (e - e_t / 2)        for e >= e_t      (the linear modulus, C1 at e_t),
//
// energy L0 k_t L0 e^3 / (6 e_t) in the toe, then
// k_t L0^2 [e_t^2 / 6 + (e^2 - e_t^2) / 2 - e_t (e - e_t) / 2]. e_t = 0 is the
// thesis' linear strand.
#pragma once

#include "msd/core/types.hpp"

#include <vector>

namespace msd {

/// Strand stiffness E A / L0 (N/m). Throws msd::Error unless all are positive.
double tendon_stiffness(double youngs_modulus, double area, double natural_length);

/// Current length of the strand through `nodes` at positions x (3 x N).
double strand_length(const Points& x, const std::vector<int>& nodes);

/// Tension T (N) of a strand of length `length` and, with `slope`, dT/dL (N/m)
/// (formulas above; toe_strain 0: k_t (L - L0) for L > L0).
double tendon_tension(double length, double natural_length, double k_t, double toe_strain = 0.0,
                      double* slope = nullptr);

/// Adds the strand's forces to f (3 x N) and returns its tension T (N, >= 0).
double add_tendon_forces(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t,
                         Points& f, double toe_strain = 0.0);

/// The strand's elastic energy (J).
double tendon_energy(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t,
                     double toe_strain = 0.0);

/// The energy of a strand of current length `length` (J): k_t (L - L0)^2 / 2
/// for L > L0, else 0 (with a toe: the formula above).
double tendon_energy_at_length(double length, double natural_length, double k_t, double toe_strain = 0.0);

}  // namespace msd
