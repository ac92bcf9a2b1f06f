// The cost of the chaos indicators: every map on the best ISA, 2 threads, stepping raw, with its
// chaos record of one deviation (lambda, FLI, MEGNO) and of nine (also the spectrum and the GALIs,
// orthonormalized every 10 steps). items_per_second = particle-steps/s; compare the three rows of
// a map within one run:
//   build/bench/chaos_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <string>

#include "bench_maps.hpp"
#include "core/isa.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

// 0: the map alone; 1 or 9: its chaos record of that many deviations.
void step_with_record(benchmark::State& state, const BenchMap& bench, int deviations) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const int chains = static_cast<int>(state.range(2));
  const long long steps = bench.steps();
  const std::string key = bench.map + "/" + std::to_string(deviations);
  auto& setup = bench_setup(key, orbits, [&] {
    return deviations == 0 ? make_model(bench.map, bench.params)
                           : make_model(bench.map, bench.params, ChaosOptions{deviations == 9, 10});
  });
  Ensemble& e = *setup.ensemble;
  const Isa isa = best_isa();
  for (auto _ : state) {
    setup.model->advance(e, next_steps(e, steps, false), Execution{isa, threads, chains});
    benchmark::DoNotOptimize(e.state[2][0]);
  }
  const char* record[] = {"raw", "lyapunov", "spectrum"};
  describe(state, bench.map,
           std::string(isa_name(isa)) + "+" + record[deviations == 0 ? 0 : deviations == 1 ? 1 : 2],
           static_cast<double>(orbits), static_cast<double>(steps), threads);
}

const bool registered = [] {
  for (const BenchMap& bench : bench_maps())
    for (int deviations : {0, 1, 9})
      benchmark::RegisterBenchmark(
          (bench.map + "/" + std::to_string(deviations) + "_deviations").c_str(), step_with_record,
          bench, deviations)
          ->ArgNames({"orbits", "threads", "chains"})
          ->Args({bench_size().simd_orbits / 4, 2, 8})
          ->Args({bench_size().simd_orbits / 4, 2, 1})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
