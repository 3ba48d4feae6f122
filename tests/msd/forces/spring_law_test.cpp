// Tests for msd/src/forces/spring_law.cpp: the edge classes of the five-tet
// lattice, the spring law (closed forms, slope, energy, monotonicity,
// refusals), and the law in a model - the engine against the per-tet loop,
// forces against the energy's gradient, zero net force and torque, and the
// lattice's Cauchy-Born elasticity per class against its closed form.
#include "msd/forces/spring_law.hpp"

#include "msd/forces/edge_springs.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/forces/force_engine.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using msd::EdgeClass;
using msd::Vec3;

namespace {

// (m, n) pairs covering the linear law, the neo-Hookean bar, the log case
// (n = 1), a pure compression law (m = 0) and fractional exponents.
const double kLaws[][2] = {{1, 0}, {1, 2}, {1, 1}, {0, 1}, {0.5, 3}, {2.5, 0.7}, {3, 0}};

msd::SpringLaw law(double stiffness, double m, double n) {
  msd::SpringLaw l;
  l.stiffness = stiffness;
  l.tension_exponent = m;
  l.compression_exponent = n;
  return l;
}

// A 3 x 3 x 3 cm block of the lattice (h = 1 cm), springs only or all terms,
// with the given class laws; physical constants, E = 3 kPa.
msd::Model lattice(unsigned terms, const std::array<msd::SpringLaw, msd::kEdgeClasses>& laws, double size = 0.03,
                   int threads = 1) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  const auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(size, size, size)), o, "block");
  msd::TissueMaterial mat;
  mat.mode = msd::ConstantsMode::Physical;
  mat.density = 1000;
  mat.youngs_modulus = 3000;
  mat.damping_time = 0.01;
  mat.repulsion_factor = 0.5;
  mat.volume_factor = 1.6;
  mat.edge_laws = laws;
  msd::ModelOptions mo;
  mo.terms = terms;
  mo.region_materials = {mat};
  mo.threads = threads;
  return msd::build_model(s.mesh, mo);
}

const std::array<msd::SpringLaw, msd::kEdgeClasses> kMixedLaws{law(0.5, 1, 2), law(1.3, 2, 1), law(1, 1, 0)};

}  // namespace

TEST(EdgeClass, TheFiveTetLatticeHasCubeEdgesAndFaceDiagonalsOnly) {
  EXPECT_EQ(msd::classify_edge(Vec3(0.01, 0, 0)), EdgeClass::axis);
  EXPECT_EQ(msd::classify_edge(Vec3(0, 0, -0.02)), EdgeClass::axis);
  EXPECT_EQ(msd::classify_edge(Vec3(0.01, -0.01, 0)), EdgeClass::face_diagonal);
  EXPECT_EQ(msd::classify_edge(Vec3(0, 0.01, 0.01)), EdgeClass::face_diagonal);
  EXPECT_EQ(msd::classify_edge(Vec3(0.01, 0.01, 0.01)), EdgeClass::other);   // a body diagonal
  EXPECT_EQ(msd::classify_edge(Vec3(0.01, 0.012, 0)), EdgeClass::other);     // a skewed face edge
  EXPECT_EQ(msd::classify_edge(Vec3(0.01, 1e-10, 0)), EdgeClass::axis);      // round-off is zero
  // The lattice: per cube, three axis edges in each of the four corner tets,
  // and six face diagonals in the centre tet and three in each corner tet.
  const msd::Model m = lattice(msd::kSprings, {});
  long axis = 0, diagonal = 0, other = 0;
  for (const msd::Element& el : m.elements)
    for (EdgeClass c : el.edge_class) (c == EdgeClass::axis ? axis : c == EdgeClass::face_diagonal ? diagonal : other)++;
  const long cubes = m.num_elements() / 5;
  EXPECT_EQ(cubes, 27);
  EXPECT_EQ(axis, 12 * cubes);
  EXPECT_EQ(diagonal, 18 * cubes);
  EXPECT_EQ(other, 0);
}

TEST(SpringLaw, TheLinearLawIsTheThesisSpringAndOneTwoIsTheNeoHookeanBar) {
  for (double s : {0.3, 0.9, 1.0, 1.4, 2.5}) {
    EXPECT_NEAR(msd::spring_law_tension(1, 0, s), s - 1.0, 1e-15);
    EXPECT_NEAR(msd::spring_law_slope(1, 0, s), 1.0, 1e-15);
    EXPECT_NEAR(msd::spring_law_energy(1, 0, s), 0.5 * (s - 1) * (s - 1), 1e-15);
    EXPECT_NEAR(msd::spring_law_factor(7.0, 0.02 * s, 1.0 / (0.02 * s), 0.02, 1, 0),
                msd::edge_spring_factor(7.0, 0.02 * s, 1.0 / (0.02 * s), 0.02), 1e-13);
    // The incompressible neo-Hookean bar: P = mu (lambda - lambda^-2) = E (lambda - lambda^-2) / 3.
    EXPECT_NEAR(msd::spring_law_tension(1, 2, s), (s - 1.0 / (s * s)) / 3.0, 1e-15);
  }
  EXPECT_TRUE(law(2, 1, 0).linear());
  EXPECT_FALSE(law(1, 1, 2).linear());
}

