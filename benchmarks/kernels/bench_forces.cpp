// Element force cost, seconds per element per evaluation (s_per_element), for
// each force term alone and for the full model (threshold off, and the thesis'
// 0.7 threshold on a mildly deformed and on a strongly compressed sample):
// the per-tet reference loop (BM_Reference*) and the fast engine
// (BM_Fast*, argument = threads) side by side in one run; then the fast full
// model's scaling from 1k to 250k tets on 1 and 2 threads (BM_FastScaling,
// arguments = cubes along x, threads). BM_FastSpringLaws / BM_FastFullModelSpringLaws:
// the same with the edge classes' non-linear spring laws (cube edges 0.3 k_s,
// compression exponent 3 on both classes: the calibrated lattice's form), beside
// the linear springs in the same run. BM_FastLadder: the model ladder's force
// evaluation on the same block, one thread, nu = 0.495 (argument = rung):
// 0 the thesis element (springs, dampers, repulsion, volume), 1 the physical
// lattice (isotropic springs, dampers, the per-cube bulk term), 2 the
// neo-Hookean lattice (zero-length springs, dampers, the bulk term's
// neo-Hookean law), 3 the continuum rung (stable neo-Hookean tets, dampers,
// one volume ratio per cube).
#include "msd/forces/element_forces.hpp"
#include "msd/forces/force_engine.hpp"
#include "msd/mesh/cubic_grid.hpp"

#include <benchmark/benchmark.h>

#include <random>

namespace {

struct Fixture {
  msd::Model model;
  msd::Points x, v, f;
};

// The benchmark block: 10 x 10 x 20 cm at h = 1 cm (2,000 cubes, 10,000
// tets), or `nx` x `nx` x 2 `nx` cubes.
msd::SampleMesh block(int nx) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  o.max_cubes = 100000000;
  return msd::mesh_closed_surface(msd::make_box(msd::Vec3::Zero(), msd::Vec3(0.01 * nx, 0.01 * nx, 0.02 * nx)), o,
                                  "benchmark block");
}

// Physical constants shared by every fixture.
msd::TissueMaterial block_material() {
  msd::TissueMaterial mat;
  mat.mode = msd::ConstantsMode::Physical;
  mat.density = 1000;
  mat.youngs_modulus = 3000;
  mat.damping_time = 0.01;
  mat.repulsion_factor = 0.2;
  mat.volume_factor = 1.0;
  return mat;
}

