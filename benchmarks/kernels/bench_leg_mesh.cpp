// The leg's structure (thesis 4.5): generating the parametric leg's surfaces,
// and meshing the shipped leg into its physical layer - validation, cubic
// approximation with erosion and bone points, the five-tet split, the pull
// behind the knee and the embedding of every surface vertex (25k) - at the
// thesis' resolution (961 cubes) and at half the spacing.
#include "msd/geometry/leg_generator.hpp"
#include "msd/mesh/limb_mesher.hpp"

#include <benchmark/benchmark.h>

#include <string>

namespace {

msd::LimbSurfaces shipped_leg() { return msd::read_leg_surfaces(std::string(TISSUEBENCH_DATA_DIR) + "/leg"); }

void BM_GenerateLeg(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(msd::make_leg(msd::LegParameters{}));
}
BENCHMARK(BM_GenerateLeg)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void BM_MeshLeg(benchmark::State& state) {
  const msd::LimbSurfaces s = shipped_leg();
  msd::LimbMeshOptions o;
  o.spacing = 0.0245 / static_cast<double>(state.range(0));
  // The shipped scene's pull area behind the knee (msd/data/leg/leg.yaml).
  o.pull_areas.push_back({"behind_knee", msd::Vec3(-0.12, -0.10, 0.42046), msd::Vec3(-0.02, 0.10, 0.58046)});
  long cubes = 0, vertices = 0, outside = 0;
  for (auto _ : state) {
    const msd::LimbMesh m = msd::mesh_limb(s, o);
    cubes = m.cubes;
    vertices = outside = 0;
    for (const auto& [r, e] : m.embedded) {
      vertices += static_cast<long>(e.vertices.size());
      outside += e.outside;
    }
  }
  state.counters["cubes"] = static_cast<double>(cubes);
  state.counters["embedded"] = static_cast<double>(vertices);
  state.counters["outside"] = static_cast<double>(outside);
}
BENCHMARK(BM_MeshLeg)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