TEST(SpringLaw, EveryLawIsForceFreeAtRestWithUnitSlopeAndItsSlopeAndEnergyAreConsistent) {
  for (const auto& mn : kLaws) {
    const double m = mn[0], n = mn[1];
    SCOPED_TRACE("m " + std::to_string(m) + ", n " + std::to_string(n));
    EXPECT_EQ(msd::spring_law_tension(m, n, 1.0), 0.0);
    EXPECT_NEAR(msd::spring_law_slope(m, n, 1.0), 1.0, 1e-15);
    EXPECT_EQ(msd::spring_law_energy(m, n, 1.0), 0.0);
    for (double s : {0.05, 0.4, 0.8, 1.1, 1.6, 3.0}) {
      const double h = 1e-6 * s;
      const double dphi = (msd::spring_law_tension(m, n, s + h) - msd::spring_law_tension(m, n, s - h)) / (2 * h);
      const double dpsi = (msd::spring_law_energy(m, n, s + h) - msd::spring_law_energy(m, n, s - h)) / (2 * h);
      const double phi = msd::spring_law_tension(m, n, s), slope = msd::spring_law_slope(m, n, s);
      EXPECT_NEAR(slope, dphi, 1e-7 * std::max(1.0, std::abs(slope)));
      EXPECT_NEAR(phi, dpsi, 1e-7 * std::max(1.0, std::abs(phi)));
      // Monotonic with positive stiffness; tension when stretched, compression when squeezed.
      EXPECT_GT(slope, 0.0);
      EXPECT_EQ(phi > 0.0, s > 1.0);
      EXPECT_GT(msd::spring_law_energy(m, n, s), 0.0);
    }
  }
  // A compression exponent stiffens the crushed spring; n >= 1 gives it an
  // energy without bound (the linear spring's stays below k r^2 / 2).
  EXPECT_GT(msd::spring_law_slope(1, 2, 0.3), 10.0);
  // Psi of (1, 2): ((lambda^2 - 1) / 2 + 1 / lambda - 1) / 3, about 333 at lambda = 1e-3.
  EXPECT_NEAR(msd::spring_law_energy(1, 2, 1e-3), ((1e-6 - 1) / 2 + 1e3 - 1) / 3, 1e-9);
  EXPECT_LT(msd::spring_law_energy(1, 0, 1e-3), 0.5);
}

TEST(SpringLaw, ForcesAreMinusTheEnergysGradientAndTheJacobianIsTheForcesDerivative) {
  std::mt19937 rng(5);
  const msd::EdgeClass cls[6] = {EdgeClass::axis, EdgeClass::face_diagonal, EdgeClass::other,
                                 EdgeClass::axis, EdgeClass::face_diagonal, EdgeClass::other};
  for (int k = 0; k < 50; ++k) {
    Vec3 rest[4], x[4];
    testing_support::random_tet(rng, rest, 0.02);
    testing_support::random_tet(rng, x, 0.02);
    double r[6], ks[6];
    for (int e = 0; e < 6; ++e) {
      r[e] = (rest[msd::kTetEdges[e][1]] - rest[msd::kTetEdges[e][0]]).norm();
      ks[e] = 1.0 + e;
    }
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    msd::add_edge_springs(msd::edge_frame(x), r, ks, cls, kMixedLaws, f);
    Vec3 grad[4];
    testing_support::fd_gradient([&](const Vec3* y) { return msd::edge_spring_energy(y, r, ks, cls, kMixedLaws); },
                                 x, 1e-8, grad);
    double scale = 0.0;
    for (int i = 0; i < 4; ++i) scale = std::max(scale, f[i].norm());
    for (int i = 0; i < 4; ++i) EXPECT_NEAR((f[i] + grad[i]).norm(), 0.0, 1e-6 * scale) << i;
    // Zero net force and torque.
    Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      net += f[i];
      torque += x[i].cross(f[i]);
    }
    EXPECT_LT(net.norm(), 1e-12 * scale);
    EXPECT_LT(torque.norm(), 1e-12 * scale * 0.05);
    // dF_a/dl against central differences of the force on a.
    const Vec3 l = x[1] - x[0];
    const double m = 1 + 0.5 * (k % 3), n = 0.5 * (k % 5);
    const msd::Mat3 J = msd::spring_law_jacobian(l, r[0], ks[0], m, n);
    const auto force = [&](const Vec3& y) {
      return Vec3(msd::spring_law_factor(ks[0], y.norm(), 1.0 / y.norm(), r[0], m, n) * y);
    };
    for (int c = 0; c < 3; ++c) {
      Vec3 up = l, down = l;
      up[c] += 1e-8;
      down[c] -= 1e-8;
      const Vec3 col = (force(up) - force(down)) / 2e-8;
      EXPECT_LT((J.col(c) - col).norm(), 1e-6 * J.norm()) << c;
    }
  }
}

