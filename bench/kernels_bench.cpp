// Stepping throughput of each map on each path: items_per_second = particle-steps/s.
// Raw stepping (no invariant tracking), 1000 steps per iteration.
//   build/bench/kernels_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <string>

#include "core/isa.hpp"
#include "bench_ensemble.hpp"
#include "ensembles/catalogue.hpp"

namespace qmaps {
namespace {

constexpr long long steps = 1000;

struct Bench {
  const char* map;
  ParamValues params;
};

// Each map at the parameters of its case (A = 0.7, alpha = 0.9, step 0.1; flow and leapfrog at
// the case IV set).
const Bench maps[] = {
    {"suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}}},
    {"case2", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}},
    {"case2-staggered", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}},
    {"case2-hky", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}, {"gamma11", 0.6}, {"gamma21", 0.3}}},
    {"case3", {{"A", 0.7}, {"alpha", 0.9}, {"ds", 0.1}}},
    {"flow", {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2}, {"delta", 5.4}, {"h", 0.1}}},
    {"leapfrog", {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2}, {"delta", 5.4}, {"h", 0.1}}},
};

void step_ensemble(benchmark::State& state, const Bench& bench, Isa isa) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto model = make_model(bench.map, bench.params);
  Ensemble e = bench_ensemble(*model, orbits);
  for (auto _ : state) {
    model->advance(e, next_steps(e, steps, false), Execution{isa, threads, 4});
    benchmark::DoNotOptimize(e.state[2][0]);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(orbits) * steps);
  state.SetLabel(std::string(isa_name(isa)));
}

// Suris, the reference of every budget, at 2^18 and 2^22 orbits on every path; the other maps
// at 2^18 on the scalar path and the best ISA. The exactly rounded per-lane FMA of sse2 is slow:
// its large case would take minutes.
const bool registered = [] {
  for (const Bench& bench : maps) {
    const std::string map = bench.map;
    const auto add = [&](Isa isa) {
      return benchmark::RegisterBenchmark((map + "/" + std::string(isa_name(isa))).c_str(),
                                          step_ensemble, bench, isa)
          ->ArgNames({"orbits", "threads"})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    };
    add(Isa::scalar)->Args({map == "suris" ? 1 << 18 : 1 << 14, 1});
    for (Isa isa : runnable_isas()) {
      if (map != "suris" && isa != best_isa()) continue;
      auto* b = add(isa);
      for (long orbits : {1L << 18, 1L << 22})
        for (long threads : {1, 2})
          if (orbits == 1L << 18 || (map == "suris" && isa != Isa::sse2)) b->Args({orbits, threads});
    }
  }
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
