#include "msd/model/model.hpp"

#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

namespace {

msd::SampleMesh block() {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  return msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.02, 0.02, 0.04)), o, "block");
}

msd::TissueMaterial material(msd::MassLumping lumping) {
  msd::TissueMaterial m;
  m.density = 1000;
  m.k_s = 1;
  m.lumping = lumping;
  return m;
}

}  // namespace

TEST(Model, MassLumpingConservesMassBothWays) {
  const auto s = block();
  const double mass = 1000 * 0.02 * 0.02 * 0.04;
  for (auto l : {msd::MassLumping::PerTet, msd::MassLumping::EqualPerNode}) {
    msd::ModelOptions o;
    o.region_materials = {material(l)};
    const msd::Model m = msd::build_model(s.mesh, o);
    EXPECT_NEAR(m.mass.sum(), mass, 1e-15);
    if (l == msd::MassLumping::EqualPerNode) {
      EXPECT_NEAR(m.mass.minCoeff(), m.mass.maxCoeff(), 1e-18);
    } else {
      // Corner nodes carry less than interior ones; centre of mass is right.
      EXPECT_LT(m.mass.minCoeff(), 0.5 * m.mass.maxCoeff());
      const Vec3 com = (m.rest_positions * m.mass) / m.mass.sum();
      EXPECT_NEAR((com - Vec3(0.01, 0.01, 0.02)).norm(), 0.0, 1e-15);
    }
  }
}

TEST(Model, RestDataOfElements) {
  const auto s = block();
  msd::ModelOptions o;
  o.region_materials = {material(msd::MassLumping::PerTet)};
  const msd::Model m = msd::build_model(s.mesh, o);
  double v = 0.0;
  for (const auto& el : m.elements) {
    v += el.rest_volume;
    for (double h : el.rest_height) EXPECT_GT(h, 0.0);
    for (double l : el.rest_length) EXPECT_TRUE(std::abs(l - 0.01) < 1e-12 || std::abs(l - 0.01 * std::sqrt(2.0)) < 1e-12);
  }
  EXPECT_NEAR(v, 0.02 * 0.02 * 0.04, 1e-15);
}

TEST(Model, BuildErrors) {
  const auto s = block();
  msd::ModelOptions o;
  EXPECT_THROW(msd::build_model(s.mesh, o), msd::Error);  // no material for region 0
  o.region_materials = {material(msd::MassLumping::PerTet)};
  o.nonlinear_threshold = 1.5;
  EXPECT_THROW(msd::build_model(s.mesh, o), msd::Error);
  o.nonlinear_threshold = 0.7;
  o.groups = {{"a", {0, 1}, {true, true, true}}, {"b", {1}, {true, true, true}}};
  EXPECT_THROW(msd::build_model(s.mesh, o), msd::Error);  // node 1 in two groups
  o.groups = {{"a", {999}, {true, true, true}}};
  EXPECT_THROW(msd::build_model(s.mesh, o), msd::Error);
}

TEST(Model, TermNames) {
  EXPECT_EQ(msd::parse_force_term("volume"), msd::kVolume);
  EXPECT_THROW(msd::parse_force_term("collisions"), msd::Error);
  EXPECT_EQ(msd::force_terms_to_string(msd::kSprings | msd::kVolume), "springs,volume");
  EXPECT_EQ(msd::parse_force_term("neo_hookean"), msd::kNeoHookean);
  EXPECT_EQ(msd::force_terms_to_string(msd::kNeoHookean | msd::kDampers), "dampers,neo_hookean");
}

TEST(Model, TheNeoHookeanTermNeedsPhysicalConstantsWithAPoissonsRatio) {
  const auto s = block();
  msd::ModelOptions o;
  o.terms = msd::kNeoHookean | msd::kDampers;
  o.region_materials = {material(msd::MassLumping::PerTet)};
  const auto refused = [&](const std::string& what) {
    try {
      msd::build_model(s.mesh, o);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find("region 0"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("oisson"), std::string::npos) << e.what();
    }
  };
  refused("raw constants");
  o.region_materials[0].mode = msd::ConstantsMode::Physical;
  o.region_materials[0].youngs_modulus = 3000.0;
  refused("no Poisson's ratio");
  o.region_materials[0].poisson_ratio = 0.5;
  refused("nu = 0.5");
  o.region_materials[0].poisson_ratio = 0.45;
  const msd::Model ok = msd::build_model(s.mesh, o);
  const double mu_l = 3000.0 / (2 * 1.45);
  ASSERT_EQ(ok.continuum.constants.size(), ok.elements.size());
  ASSERT_EQ(ok.continuum.dm_inv.size(), ok.elements.size());
  EXPECT_NEAR(ok.continuum.constants[0].mu, 4.0 / 3.0 * mu_l, 1e-9);
  EXPECT_TRUE(ok.continuum.dm_inv[0].allFinite());
  EXPECT_GT(ok.continuum.dm_inv[0].norm(), 0.0);
  // Without the term nothing is stored.
  o.terms = msd::kSprings;
  EXPECT_TRUE(msd::build_model(s.mesh, o).continuum.constants.empty());
}

TEST(Model, VolumeGroupsFromTheLatticesCubesHoldFiveTetsEightNodesAndTheCubesVolume) {
  const auto s = block();
  msd::ModelOptions o;
  o.terms = msd::kNeoHookean;
  msd::TissueMaterial m = material(msd::MassLumping::PerTet);
  m.mode = msd::ConstantsMode::Physical;
  m.youngs_modulus = 3000.0;
  m.poisson_ratio = 0.45;
  o.region_materials = {m};
  o.volume_group = s.info.tet_cube_id;
  const msd::Model model = msd::build_model(s.mesh, o);
  const msd::VolumeGroups& g = model.volume_groups;
  ASSERT_EQ(g.size(), 2 * 2 * 4);
  for (int k = 0; k < g.size(); ++k) {
    EXPECT_EQ(g.tet_offset[k + 1] - g.tet_offset[k], 5);
    EXPECT_EQ(g.node_offset[k + 1] - g.node_offset[k], 8);
    EXPECT_NEAR(g.rest_volume[k], 1e-6, 1e-18);
    for (int q = g.tet_offset[k]; q < g.tet_offset[k + 1]; ++q) {
      const int t = g.tets[q];
      EXPECT_EQ(g.of_tet[t], k);
      for (int i = 0; i < 4; ++i) EXPECT_EQ(g.nodes[g.node_offset[k] + g.corner_slot[4 * t + i]], model.elements[t].nodes[i]);
    }
  }
  // Refusals: without the neo_hookean term, a label count that is not the tet count, a group across regions.
  o.terms = msd::kSprings;
  EXPECT_THROW(msd::build_model(s.mesh, o), msd::Error);
  o.terms = msd::kNeoHookean;
  o.volume_group.pop_back();
  EXPECT_THROW(msd::build_model(s.mesh, o), msd::Error);
  o.volume_group = s.info.tet_cube_id;
  auto two = s.mesh;
  two.region[0] = 1;
  o.region_materials = {m, m};
  try {
    msd::build_model(two, o);
    ADD_FAILURE() << "a cube across two regions was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("regions"), std::string::npos) << e.what();
  }
}
