#include "msd/material/tissue_material.hpp"

#include <cmath>

namespace msd {

namespace {

void require(bool ok, const std::string& where, const std::string& field, const std::string& rule,
             double value) {
  if (!ok)
    throw Error(where + ": " + field + " must be " + rule + " (got " + std::to_string(value) + ")");
}

}  // namespace

void check_material(const TissueMaterial& m, const std::string& where) {
  auto finite_nonneg = [&](double v, const char* f) {
    require(std::isfinite(v) && v >= 0.0, where, f, "finite and >= 0", v);
  };
  require(std::isfinite(m.density) && m.density > 0.0, where, "density", "positive (kg/m^3)",
          m.density);
  require(std::isfinite(m.repulsion_floor) && m.repulsion_floor > 0.0 && m.repulsion_floor < 1.0,
          where, "repulsion_floor", "in (0, 1)", m.repulsion_floor);
  if (m.mode == ConstantsMode::Raw) {
    require(std::isfinite(m.k_s) && m.k_s > 0.0, where, "k_s", "positive (N/m)", m.k_s);
    finite_nonneg(m.k_d, "k_d");
    finite_nonneg(m.k_r, "k_r");
    finite_nonneg(m.k_v, "k_v");
  } else {
    require(std::isfinite(m.youngs_modulus) && m.youngs_modulus > 0.0, where, "youngs_modulus",
            "positive (Pa)", m.youngs_modulus);
    require(std::isfinite(m.stiffness_scale) && m.stiffness_scale > 0.0, where, "stiffness_scale",
            "positive", m.stiffness_scale);
    finite_nonneg(m.damping_time, "damping_time");
    finite_nonneg(m.repulsion_factor, "repulsion_factor");
    finite_nonneg(m.volume_factor, "volume_factor");
    require(std::isfinite(m.bulk_factor) && m.bulk_factor > 0.0, where, "bulk_factor", "positive", m.bulk_factor);
    if (m.poisson_ratio)
      require(*m.poisson_ratio > -1.0 && *m.poisson_ratio < 0.5, where, "poisson_ratio", "in (-1, 0.5)", *m.poisson_ratio);
  }
  if (m.zero_length_springs && !m.thesis_springs())
    throw Error(where + ": zero_length_springs: the springs' weights are the cotangent weights; edge classes "
                "(a factor or a law per class) do not apply to them");
  for (int c = 0; c < kEdgeClasses; ++c)
    check_spring_law(m.edge_laws[static_cast<size_t>(c)],
                     where + ": edge_classes." + to_string(static_cast<EdgeClass>(c)));
}

BulkLaw lattice_bulk_law(const TissueMaterial& m, const std::string& where) {
  if (m.mode != ConstantsMode::Physical || !m.poisson_ratio)
    throw Error(where + ": the bulk term needs physical constants with a Poisson's ratio (youngs_modulus, poisson_ratio)");
  const double nu = *m.poisson_ratio;
  const double e = m.youngs_modulus;
  const double lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), mu = e / (2.0 * (1.0 + nu));
  BulkLaw law;
  if (m.zero_length_springs) {
    require(nu > 0.0, where, "poisson_ratio", "above 0 for the bulk term with zero-length springs (lambda > 0)", nu);
    law.neo_hookean = true;
    law.modulus = m.bulk_factor * m.stiffness_scale * lambda;
    law.rest_modulus = m.stiffness_scale * mu;
  } else {
    require(nu > 0.25, where, "poisson_ratio", "above 0.25 for the bulk term (springs alone have nu = 1/4)", nu);
    law.modulus = m.bulk_factor * m.stiffness_scale * (lambda - mu);
  }
  return law;
}

double scaled_shear_modulus(const TissueMaterial& m, const std::string& where, const std::string& what) {
  if (m.mode != ConstantsMode::Physical || !m.poisson_ratio)
    throw Error(where + ": " + what + " need physical constants with a Poisson's ratio (youngs_modulus, poisson_ratio)");
  return m.stiffness_scale * m.youngs_modulus / (2.0 * (1.0 + *m.poisson_ratio));
}

bool TissueMaterial::thesis_springs() const {
  for (const SpringLaw& law : edge_laws)
    if (law.stiffness != 1.0 || !law.linear()) return false;
  return true;
}

ElementConstants element_constants(const TissueMaterial& m, double rest_volume,
                                   const double rest_length[6], const double rest_height[4],
                                   const EdgeClass* edge_class) {
  ElementConstants c{};
  // The class factor; exactly 1 (and so bit-neutral) for the thesis' springs.
  const auto factor = [&](int e) {
    return edge_class ? m.edge_laws[static_cast<size_t>(edge_class[e])].stiffness : 1.0;
  };
  if (m.mode == ConstantsMode::Raw) {
    for (int e = 0; e < 6; ++e) {
      c.k_s[e] = m.k_s * factor(e);
      c.k_d[e] = m.k_d * factor(e);
    }
    for (int i = 0; i < 4; ++i) {
      c.k_r[i] = m.k_r;
      c.k_v[i] = m.k_v;
    }
    return c;
  }
  const double ev = kLatticeStiffnessFactor * m.stiffness_scale * m.youngs_modulus * rest_volume;
  for (int e = 0; e < 6; ++e) {
    c.k_s[e] = factor(e) * ev / (rest_length[e] * rest_length[e]);
    c.k_d[e] = m.damping_time * c.k_s[e];
  }
  for (int i = 0; i < 4; ++i) {
    const double ref = ev / (rest_height[i] * rest_height[i]);
    c.k_r[i] = m.repulsion_factor * ref;
    c.k_v[i] = m.volume_factor * ref;
  }
  return c;
}

}  // namespace msd