TEST(SpringLaw, ALawThatIsNotMonotonicOrHasNoStiffnessIsRefusedNamingItsField) {
  const auto message = [](const msd::SpringLaw& l) {
    try {
      msd::check_spring_law(l, "spec.yaml: msd.edge_classes.axis");
    } catch (const msd::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message(law(1, 1, 2)), "");
  EXPECT_NE(message(law(0, 1, 0)).find("msd.edge_classes.axis.stiffness must be positive"), std::string::npos);
  EXPECT_NE(message(law(-2, 1, 0)).find("stiffness"), std::string::npos);
  EXPECT_NE(message(law(1, -1, 2)).find("msd.edge_classes.axis.tension_exponent must be >= 0"), std::string::npos);
  EXPECT_NE(message(law(1, 1, -0.5)).find("compression_exponent must be >= 0"), std::string::npos);
  EXPECT_NE(message(law(1, 0, 0)).find("no stiffness"), std::string::npos);
  EXPECT_NE(message(law(1, std::nan(""), 0)).find("tension_exponent"), std::string::npos);
  // Through the material: the class is named.
  msd::TissueMaterial mat;
  mat.density = 1000;
  mat.k_s = 1;
  mat.edge_laws[1] = law(1, 1, -1);
  try {
    msd::check_material(mat, "region 0");
    FAIL() << "a negative exponent was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("region 0: edge_classes.face_diagonal.compression_exponent"), std::string::npos)
        << e.what();
  }
}

TEST(SpringLaw, InAModelTheEngineEqualsTheReferenceLoopIsMinusTheEnergysGradientAndBitIdenticalOnTwoThreads) {
  const msd::Model m = lattice(msd::kSprings | msd::kDampers | msd::kRepulsion | msd::kVolume, kMixedLaws);
  ASSERT_EQ(m.plan.edge_law_m.size(), static_cast<size_t>(m.plan.num_edges()));
  msd::Points x, v, fast, ref, fast2;
  testing_support::deform(m, 0.6, 0.001, x, v);
  msd::compute_internal_forces(m, x, v, fast);
  msd::Model reference = m;
  reference.reference_forces = true;
  msd::compute_internal_forces(reference, x, v, ref);
  const double scale = ref.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  EXPECT_LT((fast - ref).cwiseAbs().maxCoeff(), 1e-12 * scale);
  msd::Model two = m;
  two.threads = 2;
  msd::compute_internal_forces(two, x, v, fast2);
  EXPECT_EQ((fast - fast2).cwiseAbs().maxCoeff(), 0.0);
  // The springs alone are conservative: their forces are -grad of conservative_energy.
  const msd::Model springs = lattice(msd::kSprings, kMixedLaws);
  msd::Points f, zero = msd::Points::Zero(3, x.cols());
  msd::compute_internal_forces(springs, x, zero, f);
  const double fs = f.cwiseAbs().maxCoeff();
  for (int node : {0, 7, 31, springs.num_nodes() - 1})
    for (int c = 0; c < 3; ++c) {
      msd::Points y = x;
      y(c, node) += 1e-8;
      const double up = msd::conservative_energy(springs, y);
      y(c, node) -= 2e-8;
      const double down = msd::conservative_energy(springs, y);
      EXPECT_NEAR(f(c, node), -(up - down) / 2e-8, 1e-5 * fs) << node << " " << c;
    }
  // Rest is force-free; net force and torque vanish when deformed.
  msd::Points at_rest;
  msd::compute_internal_forces(springs, springs.rest_positions, zero, at_rest);
  EXPECT_LT(at_rest.cwiseAbs().maxCoeff(), 1e-12 * fs);
  Vec3 torque = Vec3::Zero();
  for (int i = 0; i < x.cols(); ++i) torque += Vec3(x.col(i)).cross(Vec3(f.col(i)));
  EXPECT_LT(Vec3(f.rowwise().sum()).norm(), 1e-10 * fs);
  EXPECT_LT(torque.norm(), 1e-10 * fs * 0.03);
}

TEST(SpringLaw, TheThesisSpringsAreUntouchedBitForBit) {
  // The default laws take the linear path: no exponents in the plan, and the
  // same forces as a model whose materials never heard of edge classes.
  const msd::Model m = lattice(msd::kSprings | msd::kDampers, {});
  EXPECT_TRUE(m.plan.edge_law_m.empty());
  std::array<msd::SpringLaw, msd::kEdgeClasses> ones{law(1, 1, 0), law(1, 1, 0), law(1, 1, 0)};
  const msd::Model same = lattice(msd::kSprings | msd::kDampers, ones);
  msd::Points x, v, f1, f2;
  testing_support::deform(m, 0.7, 0.001, x, v);
  msd::compute_internal_forces(m, x, v, f1);
  msd::compute_internal_forces(same, x, v, f2);
  EXPECT_EQ((f1 - f2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SpringLaw, TheLatticesSpringsHaveTheClosedFormCauchyBornElasticityPerClass) {
  // One cube's five tets under a small homogeneous strain: the springs'
  // energy per volume is eps : C : eps / 2 with (spring_law.hpp, s = 5/6)
  //   C11 = 2 (a + d) s E / 3,  C12 = C44 = d s E / 3.
  const double a = 0.37, d = 1.21, E = 3000.0, s = msd::kLatticeStiffnessFactor, h = 0.01;
  const msd::Model m = lattice(msd::kSprings, {law(a, 1, 0), law(d, 1, 0), law(1, 1, 0)}, h);
  ASSERT_EQ(m.num_elements(), 5);
  const double C11 = 2 * (a + d) * s * E / 3, C12 = d * s * E / 3, C44 = C12, V = h * h * h;
  const double e = 1e-6;
  const auto energy = [&](const msd::Mat3& strain) {
    const msd::Points x = (msd::Mat3::Identity() + strain) * m.rest_positions;
    return msd::conservative_energy(m, x) / V;
  };
  msd::Mat3 uni = msd::Mat3::Zero(), bi = msd::Mat3::Zero(), shear = msd::Mat3::Zero();
  uni(0, 0) = e;
  bi(0, 0) = bi(1, 1) = e;
  shear(0, 1) = shear(1, 0) = e / 2;  // engineering shear e
  EXPECT_NEAR(energy(uni), 0.5 * C11 * e * e, 1e-4 * C11 * e * e);
  EXPECT_NEAR(energy(bi), (C11 + C12) * e * e, 1e-4 * C11 * e * e);
  EXPECT_NEAR(energy(shear), 0.5 * C44 * e * e, 1e-4 * C11 * e * e);
  // a = d / 2 is isotropic: a 45-degree shear in the xy plane costs what an axis-aligned one does.
  const msd::Model iso = lattice(msd::kSprings, {law(0.5, 1, 0), law(1, 1, 0), law(1, 1, 0)}, h);
  msd::Mat3 rotated = msd::Mat3::Zero();  // the shear above turned by 45 degrees: pure stretch +-e/2
  rotated(0, 0) = e / 2;
  rotated(1, 1) = -e / 2;
  const auto iso_energy = [&](const msd::Mat3& strain) {
    return msd::conservative_energy(iso, (msd::Mat3::Identity() + strain) * iso.rest_positions);
  };
  EXPECT_NEAR(iso_energy(rotated), iso_energy(shear), 1e-4 * iso_energy(shear));
  // The thesis' a = d is not: the rotated shear costs 3/2 times as much.
  const msd::Model thesis = lattice(msd::kSprings, {}, h);
  const double ratio = msd::conservative_energy(thesis, (msd::Mat3::Identity() + rotated) * thesis.rest_positions) /
                       msd::conservative_energy(thesis, (msd::Mat3::Identity() + shear) * thesis.rest_positions);
  EXPECT_NEAR(ratio, 1.5, 1e-4);
}

TEST(SpringLaw, RegionsThatDisagreeOnASharedEdgesLawAreRefused) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.02, 0.01, 0.01)), o, "block");
  for (size_t t = 0; t < s.mesh.tets.size(); ++t) s.mesh.region[t] = t >= 5;
  msd::TissueMaterial a;
  a.density = 1000;
  a.k_s = 1;
  msd::TissueMaterial b = a;
  b.edge_laws[0] = law(1, 1, 2);
  msd::ModelOptions mo;
  mo.terms = msd::kSprings;
  mo.region_materials = {a, b};
  try {
    msd::build_model(s.mesh, mo);
    FAIL() << "two laws on one edge were accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("different spring laws"), std::string::npos) << e.what();
  }
  // A stiffness factor may differ (the constants are summed per edge).
  b.edge_laws[0] = law(3, 1, 0);
  mo.region_materials = {a, b};
  EXPECT_NO_THROW(msd::build_model(s.mesh, mo));
}
