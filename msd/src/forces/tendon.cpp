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

double add_tendon_forces(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t,
                         Points& f) {
  const double stretch = strand_length(x, nodes) - natural_length;
  if (stretch <= 0.0 || nodes.size() < 2) return 0.0;
  const double t = k_t * stretch;
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

double tendon_energy_at_length(double length, double natural_length, double k_t) {
  const double stretch = length - natural_length;
  return stretch > 0.0 ? 0.5 * k_t * stretch * stretch : 0.0;
}

double tendon_energy(const Points& x, const std::vector<int>& nodes, double natural_length, double k_t) {
  return tendon_energy_at_length(strand_length(x, nodes), natural_length, k_t);
}

}  // namespace msd