// The model built, its positions perturbed randomly (seeded) and the block
// squeezed along z by `squeeze` (0.8 = 20 % compression), velocities random.
Fixture perturbed(const msd::TetMesh& mesh, const msd::ModelOptions& mo, double squeeze) {
  Fixture fx{msd::build_model(mesh, mo), {}, {}, {}};
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

// The block with the given terms (and the edge classes' laws), squeezed by `squeeze`.
Fixture make_fixture(unsigned terms, double threshold, double squeeze, int threads = 1, int nx = 10,
                     bool laws = false) {
  const auto sample = block(nx);
  msd::ModelOptions mo;
  mo.terms = terms;
  mo.nonlinear_threshold = threshold;
  msd::TissueMaterial mat = block_material();
  if (laws) {
    mat.edge_laws[0] = {0.3, 1.0, 3.0};
    mat.edge_laws[1] = {1.0, 1.0, 3.0};
  }
  mo.region_materials = {mat};
  mo.threads = threads;
  return perturbed(sample.mesh, mo, squeeze);
}

// The ladder's rung `rung` (BM_FastLadder above) on the 10 x 10 x 20 cm block, nu = 0.495.
Fixture make_rung(int rung) {
  const auto sample = block(10);
  msd::ModelOptions mo;
  msd::TissueMaterial mat = block_material();
  mat.poisson_ratio = 0.495;
  const unsigned full = msd::kSprings | msd::kDampers | msd::kRepulsion | msd::kVolume;
  mo.terms = rung == 0 ? full : rung == 3 ? (msd::kNeoHookean | msd::kDampers) : (msd::kSprings | msd::kDampers | msd::kBulk);
  if (rung == 1) {
    mat.edge_laws[0].stiffness = 0.9 / 1.495;
    mat.edge_laws[1].stiffness = 1.8 / 1.495;
  }
  mat.zero_length_springs = rung == 2;
  mo.region_materials = {mat};
  if (rung > 0) mo.volume_group = sample.info.tet_cube_id;
  return perturbed(sample.mesh, mo, 0.95);
}

void BM_FastLadder(benchmark::State& state) {
  static const char* names[] = {"thesis element", "physical lattice", "neo-Hookean lattice", "continuum per cube"};
  Fixture fx = make_rung(static_cast<int>(state.range(0)));
  msd::Scratch buffers;
  for (auto _ : state) {
    msd::compute_forces_fast(fx.model, fx.x, fx.v, fx.f, buffers);
    benchmark::DoNotOptimize(fx.f.data());
  }
  state.SetLabel(names[state.range(0)]);
  state.counters["tets"] = fx.model.num_elements();
  state.counters["s_per_element"] = benchmark::Counter(
      static_cast<double>(state.iterations() * fx.model.num_elements()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// fast: the engine on state.range(0) threads (or range(1) with a size in range(0)); else the reference loop.
void run(benchmark::State& state, unsigned terms, double threshold, double squeeze, bool fast = false,
         bool scaling = false, bool laws = false) {
  const int threads = fast ? static_cast<int>(state.range(scaling ? 1 : 0)) : 1;
  Fixture fx =
      make_fixture(terms, threshold, squeeze, threads, scaling ? static_cast<int>(state.range(0)) : 10, laws);
  msd::Scratch buffers;
  long active = 0;
  for (auto _ : state) {
    active = fast ? msd::compute_forces_fast(fx.model, fx.x, fx.v, fx.f, buffers)
                  : msd::compute_internal_forces_reference(fx.model, fx.x, fx.v, fx.f);
    benchmark::DoNotOptimize(fx.f.data());
  }
  state.counters["tets"] = fx.model.num_elements();
  if (fast) state.SetLabel(msd::force_engine_isa());  // the edge pass's instruction set on this CPU
  state.SetItemsProcessed(state.iterations() * fx.model.num_elements());
  state.counters["s_per_element"] = benchmark::Counter(
      static_cast<double>(state.iterations() * fx.model.num_elements()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["nonlinear_active_fraction"] =
      static_cast<double>(active) / fx.model.num_elements();
}

using namespace msd;
constexpr unsigned kFull = kSprings | kDampers | kRepulsion | kVolume;
void BM_ReferenceSprings(benchmark::State& s) { run(s, kSprings, 0.0, 0.95); }
void BM_ReferenceDampers(benchmark::State& s) { run(s, kDampers, 0.0, 0.95); }
void BM_ReferenceRepulsion(benchmark::State& s) { run(s, kRepulsion, 0.0, 0.95); }
void BM_ReferenceVolume(benchmark::State& s) { run(s, kVolume, 0.0, 0.95); }
void BM_ReferenceFullModel(benchmark::State& s) { run(s, kFull, 0.0, 0.95); }
void BM_ReferenceFullModelThreshold07Mild(benchmark::State& s) { run(s, kFull, 0.7, 0.95); }
void BM_ReferenceFullModelThreshold07Compressed(benchmark::State& s) { run(s, kFull, 0.7, 0.6); }
void BM_FastSprings(benchmark::State& s) { run(s, kSprings, 0.0, 0.95, true); }
void BM_FastDampers(benchmark::State& s) { run(s, kDampers, 0.0, 0.95, true); }
void BM_FastRepulsion(benchmark::State& s) { run(s, kRepulsion, 0.0, 0.95, true); }
void BM_FastVolume(benchmark::State& s) { run(s, kVolume, 0.0, 0.95, true); }
void BM_FastFullModel(benchmark::State& s) { run(s, kFull, 0.0, 0.95, true); }
void BM_FastFullModelThreshold07Mild(benchmark::State& s) { run(s, kFull, 0.7, 0.95, true); }
void BM_FastFullModelThreshold07Compressed(benchmark::State& s) { run(s, kFull, 0.7, 0.6, true); }
void BM_FastSpringLaws(benchmark::State& s) { run(s, kSprings, 0.0, 0.95, true, false, true); }
void BM_FastFullModelSpringLaws(benchmark::State& s) { run(s, kFull, 0.0, 0.95, true, false, true); }
void BM_FastScaling(benchmark::State& s) { run(s, kFull, 0.0, 0.95, true, true); }
void BM_ReferenceScaling(benchmark::State& s) { run(s, kFull, 0.0, 0.95, false, true); }

BENCHMARK(BM_ReferenceSprings);
BENCHMARK(BM_FastSprings)->Arg(1);
BENCHMARK(BM_FastSpringLaws)->Arg(1);
BENCHMARK(BM_FastLadder)->DenseRange(0, 3);
BENCHMARK(BM_ReferenceDampers);
BENCHMARK(BM_FastDampers)->Arg(1);
BENCHMARK(BM_ReferenceRepulsion);
BENCHMARK(BM_FastRepulsion)->Arg(1);
BENCHMARK(BM_ReferenceVolume);
BENCHMARK(BM_FastVolume)->Arg(1);
BENCHMARK(BM_ReferenceFullModel);
BENCHMARK(BM_FastFullModel)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(BM_FastFullModelSpringLaws)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(BM_ReferenceFullModelThreshold07Mild);
BENCHMARK(BM_FastFullModelThreshold07Mild)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(BM_ReferenceFullModelThreshold07Compressed);
BENCHMARK(BM_FastFullModelThreshold07Compressed)->Arg(1)->Arg(2)->UseRealTime();
// 1k, 10k, 50k, 250k tets: nx = 5 (250 cubes), 10 (2,000), 17 (9,826), 29 (48,778).
BENCHMARK(BM_ReferenceScaling)->Arg(5)->Arg(10)->Arg(17)->Arg(29);
BENCHMARK(BM_FastScaling)->ArgsProduct({{5, 10, 17, 29}, {1, 2}})->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
