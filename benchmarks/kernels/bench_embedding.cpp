// Embedded surfaces (thesis 5.5): the cost of locating 20,000 skin vertices in
// a limb-sized tet mesh (search structure + eq. 5.6 coordinates), against the
// thesis' scan over every tet, and the per-frame cost of moving them with the
// mesh.
#include "msd/mesh/cubic_grid.hpp"
#include "msd/mesh/embedding.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

namespace {

struct Limb {
  msd::SampleMesh mesh;
  msd::Points skin;  ///< 3 x 20,000 points on the smooth cylinder
};

// A thigh-sized cylinder (radius 7 cm, length 40 cm) meshed at spacing h, and
// 20,000 points scattered on its smooth lateral surface and caps (seeded).
Limb make_limb(double h) {
  const double r = 0.07, len = 0.4;
  msd::SampleMeshOptions o;
  o.spacing = h;
  Limb limb{msd::mesh_closed_surface(msd::make_cylinder(r, len, 96), o, "limb"), msd::Points(3, 20000)};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const double phi = 2 * M_PI * u(rng);
    if (i % 10 == 0) {  // caps
      const double rho = r * std::sqrt(u(rng));
      limb.skin.col(i) = msd::Vec3(rho * std::cos(phi), rho * std::sin(phi), (i % 20 == 0) ? 0.0 : len);
    } else {
      limb.skin.col(i) = msd::Vec3(r * std::cos(phi), r * std::sin(phi), len * u(rng));
    }
  }
  return limb;
}

void BM_Embed20kVertices(benchmark::State& state) {
  const double h = static_cast<double>(state.range(0)) * 1e-3;
  const Limb limb = make_limb(h);
  msd::Embedding e;
  for (auto _ : state) {
    e = msd::embed_vertices(limb.mesh.mesh, limb.skin);
    benchmark::DoNotOptimize(e.vertices.data());
  }
  state.counters["tets"] = limb.mesh.mesh.num_tets();
  state.counters["outside"] = e.outside;
  state.counters["max_outside_mm"] = 1e3 * e.max_outside_distance;
}

// The thesis' way: every vertex tested against every tet (1,000 vertices,
// so the run stays short; scale by 20 for 20,000).
void BM_ScanAllTets1kVertices(benchmark::State& state) {
  const double h = static_cast<double>(state.range(0)) * 1e-3;
  const Limb limb = make_limb(h);
  const auto& m = limb.mesh.mesh;
  std::vector<msd::Mat3> inv(m.tets.size());
  for (size_t k = 0; k < m.tets.size(); ++k) {
    const auto& t = m.tets[k];
    msd::Mat3 mm;
    mm << m.nodes.col(t[1]) - m.nodes.col(t[0]), m.nodes.col(t[2]) - m.nodes.col(t[0]),
        m.nodes.col(t[3]) - m.nodes.col(t[0]);
    inv[k] = mm.inverse();
  }
  for (auto _ : state) {
    long found = 0;
    for (int i = 0; i < 1000; ++i) {
      const msd::Vec3 p = limb.skin.col(i);
      for (size_t k = 0; k < m.tets.size(); ++k) {
        const msd::Vec3 l = inv[k] * (p - m.nodes.col(m.tets[k][0]));
        if (std::min({1.0 - l.sum(), l[0], l[1], l[2]}) >= -1e-10) {
          ++found;
          break;
        }
      }
    }
    benchmark::DoNotOptimize(found);
  }
  state.counters["tets"] = m.num_tets();
}

void BM_Move20kVertices(benchmark::State& state) {
  const Limb limb = make_limb(0.01);
  const msd::Embedding e = msd::embed_vertices(limb.mesh.mesh, limb.skin);
  msd::Points x;
  for (auto _ : state) {
    msd::embedded_positions(limb.mesh.mesh.nodes, limb.mesh.mesh.tets, e, x);
    benchmark::DoNotOptimize(x.data());
  }
}

// Spacing in mm: 25 (about the thesis' leg resolution), 10 and 5.
BENCHMARK(BM_Embed20kVertices)->Arg(25)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ScanAllTets1kVertices)->Arg(25)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Move20kVertices)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
