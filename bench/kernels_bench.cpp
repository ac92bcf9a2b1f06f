// Stepping throughput of every map on every path (scalar, each ISA compiled and supported) and
// thread count: items_per_second = particle-steps/s. Raw stepping, no invariant tracking.
//   build/bench/kernels_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// The scalar path and sse2 (an exactly rounded FMA per lane, slow) step fewer orbits; Suris on the
// best ISA also steps a million orbits (2^20), whose state leaves the caches.
#include <benchmark/benchmark.h>

#include <string>
#include <string_view>

#include "bench_maps.hpp"
#include "core/isa.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

void step_ensemble(benchmark::State& state, const BenchMap& bench, Isa isa) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const long long steps = bench.steps();
  auto& setup = bench_setup(bench.map, orbits, [&] { return make_model(bench.map, bench.params); });
  Ensemble& e = *setup.ensemble;
  for (auto _ : state) {
    setup.model->advance(e, next_steps(e, steps, false), Execution{isa, threads});
    benchmark::DoNotOptimize(e.state[2][0]);
  }
  describe(state, bench.map, isa_name(isa), static_cast<double>(orbits),
           static_cast<double>(steps), threads);
  // The map's facts that bench/report states beside its rate.
  state.counters["forces_per_step"] = bench.forces_per_step;
  state.counters["speed_budget"] = bench.speed_budget;
}

const bool registered = [] {
  std::vector<Isa> paths = {Isa::scalar};
  for (Isa isa : runnable_isas()) paths.push_back(isa);
  for (const BenchMap& bench : bench_maps())
    for (Isa isa : paths) {
      const bool slow = isa == Isa::scalar || isa == Isa::sse2;
      auto* b = benchmark::RegisterBenchmark(
                    (std::string(bench.map) + "/" + std::string(isa_name(isa))).c_str(),
                    step_ensemble, bench, isa)
                    ->ArgNames({"orbits", "threads"})
                    ->Unit(benchmark::kMillisecond)
                    ->UseRealTime();
      const long orbits = slow ? bench_size().slow_orbits : bench_size().simd_orbits;
      b->Args({orbits, 1});
      if (isa != Isa::scalar) b->Args({orbits, 2});  // the scalar reference path is serial
      if (std::string_view(bench.map) == "suris" && isa == best_isa())
        for (long threads : {1, 2}) b->Args({bench_size().million_orbits, threads});
    }
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
