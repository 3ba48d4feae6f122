#include "msd/forces/element_forces.hpp"

#include "msd/forces/bulk_volume.hpp"
#include "msd/forces/edge_dampers.hpp"
#include "msd/forces/edge_springs.hpp"
#include "msd/forces/face_repulsion.hpp"
#include "msd/forces/force_engine.hpp"
#include "msd/forces/stable_neo_hookean.hpp"
#include "msd/forces/volume_preservation.hpp"
#include "msd/mesh/tet_mesh.hpp"

#include <vector>

#include <algorithm>

namespace msd {

namespace {

// Forces of element t; returns whether its non-linear terms ran.
inline bool one_element(const Model& model, size_t t, const Vec3 x[4], const Vec3 v[4],
                        const std::vector<double>& group_pressure, Vec3 f[4]) {
  const Element& el = model.elements[t];
  const unsigned terms = model.terms;
  if (terms & (kSprings | kDampers)) {
    const EdgeFrame edges = edge_frame(x);
    if (terms & kSprings) {
      if (model.plan.edge_law_m.empty())
        add_edge_springs(edges, el.rest_length, el.k.k_s, f);
      else
        add_edge_springs(edges, el.rest_length, el.k.k_s, el.edge_class,
                         model.region_materials[static_cast<size_t>(el.region)].edge_laws, f);
    }
    if (terms & kDampers) add_edge_dampers(edges, v, el.k.k_d, f);
  }
  if (terms & kNeoHookean) add_continuum_element_forces(model, t, x, group_pressure, f);
  if (terms & kBulk) add_bulk_forces(x, group_pressure[static_cast<size_t>(model.volume_groups.of_tet[t])], f);
  if (!(terms & (kRepulsion | kVolume))) return false;
  return add_nonlinear_element_forces(model, el, x, f);
}

}  // namespace

bool nonlinear_terms_active(const Element& el, double threshold, const Vec3 x[4]) {
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  const Vec3 m1 = e2.cross(e3), m2 = e3.cross(e1), m3 = e1.cross(e2);
  const Vec3 m0 = -(m1 + m2 + m3);
  const double six_v = e1.dot(m1);
  if (!(six_v > 0.0)) return true;
  const double s2 = six_v * six_v;
  const double c0 = threshold * el.rest_height[0], c1 = threshold * el.rest_height[1];
  const double c2 = threshold * el.rest_height[2], c3 = threshold * el.rest_height[3];
  return s2 < c0 * c0 * m0.squaredNorm() || s2 < c1 * c1 * m1.squaredNorm() || s2 < c2 * c2 * m2.squaredNorm() ||
         s2 < c3 * c3 * m3.squaredNorm();
}

bool add_nonlinear_element_forces(const Model& model, const Element& el, const Vec3 x[4], Vec3 f[4]) {
  const unsigned terms = model.terms;
  if (model.nonlinear_threshold > 0.0 && !nonlinear_terms_active(el, model.nonlinear_threshold, x)) return false;
  const TetFrame g = tet_frame(x);
  // Both terms push along the same face normal with the same equalising
  // weights, so their magnitudes are summed before the forces are applied.
  double mag[4];
  for (int i = 0; i < 4; ++i) {
    mag[i] = 0.0;
    if (terms & kRepulsion)
      mag[i] += face_repulsion_magnitude(g.height[i], el.rest_height[i], el.k.k_r[i], el.floor);
    if (terms & kVolume) mag[i] += volume_force_magnitude(g, i, el.rest_volume, el.k.k_v[i]);
  }
  add_balanced_normal_forces(g, mag, f);
  return true;
}

namespace {

// The bulk term's volume ratio of group g: the sum of its tets' signed
// volumes over its rest volume.
double bulk_group_ratio(const Model& model, int g, const Points& x) {
  const VolumeGroups& G = model.volume_groups;
  double volume = 0.0;
  for (int q = G.tet_offset[static_cast<size_t>(g)]; q < G.tet_offset[static_cast<size_t>(g) + 1]; ++q) {
    const Element& el = model.elements[static_cast<size_t>(G.tets[static_cast<size_t>(q)])];
    Vec3 xe[4];
    for (int i = 0; i < 4; ++i) xe[i] = x.col(el.nodes[static_cast<size_t>(i)]);
    volume += tet_signed_volume(xe[0], xe[1], xe[2], xe[3]);
  }
  return volume / G.rest_volume[static_cast<size_t>(g)];
}

}  // namespace

double volume_group_pressure(const Model& model, int g, const Points& x) {
  const VolumeGroups& G = model.volume_groups;
  if (model.terms & kBulk)
    return bulk_law_pressure(G.bulk_law[static_cast<size_t>(g)], bulk_group_ratio(model, g, x));
  double volume = 0.0;
  for (int q = G.tet_offset[static_cast<size_t>(g)]; q < G.tet_offset[static_cast<size_t>(g) + 1]; ++q) {
    const size_t t = static_cast<size_t>(G.tets[static_cast<size_t>(q)]);
    const Element& el = model.elements[t];
    Vec3 xe[4];
    for (int i = 0; i < 4; ++i) xe[i] = x.col(el.nodes[static_cast<size_t>(i)]);
    volume += el.rest_volume * deformation_gradient(xe, model.continuum.dm_inv[t]).determinant();
  }
  const size_t first = static_cast<size_t>(G.tets[static_cast<size_t>(G.tet_offset[static_cast<size_t>(g)])]);
  return snh_pressure(volume / G.rest_volume[static_cast<size_t>(g)], model.continuum.constants[first]);
}

void add_continuum_element_forces(const Model& model, size_t t, const Vec3 x[4],
                                  const std::vector<double>& group_pressure, Vec3 f[4]) {
  const double v0 = model.elements[t].rest_volume;
  const Mat3& dm_inv = model.continuum.dm_inv[t];
  const SnhConstants& c = model.continuum.constants[t];
  if (model.volume_groups.empty())
    add_snh_forces(x, dm_inv, v0, c, f);
  else
    add_snh_forces_at_pressure(x, dm_inv, v0, c,
                               group_pressure[static_cast<size_t>(model.volume_groups.of_tet[t])], f);
}

long compute_internal_forces_reference(const Model& model, const Points& x, const Points& v, Points& f) {
  f.setZero(3, x.cols());
  long active = 0;
  std::vector<double> pressure(static_cast<size_t>(model.volume_groups.size()));
  if (model.terms & (kNeoHookean | kBulk))
    for (int g = 0; g < model.volume_groups.size(); ++g) pressure[static_cast<size_t>(g)] = volume_group_pressure(model, g, x);
  for (size_t t = 0; t < model.elements.size(); ++t) {
    const Element& el = model.elements[t];
    Vec3 xe[4], ve[4], fe[4];
    for (int i = 0; i < 4; ++i) {
      xe[i] = x.col(el.nodes[i]);
      ve[i] = v.col(el.nodes[i]);
      fe[i].setZero();
    }
    active += one_element(model, t, xe, ve, pressure, fe);
    for (int i = 0; i < 4; ++i) f.col(el.nodes[i]) += fe[i];
  }
  return active;
}

long compute_internal_forces(const Model& model, const Points& x, const Points& v, Points& f) {
  Scratch buffers;
  return compute_forces_fast(model, x, v, f, buffers);
}

void element_forces(const Model& model, int e, const Points& x, const Points& v, Vec3 f[4]) {
  const Element& el = model.elements.at(static_cast<size_t>(e));
  Vec3 xe[4], ve[4];
  for (int i = 0; i < 4; ++i) {
    xe[i] = x.col(el.nodes[i]);
    ve[i] = v.col(el.nodes[i]);
    f[i].setZero();
  }
  std::vector<double> pressure(static_cast<size_t>(model.volume_groups.size()), 0.0);
  if ((model.terms & (kNeoHookean | kBulk)) && !model.volume_groups.empty()) {
    const int g = model.volume_groups.of_tet[static_cast<size_t>(e)];
    pressure[static_cast<size_t>(g)] = volume_group_pressure(model, g, x);
  }
  one_element(model, static_cast<size_t>(e), xe, ve, pressure, f);
}

double conservative_energy(const Model& model, const Points& x) {
  double u = 0.0;
  for (size_t t = 0; t < model.elements.size(); ++t) {
    const Element& el = model.elements[t];
    Vec3 xe[4];
    for (int i = 0; i < 4; ++i) xe[i] = x.col(el.nodes[i]);
    if (model.terms & kSprings)
      u += model.plan.edge_law_m.empty()
               ? edge_spring_energy(xe, el.rest_length, el.k.k_s)
               : edge_spring_energy(xe, el.rest_length, el.k.k_s, el.edge_class,
                                    model.region_materials[static_cast<size_t>(el.region)].edge_laws);
    if (model.terms & kRepulsion)
      u += face_repulsion_energy(tet_frame(xe), el.rest_height, el.k.k_r, el.floor);
    if (model.terms & kNeoHookean)
      u += model.volume_groups.empty()
               ? snh_element_energy(xe, model.continuum.dm_inv[t], el.rest_volume, model.continuum.constants[t])
               : el.rest_volume * snh_shear_energy_density(deformation_gradient(xe, model.continuum.dm_inv[t]),
                                                           model.continuum.constants[t]);
  }
  // The groups' volume terms, V0_g lambda/2 (Jbar_g - alpha)^2 = V0_g p_g^2 / (2 lambda).
  if (model.terms & kNeoHookean)
    for (int g = 0; g < model.volume_groups.size(); ++g) {
      const VolumeGroups& G = model.volume_groups;
      const double lambda = model.continuum.constants[static_cast<size_t>(G.tets[static_cast<size_t>(G.tet_offset[static_cast<size_t>(g)])])].lambda;
      const double p = volume_group_pressure(model, g, x);
      u += G.rest_volume[static_cast<size_t>(g)] * p * p / (2.0 * lambda);
    }
  // The bulk term's, V0_g W(Jbar_g) (bulk_volume.hpp).
  if (model.terms & kBulk)
    for (int g = 0; g < model.volume_groups.size(); ++g)
      u += model.volume_groups.rest_volume[static_cast<size_t>(g)] *
           bulk_law_energy(model.volume_groups.bulk_law[static_cast<size_t>(g)], bulk_group_ratio(model, g, x));
  return u;
}

double kinetic_energy(const Model& model, const Points& v) {
  return 0.5 * (v.colwise().squaredNorm().transpose().cwiseProduct(model.mass)).sum();
}

}  // namespace msd
