// Element force loop cost, nanoseconds per element per evaluation, for each
// force term alone and for the full model (threshold off, and the thesis' 0.7
// threshold on a mildly deformed and on a strongly compressed sample).
#include "msd/forces/element_forces.hpp"
#include "msd/mesh/cubic_grid.hpp"

#include <benchmark/benchmark.h>

#include <random>

namespace {

struct Fixture {
  msd::Model model;
  msd::Points x, v, f;
};

// A 10 x 10 x 20 cm block at h = 1 cm (2,000 cubes, 10,000 tets), physical
// constants, positions perturbed randomly and the block squeezed along z by
// `squeeze` (0.8 = 20 % compression).
Fixture make_fixture(unsigned terms, double threshold, double squeeze) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  const auto sample = msd::mesh_closed_surface(
      msd::make_box(msd::Vec3::Zero(), msd::Vec3(0.1, 0.1, 0.2)), o, "benchmark block");
  msd::ModelOptions mo;
  mo.terms = terms;
  mo.nonlinear_threshold = threshold;
  msd::TissueMaterial mat;
  mat.mode = msd::ConstantsMode::Physical;
  mat.density = 1000;
  mat.youngs_modulus = 3000;
  mat.damping_time = 0.01;
  mat.repulsion_factor = 0.2;
  mat.volume_factor = 1.0;
  mo.region_materials = {mat};
  Fixture fx{msd::build_model(sample.mesh, mo), {}, {}, {}};
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  fx.x = fx.model.rest_positions;
  fx.x.row(2) *= squeeze;
  fx.v = msd::Points::Zero(3, fx.x.cols());
  for (Eigen::Index i = 0; i < fx.x.cols(); ++i)
    for (int a = 0; a < 3; ++a) {
      fx.x(a, i) += 0.001 * u(rng);
      fx.v(a, i) = 0.01 * u(rng);
    }
  return fx;
}

void run(benchmark::State& state, unsigned terms, double threshold, double squeeze) {
  Fixture fx = make_fixture(terms, threshold, squeeze);
  long active = 0;
  for (auto _ : state) {
    active = msd::compute_internal_forces(fx.model, fx.x, fx.v, fx.f);
    benchmark::DoNotOptimize(fx.f.data());
  }
  state.SetItemsProcessed(state.iterations() * fx.model.num_elements());
  state.counters["s_per_element"] = benchmark::Counter(
      static_cast<double>(state.iterations() * fx.model.num_elements()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["nonlinear_active_fraction"] =
      static_cast<double>(active) / fx.model.num_elements();
}

using namespace msd;
void BM_Springs(benchmark::State& s) { run(s, kSprings, 0.0, 0.95); }
void BM_Dampers(benchmark::State& s) { run(s, kDampers, 0.0, 0.95); }
void BM_Repulsion(benchmark::State& s) { run(s, kRepulsion, 0.0, 0.95); }
void BM_Volume(benchmark::State& s) { run(s, kVolume, 0.0, 0.95); }
void BM_FullModel(benchmark::State& s) { run(s, kSprings | kDampers | kRepulsion | kVolume, 0.0, 0.95); }
void BM_FullModelThreshold07Mild(benchmark::State& s) {
  run(s, kSprings | kDampers | kRepulsion | kVolume, 0.7, 0.95);
}
void BM_FullModelThreshold07Compressed(benchmark::State& s) {
  run(s, kSprings | kDampers | kRepulsion | kVolume, 0.7, 0.6);
}

BENCHMARK(BM_Springs);
BENCHMARK(BM_Dampers);
BENCHMARK(BM_Repulsion);
BENCHMARK(BM_Volume);
BENCHMARK(BM_FullModel);
BENCHMARK(BM_FullModelThreshold07Mild);
BENCHMARK(BM_FullModelThreshold07Compressed);

}  // namespace

BENCHMARK_MAIN();
