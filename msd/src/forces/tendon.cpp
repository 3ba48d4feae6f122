#include "msd/forces/tendon.hpp"

#include <cmath>
#include <string>

namespace msd {

double tendon_stiffness(double youngs_modulus, double area, double natural_length) {
  if (!(youngs_modulus > 0.0) || !(area > 0.0) || !(natural_length > 0.0) || !std::isfinite(youngs_modulus) ||
      !std::isfinite(area) || !std::isfinite(natural_length))
    throw Error("tendon: modulus (" + std::to_string(youngs_modulus) + " Pa), cross-section (" +
                std::to_string(area) + " m^2) and natural length (" + std::to_string(natural_length) +
                " m) must all be positive");
  return youngs_modulus * area / natural_length;
}

double strand_length(const Points& x, const std::vector<int>& nodes) {
  double l = 0.0;
  for (size_t i = 0; i + 1 < nodes.size(); ++i) l += (x.col(nodes[i + 1]) - x.col(nodes[i])).norm();
  return l;
}

double tendon_tension(double length, double natural_length, double k_t, double toe, double* slope) {
  const double stretch = length - natural_length;
  if (!(stretch > 0.0)) {
    if (slope) *slope = 0.0;
    return 0.0;
  }
  const double e = stretch / natural_length;
  if (e >= toe) {
    if (slope) *slope = k_t;
    return k_t * (stretch - 0.5 * toe * natural_length);  // toe 0: k_t (L - L0), the thesis' bits
  }
  if (slope) *slope = k_t * e / toe;
  return k_t * natural_length * e * e / (2.0 * toe);
}

double add_tendon_forces(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t,
                         Points& f, double toe) {
  if (nodes.size() < 2) return 0.0;
  const double t = tendon_tension(strand_length(x, nodes), natural_length, k_t, toe);
  if (t <= 0.0) return 0.0;
  for (size_t i = 0; i + 1 < nodes.size(); ++i) {
    const Vec3 d = x.col(nodes[i + 1]) - x.col(nodes[i]);
    const double len = d.norm();
    if (len <= 0.0) continue;  // coincident nodes: no direction, no force
    const Vec3 pull = (t / len) * d;
    f.col(nodes[i]) += pull;
    f.col(nodes[i + 1]) -= pull;
  }
  return t;
}

double tendon_energy_at_length(double length, double natural_length, double k_t, double toe) {
  const double stretch = length - natural_length;
  if (!(stretch > 0.0)) return 0.0;
  const double e = stretch / natural_length, l2 = k_t * natural_length * natural_length;
  if (e < toe) return l2 * e * e * e / (6.0 * toe);
  return l2 * (toe * toe / 6.0 + 0.5 * (e * e - toe * toe) - 0.5 * toe * (e - toe));
}

double tendon_energy(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t, double toe) {
  return tendon_energy_at_length(strand_length(x, nodes), natural_length, k_t, toe);
}

}  // namespace msd
