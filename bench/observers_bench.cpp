// The cost of observing: Suris on the best ISA, 2^18 orbits, 1000 steps per iteration (bench_size),
// raw and with the invariants tracked and a 128×128 (q1, q2) density sampled every `stride` steps.
// items_per_second = particle-steps/s; histogram_updates_per_second counts density samples.
#include <benchmark/benchmark.h>

#include "core/isa.hpp"
#include "bench_ensemble.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

void observe(benchmark::State& state, bool invariants, bool density) {
  const long long stride = state.range(0);
  const int threads = static_cast<int>(state.range(1));
  const auto model = make_model("suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}});
  const auto orbits = static_cast<std::size_t>(bench_size().simd_orbits);
  const long long steps = bench_size().steps;
  Ensemble e = bench_ensemble(*model, orbits);
  Observers o;
  if (density)
    o.densities.push_back({Histogram("q1q2", {{"q1", -1, 1, 128}, {"q2", -1, 1, 128}}),
                           {Coordinate::q1, Coordinate::q2}});
  for (auto _ : state)
    model->advance(e, next_steps(e, steps, invariants, stride), Execution{best_isa(), threads, 4},
                   density ? &o : nullptr);
  describe(state, "suris", isa_name(best_isa()), static_cast<double>(orbits),
           static_cast<double>(steps), threads);
  state.counters["stride"] = static_cast<double>(stride);
  if (density)
    state.counters["histogram_updates_per_second"] = benchmark::Counter(
        static_cast<double>(o.densities[0].histogram.samples()), benchmark::Counter::kIsRate);
}

void args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"stride", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
  for (long stride : {1, 10, 100})
    for (long threads : {1, 2}) b->Args({stride, threads});
}

BENCHMARK_CAPTURE(observe, raw, false, false)->ArgNames({"stride", "threads"})->Args({1000, 1})->Args({1000, 2})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(observe, invariants, true, false)->Apply(args);
BENCHMARK_CAPTURE(observe, invariants_density, true, true)->Apply(args);
BENCHMARK_CAPTURE(observe, density, false, true)->Apply(args);

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
