#include "msd/forces/muscle_units.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
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

std::vector<int> fibre_end_nodes(const Points& x, const std::vector<ContractileUnit>& units, const Vec3& direction,
                                 int side) {
  if (!(direction.norm() > 0.0) || !direction.allFinite()) throw Error("muscle: the line of action must be a nonzero vector");
  if (side != 1 && side != -1) throw Error("muscle: a fibre end's side must be +1 or -1");
  const Vec3 d = static_cast<double>(side) * direction.normalized();
  // Per node: whether a unit leaves it along +d (onward) and against it (back).
  std::map<int, std::pair<bool, bool>> at;
  for (const ContractileUnit& u : units) {
    const double s = (x.col(u.b) - x.col(u.a)).dot(d);
    if (s == 0.0) continue;  // across the line of action: neither way (not a unit within 90 degrees)
    const int ahead = s > 0.0 ? u.b : u.a, behind = s > 0.0 ? u.a : u.b;
    at[behind].first = true;
    at[ahead].second = true;
  }
  std::vector<int> ends;
  for (const auto& [node, ways] : at)
    if (ways.second && !ways.first) ends.push_back(node);
  return ends;
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

double unit_force_for_area(const TetMesh& mesh, int region, const std::vector<ContractileUnit>& units,
                           const Vec3& direction, double activation, double max_stress, double area) {
  if (!(area > 0.0) || !std::isfinite(area))
    throw Error("muscle: the cross-section " + std::to_string(area) + " m^2 must be positive");
  if (units.empty()) return 0.0;
  const Vec3 d = direction.normalized();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, lambda = 0.0;
  for (size_t e = 0; e < mesh.tets.size(); ++e)
    if (mesh.region[e] == region)
      for (int n : mesh.tets[e]) {
        const double s = mesh.nodes.col(n).dot(d);
        lo = std::min(lo, s);
        hi = std::max(hi, s);
      }
  for (const auto& u : units) lambda += std::abs((mesh.nodes.col(u.b) - mesh.nodes.col(u.a)).dot(d));
  return activation * max_stress * area * (hi - lo) / lambda;
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

namespace msd {

namespace {
std::string num(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}
}  // namespace

void check_hill_muscle(const HillMuscle& h, const std::string& where) {
  auto need = [&](bool ok, const char* field, const char* rule, double value) {
    if (!ok) throw Error(where + "." + field + " " + rule + ", got " + num(value));
  };
  need(h.rest_fibre_stretch > 0.0 && std::isfinite(h.rest_fibre_stretch), "rest_fibre_stretch", "must be positive",
       h.rest_fibre_stretch);
  need(h.active_width > 0.0 && h.active_width < 1.0, "active_width",
       "must lie in (0, 1) (the active force-length curve is zero at 1 +- width)", h.active_width);
  need(h.passive_strain > 0.0 && std::isfinite(h.passive_strain), "passive_strain", "must be positive", h.passive_strain);
  need(h.passive_shape > 0.0 && h.passive_shape < 50.0, "passive_shape", "must lie in (0, 50)", h.passive_shape);
  need(h.max_velocity > 0.0 && std::isfinite(h.max_velocity), "max_velocity", "must be positive", h.max_velocity);
  need(h.curvature > 0.0 && std::isfinite(h.curvature), "curvature", "must be positive", h.curvature);
  need(h.eccentric_max > 1.0 && std::isfinite(h.eccentric_max), "eccentric_max", "must exceed 1", h.eccentric_max);
  need(h.eccentric_slope_ratio > 0.0 && std::isfinite(h.eccentric_slope_ratio), "eccentric_slope_ratio",
       "must be positive", h.eccentric_slope_ratio);
}

double hill_active_force_length(double lt, double width, double* slope) {
  const double s = (lt - 1.0) / width;
  if (std::abs(s) >= 1.0) {
    if (slope) *slope = 0.0;
    return 0.0;
  }
  if (slope) *slope = -2.0 * s / width;
  return 1.0 - s * s;
}

double hill_passive_force_length(double lt, double strain, double shape, double* slope) {
  if (lt <= 1.0) {
    if (slope) *slope = 0.0;
    return 0.0;
  }
  const double scale = 1.0 / std::expm1(shape), e = std::exp(shape * (lt - 1.0) / strain);
  if (slope) *slope = scale * e * shape / strain;
  return scale * (e - 1.0);
}

double hill_force_velocity(double vt, const HillMuscle& h, double* slope) {
  if (!h.force_velocity) {
    if (slope) *slope = 0.0;
    return 1.0;
  }
  if (vt <= -1.0) {
    if (slope) *slope = 0.0;
    return 0.0;
  }
  const double A = h.curvature;
  if (vt < 0.0) {
    const double den = 1.0 - vt / A;
    if (slope) *slope = (den + (1.0 + vt) / A) / (den * den);
    return (1.0 + vt) / den;
  }
  const double fe = h.eccentric_max, c = h.eccentric_slope_ratio * (1.0 + 1.0 / A) / (fe - 1.0);
  const double den = 1.0 + c * vt;
  if (slope) *slope = (fe - 1.0) * c / (den * den);
  return fe - (fe - 1.0) / den;
}

UnitTension hill_unit_tension(double length, double rate, double rest_length, double activation, double unit_force,
                              const HillMuscle& h) {
  const double lo = rest_length / h.rest_fibre_stretch;
  const double lt = length / lo, vt = rate / (lo * h.max_velocity);
  double dA = 0.0, dP = 0.0, dV = 0.0;
  const double fA = hill_active_force_length(lt, h.active_width, &dA);
  const double fP = hill_passive_force_length(lt, h.passive_strain, h.passive_shape, &dP);
  const double fV = hill_force_velocity(vt, h, &dV);
  UnitTension t;
  t.T = unit_force * (activation * fA * fV + fP);
  t.dT_dlength = unit_force * (activation * dA * fV + dP) / lo;
  t.dT_drate = unit_force * activation * fA * dV / (lo * h.max_velocity);
  return t;
}

double hill_passive_energy(double length, double rest_length, double unit_force, const HillMuscle& h) {
  const double lo = rest_length / h.rest_fibre_stretch, lt = length / lo;
  if (lt <= 1.0) return 0.0;
  const double k = h.passive_shape, e0 = h.passive_strain;
  return unit_force * lo * ((e0 / k) * std::expm1(k * (lt - 1.0) / e0) - (lt - 1.0)) / std::expm1(k);
}

double hill_muscle_passive_energy(const Points& x, const std::vector<ContractileUnit>& units, double unit_force,
                                  const HillMuscle& hill) {
  double e = 0.0;
  for (const auto& u : units) e += hill_passive_energy((x.col(u.b) - x.col(u.a)).norm(), u.rest_length, unit_force, hill);
  return e;
}

void add_hill_muscle_forces(const Points& x, const Points& v, const std::vector<ContractileUnit>& units,
                            double unit_force, double activation, const HillMuscle& hill, Points& f) {
  for (const auto& u : units) {
    const Vec3 l = x.col(u.b) - x.col(u.a);
    const double len = l.norm();
    if (!(len > 0.0)) continue;  // coincident nodes: no direction, no force
    const double rate = l.dot(v.col(u.b) - v.col(u.a)) / len;
    const double T = hill_unit_tension(len, rate, u.rest_length, activation, unit_force, hill).T;
    if (T == 0.0) continue;
    const Vec3 pull = (T / len) * l;
    f.col(u.a) += pull;
    f.col(u.b) -= pull;
  }
}

double activation_step(double a, double u, double dt, double tau_a, double tau_d) {
  if (!(u >= 0.0 && u <= 1.0)) throw Error("muscle: an excitation must lie in [0, 1], got " + num(u));
  if (!(tau_a >= 0.0) || !(tau_d >= 0.0) || !(dt >= 0.0))
    throw Error("muscle: activation and deactivation times and the step must be >= 0");
  const double tau = u > a ? tau_a : tau_d;
  if (tau == 0.0) return u;
  return u + (a - u) * std::exp(-dt / tau);
}

}  // namespace msd
