// Whole-run timings: each thesis uni-axial spec (about 12 s simulated) run from
// start to end, results written to a temporary file as the CLI does.
#include "bench/msd_runner.hpp"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

namespace {

void run_spec(benchmark::State& state, const std::string& name) {
  const bench::Spec spec = bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/" + name);
  const std::string out = (std::filesystem::temp_directory_path() / ("tb_bench_" + spec.name + ".h5")).string();
  double simulated = 0.0;
  for (auto _ : state) {
    const bench::RunSummary s = bench::run_msd(spec, out);
    if (!s.complete) state.SkipWithError(s.failure.c_str());
    simulated = s.simulated_seconds;
  }
  state.counters["simulated_s"] = simulated;
  std::filesystem::remove(out);
  std::filesystem::remove(std::filesystem::path(out).replace_extension(".csv"));
}

void BM_ThesisNaive(benchmark::State& s) { run_spec(s, "uniaxial_thesis_naive.yaml"); }
void BM_ThesisRepulsion(benchmark::State& s) { run_spec(s, "uniaxial_thesis_repulsion.yaml"); }
void BM_ThesisFull(benchmark::State& s) { run_spec(s, "uniaxial_thesis_full.yaml"); }

BENCHMARK(BM_ThesisNaive)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ThesisRepulsion)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ThesisFull)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
