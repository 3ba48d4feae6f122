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
#pragma once

#include "msd/core/types.hpp"

#include <vector>

namespace msd {

/// Strand stiffness E A / L0 (N/m). Throws msd::Error unless all are positive.
double tendon_stiffness(double youngs_modulus, double area, double natural_length);

/// Current length of the strand through `nodes` at positions x (3 x N).
double strand_length(const Points& x, const std::vector<int>& nodes);

/// Adds the strand's forces to f (3 x N) and returns its tension T (N, >= 0).
double add_tendon_forces(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t,
                         Points& f);

/// The strand's elastic energy (J).
double tendon_energy(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t);

/// The energy of a strand of current length `length` (J): k_t (L - L0)^2 / 2 for L > L0, else 0.
double tendon_energy_at_length(double length, double natural_length, double k_t);

}  // namespace msd
