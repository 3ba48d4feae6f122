// The indentation rig: a rigid cylinder pressed into a block bonded at its base.
#include "msd/experiments/indentation.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>

using msd::Vec3;

namespace {

struct Rig {
  msd::SampleMesh sample;
  msd::IndentationSetup setup;
  msd::Model model;
};

Rig rig(msd::ContactResponse response) {
  msd::SampleMeshOptions o;
  o.spacing = 0.005;
  Rig r;
  r.sample = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.04, 0.01, 0.02)), o, "block");
  msd::ModelOptions mo;
  mo.terms = msd::kSprings | msd::kDampers;
  msd::TissueMaterial m;
  m.mode = msd::ConstantsMode::Physical;
  m.density = 1000;
  m.youngs_modulus = 3000;
  m.damping_time = 0.01;
  mo.region_materials = {m};
  msd::IndenterOptions ind;
  ind.radius = 0.01;
  ind.max_depth = 0.004;
  ind.response = response;
  r.setup = msd::add_indenter(r.sample.mesh, ind, mo);
  r.model = msd::build_model(r.sample.mesh, mo);
  return r;
}

struct Curve {
  std::vector<msd::IndentationSample> samples;
  double max_penetration = 0.0;
};

// Presses to the full depth over 1 s and holds 0.5 s.
Curve press(const Rig& r) {
  const msd::LoadingPath path({{0.0, 0.0}, {1.0, 1.0}, {1.5, 1.0}}, "test");
  msd::ExperimentHooks h;
  h.controls = [&](double t) { return msd::indentation_controls(r.model, r.setup, path, t); };
  Curve c;
  h.sample = [&](const msd::State& st, msd::Scratch& sc) {
    c.samples.push_back(msd::measure_indentation(r.model, r.setup, path, st, sc));
    const auto& ob = r.model.obstacles[0];
    for (int n : ob.nodes)
      c.max_penetration = std::max(
          c.max_penetration, msd::cylinder_gap(ob.cylinder, Vec3(0, 0, -c.samples.back().depth), st.x.col(n)).depth);
    return true;
  };
  msd::TimeSteppingOptions ts;
  ts.dt = 2e-4;
  ts.output_interval = 0.05;
  msd::run_experiment(r.model, msd::rest_state(r.model), 1.5, 0.04, ts, h);
  return c;
}

}  // namespace

TEST(Indentation, CylinderStartsTouchingTheTopFaceAboveTheCentre) {
  const Rig r = rig(msd::ContactResponse::Stick);
  const auto& c = r.model.obstacles.at(static_cast<size_t>(r.setup.obstacle)).cylinder;
  EXPECT_NEAR(c.point.x(), 0.02, 1e-15);
  EXPECT_NEAR(c.point.z(), 0.02 + 0.01, 1e-15);
  EXPECT_DOUBLE_EQ(r.setup.height, 0.02);
  const msd::Controls k = msd::indentation_controls(
      r.model, r.setup, msd::LoadingPath({{0.0, 0.0}, {2.0, 1.0}}, "test"), 1.0);
  EXPECT_NEAR(k.obstacle_offset[0].z(), -0.002, 1e-15);
  EXPECT_NEAR(k.obstacle_velocity[0].z(), -0.002, 1e-15);
  msd::Scratch sc;
  const msd::IndentationSample s0 = msd::measure_indentation(
      r.model, r.setup, msd::LoadingPath({{0.0, 0.0}, {1.0, 1.0}}, "test"), msd::rest_state(r.model), sc);
  EXPECT_EQ(s0.force, 0.0);
  EXPECT_EQ(s0.contact_nodes, 0);
}

TEST(Indentation, ForceGrowsWithDepthNoNodeEntersAndTheBaseCarriesTheLoad) {
  const Curve c = press(rig(msd::ContactResponse::Stick));
  EXPECT_LE(c.max_penetration, 1e-12);
  double last = 0.0;
  for (const auto& s : c.samples) {
    if (s.time > 0.1 && s.time <= 1.0 + 1e-9) {
      EXPECT_GT(s.force, 0.0) << "t = " << s.time;
      EXPECT_GT(s.contact_nodes, 0);
    }
    if (s.time >= 0.3 && s.time <= 1.0 + 1e-9) {
      EXPECT_GT(s.force, 0.9 * last) << "t = " << s.time;  // rising (nodes engage one by one)
      last = s.force;
    }
  }
  // Settled at the end of the hold: the reaction constraints at the contact
  // balance the bonded base's reaction (momentum balance - the force is real).
  const auto& end = c.samples.back();
  EXPECT_LT(end.kinetic_energy, 1e-9);
  EXPECT_NEAR(end.force, end.base_reaction, 0.02 * end.base_reaction);
  // Sanity of the magnitude: a bonded 4 x 1 x 2 cm block of E = 3 kPa pressed
  // 4 mm over about its middle third carries order E * strain * area.
  EXPECT_GT(end.force, 3000 * 0.2 * 0.01 * 0.01 * 0.3);
  EXPECT_LT(end.force, 3000 * 0.2 * 0.04 * 0.01 * 3.0);
}

TEST(Indentation, TheThesisResponseActsFrictionlessOnceSettled) {
  // Zeroing a contact node's velocity does not hold it in place: each step the
  // tangential force still moves it by dt^2 a before the radial projection, so
  // the thesis' response is a tangential drag while things move and no friction
  // at rest - the settled state equals the frictionless one.
  const Curve stick = press(rig(msd::ContactResponse::Stick));
  const Curve slip = press(rig(msd::ContactResponse::Frictionless));
  EXPECT_NEAR(slip.samples.back().force, stick.samples.back().force, 0.01 * stick.samples.back().force);
  EXPECT_LE(slip.max_penetration, 1e-12);
}
