// The fast force engine (msd/forces/force_engine.hpp) against the per-tet
// reference loop on the model of every shipped spec the MSD solver runs:
// each deformed and moving at random, forces within 1e-12 of the largest
// nodal force and the same count of active non-linear elements; 2 threads
// bit-identical to 1.
#include "bench/msd_runner.hpp"
#include "bench/spec.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/forces/force_engine.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

TEST(EngineOnSpecs, EveryShippedMsdBenchmarkAgreesWithTheReference) {
  int checked = 0;
  for (const auto& e : std::filesystem::directory_iterator(TISSUEBENCH_SPECS_DIR)) {
    if (e.path().extension() != ".yaml") continue;
    const bench::Spec spec = bench::load_spec(e.path().string());
    if (!spec.msd) continue;  // fem-only verification specs
    SCOPED_TRACE(e.path().filename().string());
    bench::MsdProblem p = bench::compile_msd(spec);
    const double h = spec.mesh->spacing;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    msd::Points x = p.model.rest_positions, v = msd::Points::Zero(3, x.cols());
    x.row(2) *= 0.8;  // compressed 20 %, so the thesis' threshold (where set) leaves some elements in and some out
    for (Eigen::Index i = 0; i < x.cols(); ++i)
      for (int a = 0; a < 3; ++a) {
        x(a, i) += 0.05 * h * u(rng);
        v(a, i) = 0.01 * u(rng);
      }
    msd::Points fast, two, ref;
    msd::Scratch s;
    const long active = msd::compute_forces_fast(p.model, x, v, fast, s);
    EXPECT_EQ(active, msd::compute_internal_forces_reference(p.model, x, v, ref));
    const double scale = ref.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.0);
    EXPECT_LE((fast - ref).cwiseAbs().maxCoeff(), 1e-12 * scale);
    msd::Model threaded = p.model;
    threaded.threads = 2;
    msd::compute_forces_fast(threaded, x, v, two, s);
    EXPECT_TRUE((two.array() == fast.array()).all());
    ++checked;
  }
  EXPECT_GE(checked, 14);
}

TEST(EngineOnSpecs, ASpecPicksThePathAndTheThreadsAndBadValuesAreRefused) {
  const std::string base = testing_support::small_uniaxial_spec();
  const auto with = [&](const std::string& extra) {
    std::string text = base;
    const size_t at = text.find("msd: {");
    EXPECT_NE(at, std::string::npos);
    text.insert(at + 6, extra + ", ");
    return text;
  };
  const bench::Spec ref = bench::parse_spec(with("forces: reference, threads: 2"), "s.yaml");
  const bench::MsdProblem p = bench::compile_msd(ref);
  EXPECT_TRUE(p.model.reference_forces);
  EXPECT_EQ(p.model.threads, 2);
  EXPECT_FALSE(bench::compile_msd(bench::parse_spec(base, "s.yaml")).model.reference_forces);
  const auto error = [&](const std::string& extra) {
    try {
      bench::parse_spec(with(extra), "s.yaml");
    } catch (const msd::Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error("threads: 0").find("msd.threads: must lie in [1, 256], got 0"), std::string::npos) << error("threads: 0");
  EXPECT_NE(error("forces: fast").find("msd.forces"), std::string::npos) << error("forces: fast");
}
