// Contractile units (thesis 5.2.7): the units are the muscle edges along the
// line of action; their forces are equal and opposite (no net force or
// torque); a section of a box muscle carries activation * sigma_max * area.
#include "msd/forces/muscle_units.hpp"

#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace {

// A 4 x 4 x 8 cm box of muscle at h = 1 cm, its long axis along z.
msd::TetMesh muscle_box() {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  o.region = msd::kBackMuscle;
  return msd::mesh_closed_surface(msd::make_box(msd::Vec3::Zero(), msd::Vec3(0.04, 0.04, 0.08)), o, "muscle").mesh;
}

}  // namespace

TEST(MuscleUnits, UnitsAreTheEdgesAlongTheLineOfAction) {
  const msd::TetMesh m = muscle_box();
  const auto along = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  ASSERT_FALSE(along.empty());
  for (const auto& u : along) {
    const msd::Vec3 l = m.nodes.col(u.b) - m.nodes.col(u.a);
    EXPECT_NEAR(std::abs(l.z()), l.norm(), 1e-12);  // axis-aligned z edges only
  }
  // Face diagonals (45 degrees) join within a 50 degree tolerance.
  EXPECT_GT(msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 50.0).size(), along.size());
  EXPECT_TRUE(msd::contractile_units(m, msd::kFrontMuscle, msd::Vec3::UnitZ(), 10.0).empty());
  EXPECT_THROW(msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::Zero(), 10.0), msd::Error);
  EXPECT_THROW(msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 95.0), msd::Error);
}

TEST(MuscleUnits, TheFibreEndsAreTheNodesNoUnitContinuesBeyond) {
  // The box's units along z are its grid's columns (the fibres); each column
  // ends once at the top and once at the bottom.
  const msd::TetMesh m = muscle_box();
  auto units = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  double lo = 1e9, hi = -1e9;
  std::set<std::pair<long, long>> columns;
  for (const auto& u : units)
    for (int v : {u.a, u.b}) {
      lo = std::min(lo, m.nodes(2, v));
      hi = std::max(hi, m.nodes(2, v));
      columns.insert({std::lround(m.nodes(0, v) / 0.01), std::lround(m.nodes(1, v) / 0.01)});
    }
  const auto top = msd::fibre_end_nodes(m.nodes, units, msd::Vec3::UnitZ(), 1);
  const auto bottom = msd::fibre_end_nodes(m.nodes, units, msd::Vec3::UnitZ(), -1);
  EXPECT_EQ(top.size(), columns.size());
  EXPECT_EQ(bottom.size(), columns.size());
  for (int v : top) EXPECT_NEAR(m.nodes(2, v), hi, 1e-12);
  for (int v : bottom) EXPECT_NEAR(m.nodes(2, v), lo, 1e-12);
  // The line's sense picks the side: -z's top is +z's bottom.
  EXPECT_EQ(msd::fibre_end_nodes(m.nodes, units, -msd::Vec3::UnitZ(), 1), bottom);
  // A fibre cut short ends where it is cut: drop one column's units above
  // its middle, and the node at the cut joins the top ends.
  const double x0 = m.nodes(0, top.front()), y0 = m.nodes(1, top.front()), mid = 0.5 * (lo + hi);
  auto in_column = [&](int v) { return std::abs(m.nodes(0, v) - x0) < 1e-9 && std::abs(m.nodes(1, v) - y0) < 1e-9; };
  std::vector<msd::ContractileUnit> cut;
  for (const auto& u : units)
    if (!(in_column(u.a) && in_column(u.b) && std::max(m.nodes(2, u.a), m.nodes(2, u.b)) > mid + 1e-9)) cut.push_back(u);
  const auto cut_top = msd::fibre_end_nodes(m.nodes, cut, msd::Vec3::UnitZ(), 1);
  ASSERT_EQ(cut_top.size(), top.size());
  int at_cut = 0;
  for (int v : cut_top)
    if (in_column(v)) {
      ++at_cut;
      EXPECT_NEAR(m.nodes(2, v), mid, 0.0051);  // the highest node at or below the cut (h = 1 cm)
    }
  EXPECT_EQ(at_cut, 1);
  EXPECT_EQ(msd::fibre_end_nodes(m.nodes, cut, msd::Vec3::UnitZ(), -1), bottom);
  EXPECT_THROW(msd::fibre_end_nodes(m.nodes, units, msd::Vec3::Zero(), 1), msd::Error);
  EXPECT_THROW(msd::fibre_end_nodes(m.nodes, units, msd::Vec3::UnitZ(), 0), msd::Error);
}

