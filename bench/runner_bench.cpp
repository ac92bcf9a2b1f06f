// The runner around one map (Suris on the widest ISA): how throughput depends on the number of
// orbits (2^10 to 2^24: from L1 to main memory, each iteration loads and stores every orbit once),
// the threads, and the chains per block (block = lanes × chains orbits interleaved in registers).
// items_per_second = particle-steps/s.
//   build/bench/runner_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "bench_maps.hpp"
#include "core/isa.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

void run(benchmark::State& state, long long steps) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const int chains = static_cast<int>(state.range(2));
  auto& setup = bench_setup("suris", orbits, [] { return make_model("suris", suris_params); });
  Ensemble& e = *setup.ensemble;
  for (auto _ : state) {
    setup.model->advance(e, next_steps(e, steps, false), Execution{best_isa(), threads, chains});
    benchmark::DoNotOptimize(e.state[2][0]);
  }
  describe(state, "suris", isa_name(best_isa()), static_cast<double>(orbits),
           static_cast<double>(steps), threads);
  state.counters["chains"] = chains;
}

const bool registered = [] {
  const BenchSize& size = bench_size();
  auto* sweep = benchmark::RegisterBenchmark("runner/orbits", run, size.sweep_steps)
                    ->ArgNames({"orbits", "threads", "chains"});
  for (int log2 = size.min_log2_orbits; log2 <= size.max_log2_orbits; log2 += 2)
    for (long threads : {1, 2}) sweep->Args({1L << log2, threads, Execution{}.chains});
  auto* chains = benchmark::RegisterBenchmark("runner/chains", run, size.steps)
                     ->ArgNames({"orbits", "threads", "chains"});
  for (long k : {ChainRange<kernels::Suris>::least, ChainRange<kernels::Suris>::most})
    for (long threads : {1, 2}) chains->Args({size.simd_orbits, threads, k});
  for (auto* b : {sweep, chains}) b->Unit(benchmark::kMillisecond)->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
