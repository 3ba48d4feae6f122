#include "msd/experiments/uniaxial.hpp"

#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

namespace {

struct Rig {
  msd::SampleMesh sample;
  msd::UniaxialSetup setup;
  msd::Model model;
};

Rig rig(msd::PlatenContact contact, unsigned terms = msd::kSprings | msd::kDampers) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  Rig r;
  r.sample = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.02, 0.03, 0.05)), o, "box");
  msd::ModelOptions mo;
  mo.terms = terms;
  msd::TissueMaterial m;
  m.mode = msd::ConstantsMode::Physical;
  m.density = 1000;
  m.youngs_modulus = 1e4;
  m.damping_time = 0.002;
  mo.region_materials = {m};
  r.setup = msd::add_platens(r.sample.mesh, contact, mo);
  r.model = msd::build_model(r.sample.mesh, mo);
  return r;
}

}  // namespace

TEST(Uniaxial, PlatensCoverTopAndBottomFaces) {
  const Rig r = rig(msd::PlatenContact::Bonded);
  EXPECT_DOUBLE_EQ(r.setup.length, 0.05);
  EXPECT_NEAR(r.setup.area, 0.02 * 0.03, 1e-15);
  EXPECT_NEAR(r.setup.volume, 0.02 * 0.03 * 0.05, 1e-15);
  EXPECT_EQ(r.model.groups[r.setup.bottom_group].nodes.size(), 3u * 4u);
  EXPECT_EQ(r.model.groups[r.setup.top_group].nodes.size(), 3u * 4u);
  const Rig f = rig(msd::PlatenContact::Frictionless);
  EXPECT_FALSE(f.model.groups[f.setup.top_group].axes[0]);
  EXPECT_TRUE(f.model.groups[f.setup.top_group].axes[2]);
}

TEST(Uniaxial, ControlsMoveTheTopPlatenAlongThePath) {
  const Rig r = rig(msd::PlatenContact::Bonded);
  const msd::LoadingPath p({{0, 0}, {1, 0.2}}, "p");
  const msd::Controls c = msd::uniaxial_controls(r.model, r.setup, p, 0.5);
  EXPECT_DOUBLE_EQ(c.group_offset[r.setup.top_group].z(), 0.1 * 0.05);
  EXPECT_DOUBLE_EQ(c.group_velocity[r.setup.top_group].z(), 0.2 * 0.05);
  EXPECT_EQ(c.group_offset[r.setup.bottom_group].norm(), 0.0);
}

TEST(Uniaxial, RestSampleMeasuresZero) {
  const Rig r = rig(msd::PlatenContact::Bonded);
  msd::Scratch scratch;
  const auto s = msd::measure_uniaxial(r.model, r.setup, msd::rest_state(r.model), scratch);
  EXPECT_NEAR(s.strain, 0.0, 1e-15);
  EXPECT_NEAR(s.nominal_stress, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.volume_ratio, 1.0);
  EXPECT_EQ(s.inverted_elements, 0);
}

TEST(Uniaxial, StressHasTheSignOfTheStrainAndSamplesArrive) {
  const Rig r = rig(msd::PlatenContact::Bonded);
  const msd::LoadingPath p({{0, 0}, {0.2, 0.02}, {0.4, -0.02}}, "p");
  msd::TimeSteppingOptions o;
  o.dt = 1e-4;
  o.output_interval = 0.05;
  std::vector<msd::UniaxialSample> samples;
  const auto stats = msd::run_uniaxial(r.model, r.setup, p, o, [&](const msd::UniaxialSample& s, const msd::State&) {
    samples.push_back(s);
    return true;
  });
  EXPECT_EQ(stats.steps, 4000);
  ASSERT_EQ(samples.size(), 9u);  // t = 0, 0.05, ..., 0.4
  EXPECT_NEAR(samples[4].strain, 0.02, 1e-12);
  EXPECT_GT(samples[4].nominal_stress, 0.0);
  EXPECT_NEAR(samples.back().strain, -0.02, 1e-12);
  EXPECT_LT(samples.back().nominal_stress, 0.0);
  EXPECT_NEAR(samples.back().time, 0.4, 1e-12);
}

TEST(Uniaxial, CallbackCanStopTheRun) {
  const Rig r = rig(msd::PlatenContact::Bonded);
  msd::TimeSteppingOptions o;
  o.dt = 1e-4;
  o.output_interval = 0.01;
  int n = 0;
  msd::run_uniaxial(r.model, r.setup, msd::LoadingPath({{0, 0}, {1, 0.1}}, "p"), o,
                    [&](const msd::UniaxialSample&, const msd::State&) { return ++n < 3; });
  EXPECT_EQ(n, 3);
}

TEST(Uniaxial, BlowUpIsDetectedWithTimeAndNode) {
  const Rig r = rig(msd::PlatenContact::Bonded);
  msd::TimeSteppingOptions o;
  o.dt = 5e-3;  // far beyond the stable step of this stiff little sample
  o.integrator = msd::Integrator::ExplicitEuler;
  o.output_interval = 0.01;
  try {
    msd::run_uniaxial(r.model, r.setup, msd::LoadingPath({{0, 0}, {5, 0.1}}, "p"), o,
                      [](const msd::UniaxialSample&, const msd::State&) { return true; });
    FAIL() << "expected a blow-up";
  } catch (const msd::SimulationFailure& f) {
    EXPECT_GT(f.time, 0.0);
    EXPECT_GT(f.step, 0);
    const std::string what = f.what();
    EXPECT_TRUE(what.find("blow-up") != std::string::npos || what.find("non-finite") != std::string::npos) << what;
  }
}

TEST(Uniaxial, ContactNames) {
  EXPECT_EQ(msd::parse_platen_contact("bonded"), msd::PlatenContact::Bonded);
  EXPECT_EQ(msd::parse_platen_contact("frictionless"), msd::PlatenContact::Frictionless);
  EXPECT_THROW(msd::parse_platen_contact("glued"), msd::Error);
}
