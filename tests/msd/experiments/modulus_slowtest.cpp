// Physical constants (Van Gelder form with the five-tet lattice factor): the
// small-strain modulus of a sample between frictionless platens is E, and does
// not depend on the mesh spacing h.
#include "msd/experiments/uniaxial.hpp"
#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

struct Measured {
  double modulus;      // sigma / eps at eps = 0.01
  double volume_rate;  // (V/V0 - 1) / eps = 1 - 2 nu for small strain
};

Measured measure(double h) {
  msd::SampleMeshOptions o;
  o.spacing = h;
  const auto sample = msd::mesh_closed_surface(
      msd::make_box(msd::Vec3::Zero(), msd::Vec3(0.04, 0.04, 0.08)), o, "box");
  msd::ModelOptions mo;
  mo.terms = msd::kSprings | msd::kDampers;
  msd::TissueMaterial m;
  m.mode = msd::ConstantsMode::Physical;
  m.density = 1000;
  m.youngs_modulus = 1e4;
  m.damping_time = 0.002;
  mo.region_materials = {m};
  const auto setup = msd::add_platens(sample.mesh, msd::PlatenContact::Frictionless, mo);
  const msd::Model model = msd::build_model(sample.mesh, mo);
  msd::TimeSteppingOptions t;
  t.dt = 1e-4;
  t.output_interval = 0.01;
  msd::UniaxialSample last;
  // Slow ramp to 1 % strain, then hold so the last oscillations damp out.
  msd::run_uniaxial(model, setup, msd::LoadingPath({{0, 0}, {1.0, 0.01}, {1.5, 0.01}}, "ramp"), t,
                    [&](const msd::UniaxialSample& s, const msd::State&) {
                      last = s;
                      return true;
                    });
  return {last.nominal_stress / last.strain, (last.volume_ratio - 1.0) / last.strain};
}

}  // namespace

TEST(Modulus, SmallStrainModulusIsEAndIndependentOfSpacing) {
  const double E = 1e4;
  const Measured coarse = measure(0.02), mid = measure(0.01), fine = measure(0.005);
  for (const Measured& m : {coarse, mid, fine}) {
    EXPECT_NEAR(m.modulus / E, 1.0, 0.03) << m.modulus;
    EXPECT_NEAR(m.volume_rate, 0.6, 0.1) << m.volume_rate;
  }
  // The lattice's Poisson ratio is 0.2 (Cauchy-Born), so 1 - 2 nu = 0.6; free
  // surfaces relax the coarse samples a little (0.66 at h = 2 cm).
  EXPECT_NEAR(fine.volume_rate, 0.6, 0.03) << fine.volume_rate;
  const double lo = std::min({coarse.modulus, mid.modulus, fine.modulus});
  const double hi = std::max({coarse.modulus, mid.modulus, fine.modulus});
  EXPECT_LT((hi - lo) / E, 0.03);
  // And it converges towards E from below as h shrinks (surface relaxation).
  EXPECT_LT(coarse.modulus, mid.modulus);
  EXPECT_LT(mid.modulus, fine.modulus);
}