TEST(MuscleUnits, ASectionCarriesActivationTimesMaxStressTimesArea) {
  const msd::TetMesh m = muscle_box();
  const auto units = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  const double a = 0.6, sigma = 3.0e5, area = 0.04 * 0.04;
  const double f = msd::unit_force(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), a, sigma);
  // The units crossing the plane z = 4.5 cm.
  int crossing = 0;
  for (const auto& u : units) {
    const double za = m.nodes(2, u.a), zb = m.nodes(2, u.b);
    crossing += (std::min(za, zb) < 0.045 && std::max(za, zb) > 0.045) ? 1 : 0;
  }
  EXPECT_NEAR(crossing * f, a * sigma * area, 1e-9 * a * sigma * area);
  EXPECT_EQ(msd::unit_force(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), 0.0, sigma), 0.0);
}

TEST(MuscleUnits, ASectionCarriesTheGivenCrossSectionsForceWhenOneIsGiven) {
  // A published PCSA in place of the mesh's section: the units crossing the
  // plane z = 4.5 cm carry activation * sigma_max * PCSA; for the box's own
  // section (4 x 4 cm) that is unit_force's share exactly.
  const msd::TetMesh m = muscle_box();
  const auto units = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  const double a = 0.6, sigma = 2.7e5, pcsa = 0.0225;  // the quadriceps' 225 cm^2
  int crossing = 0;
  for (const auto& u : units) {
    const double za = m.nodes(2, u.a), zb = m.nodes(2, u.b);
    crossing += (std::min(za, zb) < 0.045 && std::max(za, zb) > 0.045) ? 1 : 0;
  }
  const double f = msd::unit_force_for_area(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), a, sigma, pcsa);
  EXPECT_NEAR(crossing * f, a * sigma * pcsa, 1e-9 * a * sigma * pcsa);
  EXPECT_NEAR(msd::unit_force_for_area(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), a, sigma, 0.04 * 0.04),
              msd::unit_force(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), a, sigma), 1e-12);
  EXPECT_THROW(msd::unit_force_for_area(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), a, sigma, 0.0), msd::Error);
  EXPECT_THROW(msd::unit_force_for_area(m, msd::kBackMuscle, units, msd::Vec3::UnitZ(), a, sigma, -1e-3),
               msd::Error);
}

TEST(MuscleUnits, ForcesAreEqualAndOppositeWithNoNetForceOrTorque) {
  const msd::TetMesh m = muscle_box();
  const auto units = msd::contractile_units(m, msd::kBackMuscle, msd::Vec3::UnitZ(), 10.0);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.002, 0.002);
  msd::Points x = m.nodes;
  for (int i = 0; i < x.cols(); ++i) x.col(i) += msd::Vec3(u(rng), u(rng), u(rng));
  msd::Points f = msd::Points::Zero(3, x.cols());
  msd::add_muscle_forces(x, units, 2.5, f);
  EXPECT_LT(f.rowwise().sum().norm(), 1e-12);
  msd::Vec3 torque = msd::Vec3::Zero();
  for (int i = 0; i < x.cols(); ++i) torque += msd::Vec3(x.col(i)).cross(msd::Vec3(f.col(i)));
  EXPECT_LT(torque.norm(), 1e-12);
  // Contraction: the top face is pulled down, the bottom face up.
  double top = 0, bottom = 0;
  for (int i = 0; i < x.cols(); ++i) {
    if (m.nodes(2, i) > 0.08 - 1e-9) top += f(2, i);
    if (m.nodes(2, i) < 1e-9) bottom += f(2, i);
  }
  EXPECT_LT(top, 0.0);
  EXPECT_GT(bottom, 0.0);
}

