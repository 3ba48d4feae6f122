#include "msd/forces/muscle_units.hpp"

#include <cmath>
#include <set>
#include <string>

namespace msd {

std::vector<ContractileUnit> contractile_units(const TetMesh& mesh, int region, const Vec3& direction,
                                               double max_angle_deg) {
  if (!(direction.norm() > 0.0) || !direction.allFinite()) throw Error("muscle: the line of action must be a nonzero vector");
  if (!(max_angle_deg > 0.0 && max_angle_deg < 90.0))
    throw Error("muscle: the angle tolerance must lie between 0 and 90 degrees, got " + std::to_string(max_angle_deg));
  const Vec3 d = direction.normalized();
  const double cos_min = std::cos(max_angle_deg * M_PI / 180.0);
  std::set<std::pair<int, int>> seen;
  std::vector<ContractileUnit> units;
  for (size_t e = 0; e < mesh.tets.size(); ++e) {
    if (mesh.region[e] != region) continue;
    for (const auto& edge : kTetEdges) {
      int a = mesh.tets[e][static_cast<size_t>(edge[0])], b = mesh.tets[e][static_cast<size_t>(edge[1])];
      if (a > b) std::swap(a, b);
      if (!seen.insert({a, b}).second) continue;
      const Vec3 l = mesh.nodes.col(b) - mesh.nodes.col(a);
      if (std::abs(l.dot(d)) >= cos_min * l.norm()) units.push_back({a, b, l.norm()});
    }
  }
  return units;
}

double unit_force(const TetMesh& mesh, int region, const std::vector<ContractileUnit>& units, const Vec3& direction,
                  double activation, double max_stress) {
  if (units.empty()) return 0.0;
  const Vec3 d = direction.normalized();
  double volume = 0.0, lambda = 0.0;
  for (size_t e = 0; e < mesh.tets.size(); ++e)
    if (mesh.region[e] == region) volume += tet_signed_volume(mesh.nodes, mesh.tets[e]);
  for (const auto& u : units) lambda += std::abs((mesh.nodes.col(u.b) - mesh.nodes.col(u.a)).dot(d));
  return activation * max_stress * volume / lambda;
}

double force_length_factor(double stretch, double zero_at) {
  if (zero_at < 0.0 || stretch >= 1.0) return 1.0;
  if (stretch <= zero_at) return 0.0;
  const double s = (1.0 - stretch) / (1.0 - zero_at);
  return 1.0 - s * s;
}

void add_muscle_forces(const Points& x, const std::vector<ContractileUnit>& units, double force, Points& f,
                       const ForceLength& fl) {
  if (force == 0.0) return;
  if (fl.enabled && !(fl.zero_at >= 0.0 && fl.zero_at < 1.0))
    throw Error("muscle: the force-length relation's zero stretch must lie in [0, 1), got " + std::to_string(fl.zero_at));
  for (const auto& u : units) {
    const Vec3 l = x.col(u.b) - x.col(u.a);
    const double len = l.norm();
    if (len <= 0.0) continue;
    const double scale = fl.enabled ? force_length_factor(len / u.rest_length, fl.zero_at) : 1.0;
    if (scale == 0.0) continue;
    const Vec3 pull = (scale * force / len) * l;  // a pulled towards b, b towards a
    f.col(u.a) += pull;
    f.col(u.b) -= pull;
  }
}

}  // namespace msd