TEST(MuscleUnits, ForceLengthFactorIsTheAscendingLimb) {
  // f_L = 1 at and above the rest (optimal) length, 1 - ((1 - l) / (1 - l0))^2
  // between, 0 at and below l0; l0 < 0 is the thesis' constant force.
  EXPECT_EQ(msd::force_length_factor(1.0, 0.5), 1.0);
  EXPECT_EQ(msd::force_length_factor(1.3, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(msd::force_length_factor(0.75, 0.5), 0.75);  // 1 - (0.25 / 0.5)^2
  EXPECT_DOUBLE_EQ(msd::force_length_factor(0.9, 0.6), 1.0 - 0.25 * 0.25);
  EXPECT_EQ(msd::force_length_factor(0.5, 0.5), 0.0);
  EXPECT_EQ(msd::force_length_factor(0.2, 0.5), 0.0);
  EXPECT_EQ(msd::force_length_factor(0.2, -1.0), 1.0);
  // Continuous at both ends of the limb.
  EXPECT_NEAR(msd::force_length_factor(1.0 - 1e-9, 0.5), 1.0, 1e-8);
  EXPECT_NEAR(msd::force_length_factor(0.5 + 1e-9, 0.5), 0.0, 1e-8);
}

TEST(MuscleUnits, WithForceLengthAShortenedUnitPullsLessAndAHalfLengthOneNotAtAll) {
  // One unit along z of rest length 1 cm; pulled with 2 N at full length.
  const std::vector<msd::ContractileUnit> units{{0, 1, 0.01}};
  const msd::ForceLength fl{true, 0.5};
  auto pull = [&](double length) {
    msd::Points x(3, 2);
    x.col(0) = msd::Vec3::Zero();
    x.col(1) = msd::Vec3(0, 0, length);
    msd::Points f = msd::Points::Zero(3, 2);
    msd::add_muscle_forces(x, units, 2.0, f, fl);
    EXPECT_NEAR((f.col(0) + f.col(1)).norm(), 0.0, 1e-15);  // still equal and opposite
    return f(2, 0);  // node 0 pulled towards node 1 (+z)
  };
  EXPECT_DOUBLE_EQ(pull(0.012), 2.0);
  EXPECT_DOUBLE_EQ(pull(0.01), 2.0);
  EXPECT_DOUBLE_EQ(pull(0.0075), 2.0 * 0.75);
  EXPECT_EQ(pull(0.004), 0.0);
  // Without it (the thesis) the pull does not depend on length.
  msd::Points x(3, 2);
  x.col(0) = msd::Vec3::Zero();
  x.col(1) = msd::Vec3(0, 0, 0.004);
  msd::Points f = msd::Points::Zero(3, 2);
  msd::add_muscle_forces(x, units, 2.0, f);
  EXPECT_DOUBLE_EQ(f(2, 0), 2.0);
  // A zero stretch outside [0, 1) is refused.
  EXPECT_THROW(msd::add_muscle_forces(x, units, 2.0, f, msd::ForceLength{true, 1.0}), msd::Error);
}

// --- The Hill-type law (Zajac 1989; Thelen 2003) -----------------------------

TEST(HillMuscle, TheCurvesPassThroughZajacsAndThelensPoints) {
  const msd::HillMuscle h;
  // Active force-length: 1 at optimal length, zero at 1 -+ w (0.5, 1.5).
  EXPECT_DOUBLE_EQ(msd::hill_active_force_length(1.0, h.active_width), 1.0);
  EXPECT_EQ(msd::hill_active_force_length(0.5, h.active_width), 0.0);
  EXPECT_EQ(msd::hill_active_force_length(1.5, h.active_width), 0.0);
  EXPECT_EQ(msd::hill_active_force_length(0.3, h.active_width), 0.0);
  EXPECT_NEAR(msd::hill_active_force_length(0.75, h.active_width), 0.75, 1e-15);  // 1 - (0.25/0.5)^2
  // Passive: none up to optimal length, F_max at 1 + e0.
  EXPECT_EQ(msd::hill_passive_force_length(0.9, h.passive_strain, h.passive_shape), 0.0);
  EXPECT_EQ(msd::hill_passive_force_length(1.0, h.passive_strain, h.passive_shape), 0.0);
  EXPECT_NEAR(msd::hill_passive_force_length(1.6, h.passive_strain, h.passive_shape), 1.0, 1e-14);
  // Force-velocity: 1 isometric, 0 at v_max shortening, Hill's hyperbola between,
  // towards f_e lengthening, the slope at 0 twice as steep lengthening.
  EXPECT_DOUBLE_EQ(msd::hill_force_velocity(0.0, h), 1.0);
  EXPECT_EQ(msd::hill_force_velocity(-1.0, h), 0.0);
  EXPECT_EQ(msd::hill_force_velocity(-2.0, h), 0.0);
  EXPECT_NEAR(msd::hill_force_velocity(-0.5, h), 0.5 / 3.0, 1e-15);  // (1 - 0.5) / (1 + 0.5 / 0.25)
  EXPECT_NEAR(msd::hill_force_velocity(1e6, h), h.eccentric_max, 1e-4);
  double concentric = 0.0, eccentric = 0.0;
  msd::hill_force_velocity(-1e-12, h, &concentric);
  msd::hill_force_velocity(0.0, h, &eccentric);
  EXPECT_NEAR(concentric, 1.0 + 1.0 / h.curvature, 1e-9);
  EXPECT_NEAR(eccentric, 2.0 * concentric, 1e-9);
  msd::HillMuscle off = h;
  off.force_velocity = false;
  EXPECT_EQ(msd::hill_force_velocity(-0.5, off), 1.0);
}

TEST(HillMuscle, EachCurvesSlopeIsItsDerivative) {
  const msd::HillMuscle h;
  const double e = 1e-7;
  for (double lt : {0.6, 0.9, 1.1, 1.3, 1.45}) {
    double s = 0.0;
    msd::hill_active_force_length(lt, h.active_width, &s);
    EXPECT_NEAR(s, (msd::hill_active_force_length(lt + e, h.active_width) - msd::hill_active_force_length(lt - e, h.active_width)) / (2 * e), 1e-6);
    msd::hill_passive_force_length(lt, h.passive_strain, h.passive_shape, &s);
    if (lt > 1.0) {
      EXPECT_NEAR(s, (msd::hill_passive_force_length(lt + e, h.passive_strain, h.passive_shape) -
                      msd::hill_passive_force_length(lt - e, h.passive_strain, h.passive_shape)) / (2 * e), 1e-6);
    }
  }
  for (double vt : {-0.9, -0.4, -0.05, 0.05, 0.3, 2.0}) {
    double s = 0.0;
    msd::hill_force_velocity(vt, h, &s);
    EXPECT_NEAR(s, (msd::hill_force_velocity(vt + e, h) - msd::hill_force_velocity(vt - e, h)) / (2 * e), 1e-6) << vt;
  }
}

TEST(HillMuscle, AnIsometricUnitAtOptimalLengthPullsLikeTheThesisUnit) {
  // l = l_o and no rate: T = a F_u, the thesis' constant force.
  msd::Points x(3, 2), v = msd::Points::Zero(3, 2), f1 = msd::Points::Zero(3, 2), f2 = msd::Points::Zero(3, 2);
  x.col(0).setZero();
  x.col(1) = msd::Vec3(0.003, -0.004, 0.012);
  const std::vector<msd::ContractileUnit> units{{0, 1, x.col(1).norm()}};
  msd::HillMuscle h;
  h.enabled = true;
  msd::add_hill_muscle_forces(x, v, units, 2.5, 0.6, h, f1);
  msd::add_muscle_forces(x, units, 0.6 * 2.5, f2);
  EXPECT_LT((f1 - f2).norm(), 1e-14);
  EXPECT_NEAR(f1.col(0).norm(), 1.5, 1e-14);
  // Shortening at half of v_max it pulls (1 - 0.5) / (1 + 2) of that; relaxed, nothing.
  v.col(1) = -0.5 * h.max_velocity * units[0].rest_length * x.col(1).normalized();
  f1.setZero();
  msd::add_hill_muscle_forces(x, v, units, 2.5, 0.6, h, f1);
  EXPECT_NEAR(f1.col(0).norm(), 1.5 / 6.0, 1e-12);
  f1.setZero();
  msd::add_hill_muscle_forces(x, v, units, 2.5, 0.0, h, f1);
  EXPECT_EQ(f1.norm(), 0.0);
}

TEST(HillMuscle, ARelaxedUnitPullsOnlyWhenStretchedPastOptimalLength) {
  msd::HillMuscle h;
  h.enabled = true;
  h.rest_fibre_stretch = 1.0;
  const double rest = 0.01, F = 3.0;
  EXPECT_EQ(msd::hill_unit_tension(0.95 * rest, 0.0, rest, 0.0, F, h).T, 0.0);
  EXPECT_EQ(msd::hill_unit_tension(rest, 0.0, rest, 0.0, F, h).T, 0.0);
  EXPECT_NEAR(msd::hill_unit_tension(1.6 * rest, 0.0, rest, 0.0, F, h).T, F, 1e-12);  // F_max at 60 % strain
  // Fibres at 1.1 optimal length in the mesh: the same unit is already past it.
  h.rest_fibre_stretch = 1.1;
  EXPECT_GT(msd::hill_unit_tension(rest, 0.0, rest, 0.0, F, h).T, 0.0);
}

TEST(HillMuscle, ThePassiveEnergysDerivativeIsThePassiveTension) {
  // dE/dl = F_u f_P (central differences), E = 0 up to the optimal length,
  // and the closed form at 60 % strain: F_u l_o [e0/k (e^k - 1) - e0] / (e^k - 1).
  msd::HillMuscle h;
  h.enabled = true;
  h.rest_fibre_stretch = 1.05;
  const double rest = 0.012, F = 2.5, lo = rest / 1.05;
  EXPECT_EQ(msd::hill_passive_energy(0.9 * lo, rest, F, h), 0.0);
  EXPECT_EQ(msd::hill_passive_energy(lo, rest, F, h), 0.0);
  for (double lt : {1.02, 1.2, 1.45, 1.7}) {
    const double l = lt * lo, d = 1e-7 * lo;
    const double fd = (msd::hill_passive_energy(l + d, rest, F, h) - msd::hill_passive_energy(l - d, rest, F, h)) / (2 * d);
    const double T = msd::hill_unit_tension(l, 0.0, rest, 0.0, F, h).T;
    EXPECT_NEAR(fd, T, 1e-6 * (1.0 + T)) << lt;
  }
  const double k = h.passive_shape, e0 = h.passive_strain;
  EXPECT_NEAR(msd::hill_passive_energy(1.6 * lo, rest, F, h), F * lo * (e0 / k * std::expm1(k) - e0) / std::expm1(k),
              1e-15);
  // A muscle's: the sum over its units.
  msd::Points x(3, 3);
  x << 0, 1.3 * lo, 1.3 * lo + 1.1 * lo, 0, 0, 0, 0, 0, 0;
  const std::vector<msd::ContractileUnit> units = {{0, 1, rest}, {1, 2, rest}};
  EXPECT_NEAR(msd::hill_muscle_passive_energy(x, units, F, h),
              msd::hill_passive_energy(1.3 * lo, rest, F, h) + msd::hill_passive_energy(1.1 * lo, rest, F, h), 1e-15);
}

TEST(HillMuscle, ACurveThatIsNotACurveIsRefusedNamingItsField) {
  auto refused = [](msd::HillMuscle h, const std::string& field) {
    try {
      msd::check_hill_muscle(h, "scene.yaml: muscles.hill");
      ADD_FAILURE() << field << " accepted";
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find("scene.yaml: muscles.hill." + field), std::string::npos) << e.what();
    }
  };
  msd::HillMuscle h;
  EXPECT_NO_THROW(msd::check_hill_muscle(h, "x"));
  h.active_width = 0.0;
  refused(h, "active_width");
  h = {};
  h.active_width = 1.2;  // would pull at zero length
  refused(h, "active_width");
  h = {};
  h.rest_fibre_stretch = -1.0;
  refused(h, "rest_fibre_stretch");
  h = {};
  h.passive_strain = 0.0;
  refused(h, "passive_strain");
  h = {};
  h.eccentric_max = 0.9;
  refused(h, "eccentric_max");
  h = {};
  h.max_velocity = 0.0;
  refused(h, "max_velocity");
}

TEST(ActivationDynamics, TheExactStepRisesWithTauAFallsWithTauDAndSettlesAtTheExcitation) {
  const double ta = 0.01, td = 0.04;
  // One step of tau_a from rest: 1 - 1/e of the way; many small steps the same
  // (the step is exact for a held excitation).
  EXPECT_NEAR(msd::activation_step(0.0, 1.0, ta, ta, td), 1.0 - std::exp(-1.0), 1e-15);
  double a = 0.0;
  for (int i = 0; i < 100; ++i) a = msd::activation_step(a, 1.0, ta / 100, ta, td);
  EXPECT_NEAR(a, 1.0 - std::exp(-1.0), 1e-12);
  // Falling from 1 to 0.2 with tau_d.
  EXPECT_NEAR(msd::activation_step(1.0, 0.2, td, ta, td), 0.2 + 0.8 * std::exp(-1.0), 1e-15);
  // Held, it reaches u and stays; a huge step is still bounded (no overshoot).
  EXPECT_NEAR(msd::activation_step(0.1, 0.65, 10.0, ta, td), 0.65, 1e-15);
  EXPECT_DOUBLE_EQ(msd::activation_step(0.65, 0.65, 0.001, ta, td), 0.65);
  // No dynamics: the activation is the excitation.
  EXPECT_EQ(msd::activation_step(0.1, 0.4, 1e-4, 0.0, 0.0), 0.4);
  EXPECT_THROW(msd::activation_step(0.1, 1.5, 1e-4, ta, td), msd::Error);
  EXPECT_THROW(msd::activation_step(0.1, 0.5, 1e-4, -ta, td), msd::Error);
}
